// Rayleigh damping C = a M + b K in central differences (contact/dynamics.hpp). The
// velocity is lagged, v^k = (u^k - u^{k-1}) / dt, so the step stays explicit in C:
//     M (u^{k+1} - 2 u^k + u^{k-1}) / dt^2 + C v^k + K u^k = f(t_k) + r^{k+1},
// i.e. Q^k (eq. 73) gains + C v^k and every step method solves the same system as
// without damping. On one mode (omega, xi = a / (2 omega) + b omega / 2) the recursion
// is stable iff omega^2 dt^2 + 2 (a + b omega^2) dt < 4, i.e.
//     dt <= dt_crit = (2 / omega) (sqrt(1 + xi^2) - xi),
// and since the left side grows with omega the highest mode omega_max decides.
// The work of C v^k over the half span (u^{k+1} - u^{k-1}) / 2 is the dissipation D of
// the energy balance: E^{k+1/2} - E^{-1/2} = W_ext + W_contact - D.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

#include "contact/dynamics_types.hpp"

namespace contact::internal {

/// The damped critical step (2 / omega)(sqrt(1 + xi^2) - xi) at omega = omega_max [rad/s]
/// in the cancellation-free form 4 / (c + sqrt(c^2 + 4 omega^2)), c = a + b omega^2
/// [1/s]: 2 / omega undamped, 2 / a at omega = 0, infinity without stiffness or damping.
double DampedCriticalStep(double omega_max, const RayleighDamping& damping);

/// The critical step of the run: crit with dt_crit replaced by DampedCriticalStep.
CriticalTimeStep WithDamping(CriticalTimeStep crit, const RayleighDamping& damping);

/// What a refused step's message adds for a damped run (empty when undamped).
std::string DampedCriticalStepNote(const CriticalTimeStep& crit,
                                   const RayleighDamping& damping);

/// The lagged viscous force c^k = C v^k [N] of a model on its free dofs.
class DampingForce {
 public:
  DampingForce(const DynamicModel& model, double dt);
  bool active() const { return damping_.active(); }
  /// c = (a M du + b K du) / dt from Mdu = M du and du = u^k - u^{k-1} [m] (one product
  /// with K when b != 0). No allocation once *c is sized.
  void Compute(const Eigen::VectorXd& Mdu, const Eigen::VectorXd& du, Eigen::VectorXd* c);

 private:
  const Eigen::SparseMatrix<double>& K_;
  RayleighDamping damping_;
  double dt_;
  Eigen::VectorXd Kdu_;
};

}  // namespace contact::internal
