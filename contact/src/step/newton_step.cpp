#include "step/newton_step.hpp"

#include <chrono>

namespace contact::internal {

StepOutcome NewtonStep::Solve(ContactSystem* system, const Eigen::VectorXd& guess,
                              ncp::Vector* z) {
  const auto start = std::chrono::steady_clock::now();
  StepOutcome out;
  *z = system->StartPoint(guess, friction_previous_);
  ncp::Summary s;
  solver_.Solve(*system, z, &s);
  out.newton_iterations = s.iterations;
  out.jacobian_evaluations = s.jacobian_evaluations;
  out.residual_evaluations = s.residual_evaluations;
  if (!s.IsSolutionUsable() && system->num_friction_nodes() > 0 &&
      friction_previous_.size()) {
    *z = system->StartPoint(guess);
    solver_.Solve(*system, z, &s);
    out.newton_iterations += s.iterations;
    out.jacobian_evaluations += s.jacobian_evaluations;
    out.residual_evaluations += s.residual_evaluations;
    ++out.friction_restarts;
  }
  out.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.ok = s.IsSolutionUsable();
  out.status = out.ok ? "converged" : s.message;
  return out;
}

}  // namespace contact::internal
