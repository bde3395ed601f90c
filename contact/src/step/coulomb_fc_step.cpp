// StepMethod::kCondensed with FrictionFormulation::kCoulombFc: the step over the contact
// unknowns as the frictional contact problem in Delassus form (coulomb_step.hpp), solved
// by ncp::fc, with implicit Coulomb friction |tau_c| <= f_c lambda_c^{k+1}.
// StepMethod::kSparse: the same problem with W = H S^-1 H' never formed - each product
// with it is one solve with the Cholesky factor of M - solved by ncp::fc's matrix-free
// Newton (GMRES); with or without friction (f_c = 0: Signorini alone). Memory and set-up
// follow the factor of M, not the square of the contact set.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "delassus.hpp"
#include "step/coulomb_step.hpp"
#include "step/step_method.hpp"

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
  CoulombFcStep(const DynamicModel& model, MassInverse* mass, double m_max,
                const DynamicOptions& options, bool matrix_free)
      : nodes_(model.contact_nodes),
        delassus_(model, mass, m_max, /*normal_only=*/false, matrix_free),
        tolerance_(options.ncp.tolerance),
        friction_(options.friction_coefficient > 0.0),
        gap0_(static_cast<Eigen::Index>(nodes_.size())) {
    if (matrix_free)
      coulomb_ = std::make_unique<CoulombStep>(
          model.dim,
          [this](const Eigen::VectorXd& F, Eigen::VectorXd* x) { delassus_.Apply(F, x); },
          delassus_.ProbedDiagonal(), delassus_.condensed_nodes(),
          options.friction_coefficient, FcOptions(options));
    else
      coulomb_ = std::make_unique<CoulombStep>(
          model.dim, delassus_.W(), delassus_.condensed_nodes(),
          options.friction_coefficient, FcOptions(options));
    // The trace holds one record per Newton step of a solve (dense form): sized once.
    outcome_.summary.trace.reserve(static_cast<size_t>(options.ncp.max_iterations));
  }

  Eigen::MatrixXd WarmStart() const override { return coulomb_->previous_forces(); }
  void SetWarmStart(const Eigen::MatrixXd& warm_start) override {
    if (warm_start.cols() > 1)
      throw std::invalid_argument("the warm start must be one column of forces");
    coulomb_->RestorePreviousForces(warm_start.size() ? Eigen::VectorXd(warm_start.col(0))
                                                      : Eigen::VectorXd());
  }

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    const auto start = std::chrono::steady_clock::now();
    delassus_.SolveS(step.q, &full_);
    x_free_.noalias() = delassus_.H() * full_;
    x_free_ = -x_free_;
    for (size_t c = 0; c < nodes_.size(); ++c) {
      double normal_motion = 0.0;
      for (int a = 0; a < 3; ++a)
        if (nodes_[c].dofs[a] >= 0)
          normal_motion += nodes_[c].normal(a) * step.u(nodes_[c].dofs[a]);
      gap0_(static_cast<Eigen::Index>(c)) =
          step.gap(static_cast<Eigen::Index>(c)) - normal_motion;
    }
    const bool ok = coulomb_->Solve(x_free_, gap0_, step.scales.force / step.force_scale,
                                    step.scales.displacement, tolerance_, &outcome_);
    // du = S^-1 (H' F - q); the contact forces, gaps and slips as CoulombStep found them.
    full_.noalias() = delassus_.H().transpose() * outcome_.force;
    full_ -= step.q;
    // (Field by field: outcome_.contact.x holds the contact unknowns, result->x all free
    // dofs - a copy of the whole Result would resize result->x twice per step.)
    const ContactSystem::Result& contact = outcome_.contact;
    result->normal_force = contact.normal_force;
    result->tangent_force = contact.tangent_force;
    result->gap = contact.gap;
    result->slip = contact.slip;
    delassus_.SolveS(full_, &result->x);

    const ncp::fc::Summary& s = outcome_.summary;
    StepOutcome out;
    out.ok = ok;
    if (ok) {
      out.status = "converged";
    } else {
      char buffer[96];
      std::snprintf(buffer, sizeof buffer,
                    "natural-map residual %.3e > tolerance %.3e (scaled): ",
                    outcome_.natural_map_residual, tolerance_);
      out.status = buffer + s.message;
    }
    out.newton_iterations = s.iterations;
    out.jacobian_evaluations = s.iterations;  // one generalized Jacobian per Newton step
    out.residual_evaluations = s.iterations + s.backtracks + 1;
    out.krylov_iterations = std::max(0, s.krylov_iterations);  // -1: dense (no GMRES)
    out.implicit_friction_bound = friction_;
    out.solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  std::vector<ContactNode> nodes_;
  DelassusOperator delassus_;
  std::unique_ptr<CoulombStep> coulomb_;
  double tolerance_;
  bool friction_;
  Eigen::VectorXd gap0_, x_free_, full_;
  CoulombStep::Outcome outcome_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeCoulombFcStep(const DynamicModel& model,
                                                 MassInverse* mass, double m_max,
                                                 const DynamicOptions& options) {
  return std::make_unique<CoulombFcStep>(model, mass, m_max, options,
                                         /*matrix_free=*/false);
}

std::unique_ptr<StepAlgorithm> MakeSparseStep(const DynamicModel& model,
                                              MassInverse* mass, double m_max,
                                              const DynamicOptions& options) {
  return std::make_unique<CoulombFcStep>(model, mass, m_max, options,
                                         /*matrix_free=*/true);
}

}  // namespace contact::internal
