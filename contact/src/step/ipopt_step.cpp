// The frictionless step as a convex QP solved by Ipopt (StepMethod::kIpopt), and the QP
// itself, which DynamicOptions::compare_with_ipopt solves next to another step method.
#include <chrono>

#include "step/step_method.hpp"

namespace contact::internal {

IpoptQp::IpoptQp(const DynamicModel& model, double m_max, double tolerance)
    : S_(model.M / m_max), tolerance_(tolerance) {
  // Rows n_c . du_c <= s_c - n_c . u^k, i.e. G = Y R.
  const RestrictionMaps maps = MakeRestrictionMaps(
      model.dim, static_cast<int>(model.M.rows()), model.contact_nodes);
  G_ = maps.Y * maps.R;
}

ConvexQpResult IpoptQp::Solve(const StepData& step) const {
  // Posed in the step's own scales (du = D xi, forces = F z), so that Ipopt's tests at
  // tol = ncp.tolerance - stationarity, constraint violation and lambda_c gap_c - mean
  // tolerance F, tolerance D and tolerance F D in the units of the step:
  //   min 1/2 xi' (S D / F) xi + (q / F)' xi   s.t.  G xi <= (s - G u^k) / D.
  const double F = step.scales.force / step.force_scale, D = step.scales.displacement;
  ConvexQpOptions qp_options;
  qp_options.tolerance = tolerance_;
  qp_options.dual_infeasibility_tolerance = tolerance_;
  qp_options.constraint_violation_tolerance = tolerance_;
  qp_options.complementarity_tolerance = tolerance_;
  ConvexQpResult qp =
      SolveConvexQpIpopt((D / F) * S_, step.q / F, G_, (step.gap - G_ * step.u) / D,
                         step.guess / D, qp_options);
  qp.x *= D;
  qp.multipliers *= F;
  return qp;
}

namespace {

// The step method: the QP's solution, with gaps and slips from a ContactSystem over the
// same S (frictionless: no tangent forces).
class IpoptStep : public StepAlgorithm {
 public:
  IpoptStep(const DynamicModel& model, double m_max, double tolerance)
      : qp_(model, m_max, tolerance),
        system_(model.dim, model.M / m_max, model.contact_nodes) {}

  StepOutcome Solve(const StepData& step, ContactSystem::Result* result) override {
    system_.SetGaps(step.gap);
    system_.Update(step.q, step.u, step.bound);
    system_.SetResidualScales(step.scales.force / step.force_scale,
                              step.scales.displacement);
    const auto start = std::chrono::steady_clock::now();
    const ConvexQpResult qp = qp_.Solve(step);
    StepOutcome out;
    out.solve_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.ok = qp.status == ConvexQpStatus::kSolved;
    out.status = out.ok ? "converged" : qp.message;
    out.newton_iterations = qp.iterations;
    *result = system_.Extract(system_.StartPoint(qp.x));
    result->normal_force = qp.multipliers;
    return out;
  }

 private:
  IpoptQp qp_;
  ContactSystem system_;
};

}  // namespace

std::unique_ptr<StepAlgorithm> MakeIpoptStep(const DynamicModel& model, double m_max,
                                             double tolerance) {
  return std::make_unique<IpoptStep>(model, m_max, tolerance);
}

}  // namespace contact::internal
