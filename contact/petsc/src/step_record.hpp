// The record of a distributed step, whichever step it is (steps.csv's row, the summary's
// maxima, the energy blow-up guard, the final status) with the definitions and scales of
// the serial step (contact/src/step_accuracy.hpp, energy_balance.hpp, dynamics.cpp
// MeasureStep): every rank reduces its owned free dofs and contact nodes to a few sums
// and maxima (RankStepPart: M du with the step's own M, lumped or consistent) and sends
// them, with one NodeResult per contact node it holds the result of, to rank 0 in one
// MPI_Gatherv per step (StepGather); rank 0 sums the parts in rank order (the same order
// on every run with the same ranks) and evaluates each contact node in the serial node
// order with the serial functions (StepRecorder).
#pragma once

#include <mpi.h>

#include <Eigen/Core>
#include <vector>

#include "contact/contact_system.hpp"
#include "contact/dynamics.hpp"
#include "contact/scene.hpp"
#include "energy_balance.hpp"
#include "step_accuracy.hpp"

namespace contact::petsc::internal {

/// One rank's part of a step k -> k+1 over its owned free dofs i and contact nodes c.
struct RankStepPart {
  enum Sum {
    kDuMdu,          ///< sum du_i m_i du_i [kg m^2]
    kFUNext,         ///< sum f^k_i u^{k+1}_i [J]
    kFUPrevious,     ///< sum f^k_i u^{k-1}_i [J]
    kUKuNext,        ///< sum u^k_i (K u^{k+1})_i [J]
    kUNextKuNext,    ///< sum u^{k+1}_i (K u^{k+1})_i [J]
    kNonFinite,      ///< 1 if an increment is not finite
    kStopRequested,  ///< 1 if this rank read a stop request (SIGINT, SIGTERM)
    kNumSums
  };
  enum Max {
    kF,            ///< |f^k|_inf [N]
    kKu,           ///< |K u^k|_inf [N]
    kDu,           ///< |u^k - u^{k-1}|_inf [m]
    kPenetration,  ///< max(0, max_c n_c . u^k_c - s_c) [m]
    kQ,            ///< |Q^k|_inf [N]
    kMdu,          ///< |M du|_inf [kg m]
    kUNext,        ///< |u^{k+1}|_inf [m]
    kRFree,        ///< |r|_inf over the free dofs of no contact node [N]
    kNumMaxima
  };
  static constexpr int kWidth = kNumSums + kNumMaxima;
  double sum[kNumSums] = {};
  double max[kNumMaxima] = {};
};

/// One owned contact node after the step: its result (system units) and, per component
/// (0 where constrained), r = M du / dt^2 + Q [N], u^{k+1} and u^{k-1} [m].
struct NodeResult {
  int index = 0;  ///< in the serial contact node order
  double normal_force = 0.0, gap = 0.0;
  Eigen::Vector2d tangent_force = Eigen::Vector2d::Zero(), slip = Eigen::Vector2d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero(), u_next = Eigen::Vector3d::Zero(),
                  u_previous = Eigen::Vector3d::Zero();
};

/// What rank 0 holds after StepGather::Gather: the parts in rank order and, in the serial
/// contact node order, the contact result and r, u^{k+1}, u^{k-1} at the nodes' free
/// components (dim entries per node: entry dim c + a for component a of node c).
struct GatheredStep {
  std::vector<RankStepPart> parts;
  ContactSystem::Result contact;
  Eigen::VectorXd r, u_next, u_previous;
};

class StepGather {
 public:
  StepGather(MPI_Comm comm, int dim, int num_contact_nodes);
  /// Collective: this rank's part and node results to rank 0 (*out filled on rank 0).
  void Gather(const RankStepPart& part, const std::vector<NodeResult>& nodes,
              GatheredStep* out);

 private:
  int NodeWidth() const { return 3 + 2 * (dim_ - 1) + 3 * dim_; }  // (NodeResult)
  MPI_Comm comm_;
  int dim_, num_contact_nodes_, rank_;
  std::vector<int> counts_, offsets_;
  std::vector<double> send_, receive_;
};

/// Rank 0: the serial step's measures of each distributed step, whichever step produced
/// the parts (explicit, condensed, ...).
class StepRecorder {
 public:
  /// method: the step that runs - the Tresca bound the friction residual is measured
  /// against is the lagged f_c lambda^k for the explicit step and f_c lambda^{k+1}
  /// (implicit Coulomb, as the serial dynamics.cpp SolveStep) for the others; nodes: the
  /// scene's contact nodes (dofs in the serial free numbering); lambda0 [N] the initial
  /// normal forces; energy: the balance at the start (EnergyBalance of u^0, u^{-1} with
  /// the scene's M); m_max [kg] the step scaling (the largest lumped mass, or the largest
  /// entry of M_FF).
  StepRecorder(const Scene& scene, StepMethod method,
               const std::vector<ContactNode>& nodes, const Eigen::VectorXd& lambda0,
               const ::contact::internal::EnergyBalance& energy, double m_max);

  /// The scales of the coming step (step_accuracy.hpp) from the maxima over all ranks of
  /// |f^k|, |K u^k| [N], |u^k - u^{k-1}| [m] and the penetration of u^k [m], with the
  /// contact forces of the last recorded step: what Record measures the step against,
  /// for a step that solves against them (the condensed step).
  ::contact::internal::StepScales Scales(double f_max, double Ku_max, double du_max,
                                         double penetration) const;

  /// Fills rec (all but step, time, the timings) from the gathered step and adds it to
  /// the summary (maxima, inaccurate steps). False if the run must stop after this step
  /// (the summary says why): a non-finite increment (then nothing is recorded), an energy
  /// blow-up, or a stop request.
  bool Record(GatheredStep* step, long num_steps, StepRecord* rec,
              DynamicSummary* summary);

  /// The run's status once it ended (DynamicSummary::status kNotRun if it went to the
  /// end): completed or kAccuracyNotReached, as in one process.
  void Finish(DynamicSummary* summary) const;

 private:
  int dim_;
  StepMethod method_;
  double dt_, tolerance_, friction_, blowup_factor_, m_max_, force_scale_,
      gap0_max_ = 0.0;
  std::vector<ContactNode> nodes_;  // dofs: entry dim c + a of the gathered vectors
  Eigen::VectorXd lambda_, bound_, residual_;
  double contact_force_max_ = 0.0;  // |r^k|_inf of the previous step [N]
  ::contact::internal::EnergyBalance energy_;
  StepRecord first_inaccurate_;
};

}  // namespace contact::petsc::internal
