// One step k -> k+1 of central differences as a complementarity problem, behind one small
// interface so that every way of solving it (full, condensed, explicit, Ipopt, ...) is
// one class in one file and the time integrator (dynamics.cpp) does not know which it
// runs.
//
// The step (contact/dynamics.hpp, thesis eq. 73, 80, 81): find du = u^{k+1} - u^k with
//     S du + q = H' F,   S = M / m_max,   q = dt^2 Q^k / m_max,
// F the contact forces (system units: times force_scale = m_max / dt^2 for newtons),
// which satisfy Signorini's conditions at u^k + du and Tresca friction with bounds g_c.
//
// Adding a step method: a class deriving from StepAlgorithm in its own file (set-up in
// the constructor, once per run; Solve once per step), and one line in MakeStepAlgorithm
// (step_method.cpp). Solve must not allocate once the sizes are set, apart from a
// constant few per step (tests/contact/test_no_allocation.cpp), and must not throw on
// numerical trouble: it reports it in StepOutcome.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "contact/convex_qp.hpp"
#include "contact/dynamics_types.hpp"
#include "mass_inverse.hpp"
#include "step_accuracy.hpp"

namespace contact::internal {

/// The data of one step (vectors over the free dofs unless said).
struct StepData {
  const Eigen::VectorXd& q;      ///< dt^2 Q^k / m_max (system units)
  const Eigen::VectorXd& u;      ///< u^k [m]
  const Eigen::VectorXd& bound;  ///< Tresca bound g_c per contact node (system units);
                                 ///< empty = frictionless
  const Eigen::VectorXd&
      guess;                 ///< start guess of du [m] (the previous step's increment)
  StepScales scales;         ///< what the step is solved against: tolerance F, D [N], [m]
  double force_scale = 0.0;  ///< m_max / dt^2: system force units -> N
  /// s_c per contact node [m]: the initial gaps of the step's obstacle position (the
  /// obstacle may move between steps, contact::Simulation::SetContactGaps); the
  /// ContactNode::gap of the set-up is not read by Solve.
  const Eigen::VectorXd& gap;
  /// The obstacle's translation over the step [m] (size dim; nullptr: at rest): the
  /// friction slip is relative to it (TakesObstacleSlip).
  const Eigen::VectorXd* obstacle_step = nullptr;
};

/// How a step's solve ended.
struct StepOutcome {
  bool ok = false;                    ///< the result is usable (solved to its tolerance)
  std::string status = "not solved";  ///< "converged", or why not
  int newton_iterations = 0, jacobian_evaluations = 0, residual_evaluations = 0;
  int friction_restarts = 0;  ///< Newton solves repeated from the neutral friction start
  /// Krylov (GMRES) iterations of the Newton systems (the sparse step; 0 otherwise).
  int krylov_iterations = 0;
  /// Friction was solved against f_c lambda^{k+1} (this step's normal forces, implicit
  /// Coulomb), not against StepData::bound: the step's accuracy is measured against it.
  bool implicit_friction_bound = false;
  double solve_seconds = 0.0;  ///< time in the solver proper [s]
};

class StepAlgorithm {
 public:
  virtual ~StepAlgorithm() = default;
  /// Solves one step: *result gets du (result->x, [m]) and the contact forces, gaps and
  /// slips (ContactSystem::Result, system units). Reuses *result's storage.
  virtual StepOutcome Solve(const StepData& step, ContactSystem::Result* result) = 0;
  /// What a step keeps for the next one (the warm start: the previous friction forces,
  /// system units), for a checkpoint (contact/simulation.hpp); empty if nothing is kept.
  virtual Eigen::MatrixXd WarmStart() const { return {}; }
  /// Whether Solve takes the friction slip relative to StepData::obstacle_step (a method
  /// that does not would take the body's own slip: the integrator refuses to move the
  /// obstacle under friction then).
  virtual bool TakesObstacleSlip() const { return false; }
  /// Restores what WarmStart returned. Throws std::invalid_argument on a size that does
  /// not fit the method (a checkpoint of another run).
  virtual void SetWarmStart(const Eigen::MatrixXd& warm_start) {
    if (warm_start.size() != 0)
      throw std::invalid_argument(
          "this step method keeps no warm start, the checkpoint has " +
          std::to_string(warm_start.size()) + " numbers");
  }
};

/// The predicted time per step of the explicit, condensed and sparse steps for the run
/// (`mass`: M^-1 with its factor) and the cheapest, kAuto's choice (StepCostPrediction).
StepCostPrediction PredictStepCost(const DynamicModel& model,
                                   const DynamicOptions& options,
                                   const MassInverse& mass);

/// The method that runs: options.step_method, or for kAuto PredictStepCost's choice.
/// Throws std::invalid_argument for the sparse step with friction posed with the lagged
/// bound (FrictionFormulation::kLaggedBound).
StepMethod ResolveStepMethod(const DynamicModel& model, const DynamicOptions& options,
                             const MassInverse& mass);

/// The step method of `options` (ResolveStepMethod), set up for the model. `mass` (M^-1)
/// must outlive the result. Throws std::invalid_argument when the method cannot take the
/// model (explicit without a lumped mass, condensed with a singular Delassus operator).
std::unique_ptr<StepAlgorithm> MakeStepAlgorithm(const DynamicModel& model,
                                                 const DynamicOptions& options,
                                                 MassInverse* mass, double m_max);

/// The step methods, one per file (full_step.cpp, condensed_step.cpp, explicit_step.cpp,
/// ipopt_step.cpp), which MakeStepAlgorithm chooses from. ncp_options: the Newton
/// settings (DynamicOptions::ncp).
std::unique_ptr<StepAlgorithm> MakeFullStep(const DynamicModel& model, double m_max,
                                            const ncp::Options& ncp_options,
                                            bool friction);
std::unique_ptr<StepAlgorithm> MakeCondensedStep(const DynamicModel& model,
                                                 MassInverse* mass, double m_max,
                                                 const ncp::Options& ncp_options,
                                                 bool friction);
/// The condensed step with FrictionFormulation::kCoulombFc (coulomb_fc_step.cpp).
std::unique_ptr<StepAlgorithm> MakeCoulombFcStep(const DynamicModel& model,
                                                 MassInverse* mass, double m_max,
                                                 const DynamicOptions& options);
/// StepMethod::kSparse: the problem of MakeCoulombFcStep (f_c >= 0) with W applied, not
/// formed (coulomb_fc_step.cpp).
std::unique_ptr<StepAlgorithm> MakeSparseStep(const DynamicModel& model,
                                              MassInverse* mass, double m_max,
                                              const DynamicOptions& options);
std::unique_ptr<StepAlgorithm> MakeExplicitStep(const DynamicModel& model, double m_max);
/// The explicit step's condition on a lumped mass (diagonal: of M, or of S = M / m_max):
/// the mesh node of the first contact node whose free components have different masses,
/// or -1.
int UnequalLumpedMassNode(int dim, const Eigen::VectorXd& diagonal,
                          const std::vector<ContactNode>& nodes);
std::unique_ptr<StepAlgorithm> MakeIpoptStep(const DynamicModel& model, double m_max,
                                             double tolerance);

/// The frictionless step as the convex QP
///   min 1/2 du' S du + q' du   s.t.   n_c . du_c <= s_c - n_c . u^k_c
/// (multipliers: the normal reactions, system units), solved by Ipopt in the step's own
/// scales. The Ipopt step method, and the reference of
/// DynamicOptions::compare_with_ipopt.
class IpoptQp {
 public:
  /// Ipopt's tests at `tolerance` (ncp.tolerance) in the step's scales.
  IpoptQp(const DynamicModel& model, double m_max, double tolerance);
  /// du (qp.x, [m]) and the multipliers (system units) of the step.
  ConvexQpResult Solve(const StepData& step) const;

 private:
  Eigen::SparseMatrix<double> S_;  // M / m_max
  Eigen::SparseMatrix<double> G_;  // rows n_c' R_c: n_c . du_c
  double tolerance_;
};

}  // namespace contact::internal
