#include "step_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace contact::internal {

StepScales ComputeStepScales(const Eigen::VectorXd& f, const Eigen::VectorXd& Ku,
                             double contact_force_max, const Eigen::VectorXd& du_previous,
                             const std::vector<ContactNode>& nodes,
                             const Eigen::VectorXd& u, double m_max, double dt) {
  double penetration = 0.0;
  for (const ContactNode& node : nodes) {
    double un = 0.0;
    for (int a = 0; a < 3; ++a)
      if (node.dofs[a] >= 0) un += node.normal(a) * u(node.dofs[a]);
    penetration = std::max(penetration, un - node.gap);
  }
  return StepScalesFromMaxima(f.lpNorm<Eigen::Infinity>(), Ku.lpNorm<Eigen::Infinity>(),
                              contact_force_max, du_previous.lpNorm<Eigen::Infinity>(),
                              penetration, m_max, dt);
}

StepScales StepScalesFromMaxima(double f_max, double Ku_max, double contact_force_max,
                                double du_max, double penetration, double m_max,
                                double dt) {
  StepScales out;
  out.force = std::max({f_max, Ku_max, contact_force_max});
  const double step_of_force = out.force * dt * dt / m_max;
  out.displacement = std::max({du_max, step_of_force, std::max(penetration, 0.0)});
  if (out.force == 0.0) out.force = out.displacement * m_max / (dt * dt);
  if (out.force == 0.0)
    out.force = out.displacement = 1.0;  // nothing moves, loads or touches
  return out;
}

void SetAskedAccuracy(double tolerance, const StepScales& scales,
                      const Eigen::VectorXd& Q, const Eigen::VectorXd& Mdu, double dt,
                      const Eigen::VectorXd& u_next, const Eigen::VectorXd& gap0,
                      StepRecord* rec) {
  AskedAccuracyMaxima maxima;
  maxima.Q = Q.lpNorm<Eigen::Infinity>();
  maxima.Mdu = Mdu.lpNorm<Eigen::Infinity>();
  maxima.u_next = u_next.lpNorm<Eigen::Infinity>();
  maxima.gap0 = gap0.lpNorm<Eigen::Infinity>();
  SetAskedAccuracy(tolerance, scales, maxima, dt, rec);
}

void SetAskedAccuracy(double tolerance, const StepScales& scales,
                      const AskedAccuracyMaxima& maxima, double dt, StepRecord* rec) {
  const double eps = std::numeric_limits<double>::epsilon();
  rec->force_accuracy =
      tolerance * scales.force +
      ContactSystem::kRoundoffUlps * eps * (maxima.Q + maxima.Mdu / (dt * dt));
  rec->displacement_accuracy =
      tolerance * scales.displacement +
      ContactSystem::kRoundoffUlps * eps * (maxima.u_next + maxima.gap0);
}

// Accuracy of a completed step, recomputed from the state in newtons and metres:
//   equilibrium: r = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k - f^k (given) must equal
//   the
//     contact forces -lambda_c n_c + tau_c at the contact nodes and 0 elsewhere;
//   penetration: max(0, -(s_c - n_c . u^{k+1}_c));
//   complementarity: lambda_c >= 0, and lambda_c = 0 where the gap is open by more than
//     kAccuracySlack displacement accuracies;
//   friction: |tau_c| <= g_c, and tau_c = -g_c slip_c / |slip_c| where the node slips by
//   more
//     than kAccuracySlack displacement accuracies (g_c [N] the step's Tresca bound), its
//     direction to within the angle that the slip's own accuracy leaves (see below).
void MeasureStepAccuracy(int dim, const std::vector<ContactNode>& nodes,
                         const Eigen::VectorXd& r, const ContactSystem::Result& contact,
                         double force_scale, const Eigen::VectorXd& u_next,
                         const Eigen::VectorXd& bound, Eigen::VectorXd* residual,
                         StepRecord* rec) {
  // (bound and the contact result in system units: times force_scale for newtons.)
  *residual = r;  // minus the contact forces below
  double penetration = 0.0, complementarity = 0.0, friction = 0.0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const ContactNode& node = nodes[i];
    const auto c = static_cast<Eigen::Index>(i);
    const double lambda = force_scale * contact.normal_force(c);
    Eigen::Vector3d force = -lambda * node.normal;
    Eigen::Vector2d tau = Eigen::Vector2d::Zero(), slip = Eigen::Vector2d::Zero();
    for (int a = 1; a < dim; ++a) {
      const Eigen::Vector3d& t = a == 1 ? node.tangent1 : node.tangent2;
      tau(a - 1) = force_scale * contact.tangent_force(a - 1, c);
      slip(a - 1) = contact.slip(a - 1, c);
      force += tau(a - 1) * t;
    }
    double un = 0.0;
    for (int a = 0; a < dim; ++a) {
      if (node.dofs[a] < 0) continue;
      (*residual)(node.dofs[a]) -= force(a);
      un += node.normal(a) * u_next(node.dofs[a]);
    }
    const double gap = node.gap - un;
    penetration = std::max(penetration, -gap);
    complementarity = std::max(complementarity, -lambda);
    if (gap > kAccuracySlack * rec->displacement_accuracy)  // open: no force
      complementarity = std::max(complementarity, lambda);
    const double g = bound.size() ? force_scale * bound(c) : 0.0;
    friction = std::max(friction, tau.norm() - g);
    const double slack_of_slip = kAccuracySlack * rec->displacement_accuracy;
    if (slip.norm() > slack_of_slip) {  // slipping: tau = -g s/|s| (s = slip)
      // Along the slip, |tau| must reach g. Across it, the slip - right to slack_of_slip
      // in each component - fixes its direction only to within the angle slack_of_slip /
      // |s|, so tau may lean off -s by g times that angle before it violates the law (at
      // |s| >> the accuracy this is no allowance; at a slip just above it, tau's
      // direction is not data).
      const Eigen::Vector2d direction = slip / slip.norm();
      const double along = tau.dot(direction) + g;
      const double across = (tau - tau.dot(direction) * direction).norm();
      const double lean =
          std::max(0.0, across - g * std::min(1.0, slack_of_slip / slip.norm()));
      friction = std::max(friction, std::hypot(along, lean));
    }
  }
  rec->equilibrium_residual = residual->lpNorm<Eigen::Infinity>();
  rec->max_penetration = std::max(0.0, penetration);
  rec->complementarity_residual = complementarity;
  rec->friction_residual = friction;
  rec->accurate = StepIsAccurate(*rec);
}

bool StepIsAccurate(const StepRecord& rec) {
  return rec.equilibrium_residual <= kAccuracySlack * rec.force_accuracy &&
         rec.complementarity_residual <= kAccuracySlack * rec.force_accuracy &&
         rec.friction_residual <= kAccuracySlack * rec.force_accuracy &&
         rec.max_penetration <= kAccuracySlack * rec.displacement_accuracy;
}

void SetFinalStatus(const StepRecord& first_inaccurate, DynamicSummary* summary) {
  if (summary->status == DynamicStatus::kNotRun && summary->inaccurate_steps > 0) {
    summary->status = DynamicStatus::kAccuracyNotReached;
    char buffer[400];
    std::snprintf(
        buffer, sizeof buffer,
        "%d of %d steps missed their accuracy; the first, step %d (t = %.6g s): "
        "equilibrium %.3e N, contact %.3e N, friction %.3e N against %.3e N, "
        "penetration %.3e m against %.3e m (x %g allowed)",
        summary->inaccurate_steps, summary->steps, first_inaccurate.step,
        first_inaccurate.time, first_inaccurate.equilibrium_residual,
        first_inaccurate.complementarity_residual, first_inaccurate.friction_residual,
        first_inaccurate.force_accuracy, first_inaccurate.max_penetration,
        first_inaccurate.displacement_accuracy, kAccuracySlack);
    summary->message = buffer;
  }
  if (summary->status == DynamicStatus::kNotRun) {
    summary->status = DynamicStatus::kCompleted;
    summary->message =
        "all " + std::to_string(summary->steps) + " time steps solved to their accuracy";
  }
}

void SetInterrupted(const StepRecord& rec, long num_steps, DynamicSummary* summary) {
  summary->status = DynamicStatus::kInterrupted;
  char buffer[200];
  std::snprintf(buffer, sizeof buffer, "interrupted at step %d (t = %.9g s) of %ld",
                rec.step, rec.time, num_steps);
  summary->message = buffer;
}

}  // namespace contact::internal
