/// \file coulomb_step.hpp
/// (internal) One condensed time step with Coulomb friction posed as the local frictional
/// contact problem in Delassus form and solved by ncp::fc.
///
/// The condensed step (dynamics.cpp, CondensedStep) works on the contact unknowns x_c
/// (the free displacement components of the contact nodes over the step) with the
/// Delassus operator W = H S^-1 H' (S = M / m_max; forces in the units of S x + q):
///     x_c = W F + x_free,   x_free = -H S^-1 q  (the motion without contact forces).
/// Per contact node c the local frame e_c = (-n_c, t1_c[, t2_c]) (n_c the outward normal
/// of the body), stacked into E (one row per local component, on the contact unknowns),
/// gives
///     F = E' r,   r_c = (lambda_c, tau_c)   (normal reaction >= 0, friction force),
///     u = (gap_c, slip_c) = E x_c + (gap0_c, 0[, 0]),   gap0_c = s_c - n_c . u^k_c,
/// hence the problem of ncp::fc (ncp/fc/include/ncp/fc/problem.hpp):
///     u = W_fc r + q_fc,   W_fc = E W E',   q_fc = E x_free + (gap0, 0[, 0]),
///     C*_mu ∋ u + (mu |u_T|, 0[, 0])  ⟂  r ∈ C_mu     (De Saxce's form of
///     Signorini-Coulomb).
/// The friction bound is IMPLICIT: |tau_c| <= f_c lambda_c with this step's normal force
/// (true Coulomb), not the thesis's lagged bound f_c lambda_c^k (eq. 70) of
/// ContactSystem.
///
/// Stopping test in the step's scales: the problem is solved as r = F r', u = D u' (F the
/// force scale and D the displacement scale of the step, system units):
///     u' = (F / D) W_fc r' + q_fc / D,
/// to Siconos' natural-map error ||r' - P_C(r' - u'_hat)||_2 <= kNaturalMapMargin
/// tolerance
/// (+ round-off), so that every reaction is right to tolerance F and every gap and slip
/// to tolerance D, as with the other step methods (README, "Stopping rules in physical
/// units"). ncp::fc's measure is relative to 1 + ||q'||_2, so its tolerance is set to
/// that bound divided by 1 + ||q'||_2.
///
/// W dense (condensed step): W_fc formed, ncp::fc's hybrid on it. W as an operator
/// (sparse step, large contact sets): W_fc r = E W E' r applied, ncp::fc's matrix-free
/// Alart-Curnier Newton (ncp/fc/operator_problem.hpp); same problem, same stopping test.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <vector>

#include "contact/contact_system.hpp"
#include "ncp/fc/operator_problem.hpp"
#include "ncp/fc/solver.hpp"

namespace contact::internal {

class CoulombStep {
 public:
  /// The natural map does not bound the friction law at a node that slips by little:
  /// there |r_T| may sit below f_c r_N by much more than the residual, so the solve asks
  /// for this fraction of the tolerance; Newton converges quadratically near the
  /// solution, so the margin costs a fraction of an iteration per step (the choice of
  /// 1e-5: benchmarks/results/defaults/README.md). The margin is asked for, not required:
  /// a solve that stops short of it (round-off) but within the tolerance counts.
  static constexpr double kNaturalMapMargin = 1e-5;

  /// dim = 2 or 3; W: the Delassus operator on the contact unknowns (symmetric positive
  /// semidefinite, system units); nodes: the contact nodes with dofs numbered on the
  /// contact unknowns (-1: constrained component) and unit frames; friction_coefficient
  /// f_c >= 0; fc_options: the ncp::fc settings (its tolerance is replaced per step, see
  /// above). Throws std::invalid_argument on sizes that do not agree, f_c < 0 or invalid
  /// options.
  CoulombStep(int dim, const Eigen::MatrixXd& W, std::vector<ContactNode> nodes,
              double friction_coefficient, const ncp::fc::Options& fc_options);

  /// x = W F on the contact unknowns (x may not alias F).
  using Operator = std::function<void(const Eigen::VectorXd& F, Eigen::VectorXd* x)>;
  /// Matrix-free: W given by apply_W on `num_unknowns` contact unknowns and an
  /// approximation of its diagonal (> 0), otherwise as above. Distributed (`reduction`
  /// set, ncp/fc/operator_problem.hpp): nodes, W_diagonal and the vectors of Solve are
  /// this process's part of the contact set (its contact nodes, numbered on its contact
  /// unknowns), apply_W is collective, and every norm and maximum of the step (its
  /// stopping test included) is reduced over the parts, so that every part takes the same
  /// decisions; each part calls Solve for every step.
  CoulombStep(int dim, Operator apply_W, const Eigen::VectorXd& W_diagonal,
              std::vector<ContactNode> nodes, double friction_coefficient,
              const ncp::fc::Options& fc_options, ncp::fc::Reduction reduction = {});

  /// The step's outcome, system units.
  struct Outcome {
    ContactSystem::Result
        contact;               ///< x = x_c (contact unknowns), lambda, tau, gap, slip
    Eigen::VectorXd force;     ///< F = E' r on the contact unknowns
    ncp::fc::Summary summary;  ///< of the fc solve (error of the scaled problem)
    double natural_map_residual = -1.0;  ///< ||r' - P_C(r' - u'_hat)||_2 reached (scaled)
  };

  /// Solves one step: x_free (contact unknowns), gap0 (one per node, s_c - n_c . u^k_c),
  /// force and displacement scales F, D > 0 (system units), tolerance > 0. Starts from
  /// the previous call's forces. Returns true when the natural-map residual recomputed at
  /// the returned forces is within tolerance (+ round-off); otherwise the outcome holds
  /// the best iterate and the summary says why (never thrown).
  bool Solve(const Eigen::VectorXd& x_free, const Eigen::VectorXd& gap0,
             double force_scale, double displacement_scale, double tolerance,
             Outcome* out);

  /// The previous call's forces r (system units; empty before the first solved step), the
  /// start of the next call: a checkpoint's warm start.
  const Eigen::VectorXd& previous_forces() const { return r_previous_; }
  /// Restores previous_forces() of a checkpoint: empty or one r per local component (dim
  /// per node). Throws std::invalid_argument otherwise.
  void RestorePreviousForces(const Eigen::VectorXd& r);

  /// W_fc = E W E' (system units; empty when matrix-free), for tests.
  const Eigen::MatrixXd& local_delassus() const { return W_fc_; }
  /// E: local components (normal, tangents per node) from the contact unknowns.
  const Eigen::SparseMatrix<double>& frames() const { return E_; }

 private:
  /// E, transmits_ and the problem's constant parts, checking the arguments.
  void Build(Eigen::Index num_unknowns, double friction_coefficient);
  /// The scaled problem u' = (F / D) W_fc r' + q_fc / D solved from *r (scaled, r' = r /
  /// F) to the natural-map residual `asked`, accepted at `required` (absolute, scaled);
  /// *r returned zero on the non-transmitting components and projected onto the cones.
  void SolveScaled(const Eigen::VectorXd& q_fc, double F, double D, double asked,
                   double required, Eigen::VectorXd* r, ncp::fc::Summary* summary);
  /// At the forces r (system units): out->force = E' r, out->contact.x = W E' r + x_free
  /// (one product with W), local_ = E x_c; returns the natural-map residual
  /// ||r' - P_C(r' - u'_hat)||_2 at r' = r / F, u' = (E x_c + (gap0, 0[, 0])) / D =
  /// (F / D) W_fc r' + q_fc / D.
  double Motion(const Eigen::VectorXd& r, const Eigen::VectorXd& x_free,
                const Eigen::VectorXd& gap0, double F, double D, Outcome* out);
  /// The summary of a step its start point solves (no Newton step), error relative to 1
  /// + ||q'||_2 as ncp::fc's.
  void SolvedAtStart(double error, ncp::fc::Summary* summary) const;
  /// ||v||_2 over all parts (the serial norm() when not distributed).
  double Norm(const Eigen::VectorXd& v) const;

  int dim_;
  std::vector<ContactNode> nodes_;
  Eigen::SparseMatrix<double> E_;
  std::vector<bool>
      transmits_;     // per row of E: acts on a free component (normals always)
  Operator apply_W_;  // W on the contact unknowns
  bool matrix_free_ = false;
  Eigen::MatrixXd W_fc_;         // E W E' (dense form)
  Eigen::VectorXd diagonal_fc_;  // approximate diag(E W E') (matrix-free form)
  ncp::fc::Options options_;
  ncp::fc::FrictionProblem problem_;         // sizes, mu; W = W_fc unscaled (dense form)
  std::unique_ptr<ncp::fc::Solver> solver_;  // problem_ kept for the run (dense form)
  ncp::fc::Options solve_options_;           // options_ with this step's tolerances
  ncp::fc::OperatorProblem operator_problem_;  // the same, matrix-free (its reduction:
                                               // over the parts, when distributed)
  ncp::fc::OperatorSolver operator_solver_;    // its workspaces kept for the run
  double operator_scale_ = 1.0;                // F / D of the current step (matrix-free)
  Eigen::VectorXd spread_, applied_;           // buffers of the matrix-free product
  Eigen::VectorXd r_previous_;  // system units; empty before the first step
  Eigen::VectorXd q_, q_fc_, r_, r_scaled_, u_,
      local_;  // work vectors (no allocation per step)
};

}  // namespace contact::internal
