// StepMethod::kCondensed with FrictionFormulation::kCoulombFc: the step over the contact
// unknowns as the frictional contact problem in Delassus form (coulomb_step.hpp), solved by
// ncp::fc, with implicit Coulomb friction |tau_c| <= f_c lambda_c^{k+1}.
#include <chrono>
#include <string>

#include "coulomb_step.hpp"
#include "delassus.hpp"
#include "step_method.hpp"

namespace contact::internal {
namespace {

ncp::fc::Options FcOptions(const DynamicOptions& options) {
  ncp::fc::Options fc;  // the hybrid: Alart-Curnier, switching formulation when it stalls
  fc.max_iterations = options.ncp.max_iterations;
  fc.log_to_stderr = options.ncp.log_to_stderr;
  return fc;
}

// With H and W = H S^-1 H' of the condensed step (delassus.hpp), per step:
//   x_free = -H S^-1 q,  gap0_c = s_c - n_c . u^k_c   ->  F (CoulombStep)  ->
//   du = S^-1 (H' F - q).
class CoulombFcStep : public StepAlgorithm {
 public:
  CoulombFcStep(const DynamicModel& model, MassInverse* mass, double m_max, const DynamicOptions& options)
      : nodes_(model.contact_nodes),
        delassus_(model, mass, m_max, /*normal_only=*/false),
        coulomb_(model.dim, delassus_.W(), delassus_.condensed_nodes(), options.friction_coefficient,
                 FcOptions(options)),
        tolerance_(options.ncp.tolerance),
        gap0_(static_cast<Eigen::Index>(nodes_.size())) {}

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    const auto start = std::chrono::steady_clock::now();
    delassus_.SolveS(step.q, &full_);
    x_free_.noalias() = delassus_.H() * full_;
    x_free_ = -x_free_;
    for (size_t c = 0; c < nodes_.size(); ++c) {
      double normal_motion = 0.0;
      for (int a = 0; a < 3; ++a)
        if (nodes_[c].dofs[a] >= 0) normal_motion += nodes_[c].normal(a) * step.u(nodes_[c].dofs[a]);
      gap0_(static_cast<Eigen::Index>(c)) = nodes_[c].gap - normal_motion;
    }
    const bool ok = coulomb_.Solve(x_free_, gap0_, step.scales.force / step.force_scale,
                                   step.scales.displacement, tolerance_, &outcome_);
    // du = S^-1 (H' F - q); the contact forces, gaps and slips as CoulombStep found them.
    full_.noalias() = delassus_.H().transpose() * outcome_.force;
    full_ -= step.q;
    *result = outcome_.contact;
    delassus_.SolveS(full_, &result->x);

    const ncp::fc::Summary& s = outcome_.summary;
    StepOutcome out;
    out.ok = ok;
    out.status = ok ? "converged" : "natural-map residual " + std::to_string(outcome_.natural_map_residual) +
                                        " > tolerance " + std::to_string(tolerance_) + " (scaled): " + s.message;
    out.newton_iterations = s.iterations;
    out.jacobian_evaluations = s.iterations;  // one generalized Jacobian per Newton step
    out.residual_evaluations = s.iterations + s.backtracks + 1;
    out.implicit_friction_bound = true;
    out.solve_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  std::vector<ContactNode> nodes_;
  DelassusOperator delassus_;
  CoulombStep coulomb_;
  double tolerance_;
  Eigen::VectorXd gap0_, x_free_, full_;
  CoulombStep::Outcome outcome_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeCoulombFcStep(const DynamicModel& model, MassInverse* mass,
                                                 double m_max, const DynamicOptions& options) {
  return std::make_unique<CoulombFcStep>(model, mass, m_max, options);
}

}  // namespace contact::internal
