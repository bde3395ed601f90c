// The explicit step of one contact node in closed form (StepMethod::kExplicit), shared by
// the serial step (explicit_step.cpp) and the distributed one (contact/petsc/).
#pragma once

#include <Eigen/Core>

#include "contact/contact_system.hpp"

namespace contact::internal {

/// What one contact node's explicit step gives (system units: forces / force_scale).
struct ExplicitNodeStep {
  double normal_force = 0.0;  ///< lambda_c >= 0
  double gap = 0.0;           ///< s_c - n_c . (u0 + y)_c [m]
  Eigen::Vector2d tangent_force = Eigen::Vector2d::Zero();  ///< tau_c (dim - 1 used)
  Eigen::Vector2d slip = Eigen::Vector2d::Zero();           ///< y_T [m] (dim - 1 used)
};

/// The node's step m y + q = F, F = (-lambda, tau), in the local frame of its free
/// components (S restricted to the node is m I, so the rotation keeps it diagonal):
///   normal:  y_n = -q_n / m predicted; if it would close past the obstacle
///            (s - u0_n - y_n < 0) then y_n = s - u0_n and lambda = -(m y_n + q_n) >= 0;
///   tangent: stick (y_T = 0, tau = q_T) if |q_T| <= g, else slide with tau = g q_T /
///   |q_T|
///            and y_T = (tau - q_T) / m - the return map onto the friction disc
/// (forward-increment Lagrange multipliers, Carpenter, Taylor and Katona 1991).
/// q, u0 and y are indexed by node.dofs (free components; -1 = constrained, skipped);
/// y gets the node's increment in global components. m: the node's diagonal of S (the
/// same in every free component), gap: s_c [m], bound: g_c (0 = frictionless).
/// obstacle_step (dim global components [m], or nullptr: at rest): the obstacle's
/// translation w over the step; the slip is then relative to it, y_T - w_T: stick is
/// y_T = w_T with tau = q_T + m w_T, so q_T is replaced by q_T + m w_T above.
inline ExplicitNodeStep SolveExplicitContactNode(int dim, const ContactNode& node,
                                                 double m, double gap, double bound,
                                                 const double* q, const double* u0,
                                                 double* y,
                                                 const double* obstacle_step = nullptr) {
  const Eigen::Vector3d frame[3] = {node.normal, node.tangent1, node.tangent2};
  int slots[3] = {0, 0, 0}, axes[3] = {0, 0, 0}, num_free = 0;
  for (int a = 0; a < dim; ++a)
    if (node.dofs[a] >= 0) slots[num_free] = node.dofs[a], axes[num_free++] = a;
  auto local = [&](const double* v, int a) {
    double sum = 0.0;
    for (int b = 0; b < num_free; ++b) sum += frame[a](axes[b]) * v[slots[b]];
    return sum;
  };
  ExplicitNodeStep out;
  // Normal.
  const double qn = local(q, 0), u0n = local(u0, 0);
  double yn = -qn / m, lambda = 0.0;
  if (gap - u0n - yn < 0.0) {
    yn = gap - u0n;
    lambda = -(m * yn + qn);
  }
  // Tangent: the return map onto |tau| <= g.
  const double g = bound;
  Eigen::Vector2d qt = Eigen::Vector2d::Zero(), yt = Eigen::Vector2d::Zero(),
                  tau = Eigen::Vector2d::Zero();
  for (int a = 1; a < num_free; ++a) qt(a - 1) = local(q, a);
  Eigen::Vector2d wt = Eigen::Vector2d::Zero();  // the obstacle's tangential step
  for (int a = 1; a < num_free && obstacle_step; ++a)
    for (int b = 0; b < num_free; ++b)
      wt(a - 1) += frame[a](axes[b]) * obstacle_step[axes[b]];
  qt += m * wt;  // the force that keeps the node stuck to the moving obstacle, minus m w
  if (g > 0.0 && qt.norm() <= g) {
    tau = qt;  // stick: y_T = w_T
    yt = wt;
  } else {
    tau = g > 0.0 ? Eigen::Vector2d(g * qt / qt.norm()) : Eigen::Vector2d::Zero();
    yt = (tau - qt) / m + wt;
  }
  // Back to the global components of the node.
  for (int b = 0; b < num_free; ++b) {
    double v = frame[0](axes[b]) * yn;
    for (int a = 1; a < num_free; ++a) v += frame[a](axes[b]) * yt(a - 1);
    y[slots[b]] = v;
  }
  out.normal_force = lambda;
  out.gap = gap - u0n - yn;
  for (int a = 1; a < num_free; ++a) {
    out.tangent_force(a - 1) = tau(a - 1);
    out.slip(a - 1) = yt(a - 1) - wt(a - 1);
  }
  return out;
}

}  // namespace contact::internal
