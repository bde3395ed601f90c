// Rayleigh damping in central differences (damping.hpp).
#include "damping.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "parallel.hpp"

namespace contact::internal {

double DampedCriticalStep(double omega_max, const RayleighDamping& damping) {
  // Positive root of omega^2 dt^2 + 2 c dt - 4 = 0, c = a + b omega^2.
  const double c = damping.mass + damping.stiffness * omega_max * omega_max;
  const double denominator = c + std::sqrt(c * c + 4.0 * omega_max * omega_max);
  return denominator > 0.0 ? 4.0 / denominator : std::numeric_limits<double>::infinity();
}

CriticalTimeStep WithDamping(CriticalTimeStep crit, const RayleighDamping& damping) {
  if (damping.active() && crit.omega_max >= 0.0 && std::isfinite(crit.omega_max))
    crit.dt_crit = DampedCriticalStep(crit.omega_max, damping);
  return crit;
}

std::string DampedCriticalStepNote(const CriticalTimeStep& crit,
                                   const RayleighDamping& damping) {
  if (!damping.active()) return "";
  const double w = crit.omega_max;
  const double xi = 0.5 * damping.mass / w + 0.5 * damping.stiffness * w;
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "; with Rayleigh damping (material.damping, lagged velocity) dt_crit = "
                "(2/omega_max)(sqrt(1 + xi^2) - xi), xi = a/(2 omega_max) + b "
                "omega_max/2 = %.6g",
                xi);
  return buffer;
}

DampingForce::DampingForce(const DynamicModel& model, double dt)
    : K_(model.K), damping_(model.damping), dt_(dt) {}

void DampingForce::Compute(const Eigen::VectorXd& Mdu, const Eigen::VectorXd& du,
                           Eigen::VectorXd* c) {
  *c = (damping_.mass / dt_) * Mdu;
  if (damping_.stiffness == 0.0) return;
  Kdu_.resize(du.size());
  SymmetricMultiply(K_, du, &Kdu_);
  *c += (damping_.stiffness / dt_) * Kdu_;
}

}  // namespace contact::internal
