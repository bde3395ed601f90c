// The internal force of each step of central differences (contact/dynamics.hpp): K u
// under small strain, f_int(u) under finite strain (contact/kinematics.hpp), with the
// choice of material.kinematics = "auto" made step by step and reported in the summary.
#pragma once

#include <Eigen/Core>

#include "contact/dynamics.hpp"
#include "mass_inverse.hpp"

namespace contact::internal {

class InternalForce {
 public:
  explicit InternalForce(const DynamicModel& model);

  /// Ku = the internal force at u = u^{step} [N] (free dofs), W = the stored energy
  /// [J]. Small strain: K u and u'Ku/2, after the validity check (auto switches to finite
  /// strain from this step on when it fails; small records it). False if an element
  /// is inverted: the summary gets kInvertedElement and a message naming element and
  /// step.
  bool Evaluate(int step, double time, const Eigen::VectorXd& u, Eigen::VectorXd* Ku,
                double* W, DynamicSummary* summary);
  /// Whether the forces are those of finite strain (from the step of the switch on).
  bool finite() const { return finite_; }
  /// Takes the switch from a restored summary (finite_strain_from_step).
  void Restore(const DynamicSummary& summary) {
    finite_ = summary.finite_strain_from_step >= 0;
  }
  /// Finite strain, every kRecheckSteps steps: dt_crit = 2 / omega_max of the current
  /// tangent K_t(u) on the free dofs (Lanczos on (K_t, M) to a relative 1e-3); the
  /// smallest estimate is summary->critical_time_step. False (kRefusedUnstable, the
  /// message naming the step) if options.dt exceeds it without allow_unstable_time_step:
  /// the run is refused from there on, dt is never shortened silently.
  bool RecheckCriticalStep(int step, const Eigen::VectorXd& u,
                           const DynamicOptions& options, MassInverse* mass,
                           DynamicSummary* summary) const;
  static constexpr int kRecheckSteps = 500;

  /// Marks a run whose small strain was not valid (kOutsideSmallStrain) once it ended
  /// otherwise completed; else leaves the summary as it is.
  static void SetFinalStatus(DynamicSummary* summary);

 private:
  void Check(int step, const Eigen::VectorXd& u, DynamicSummary* summary);

  // u and f_int on every dof, kept so that a step allocates nothing.
  const Eigen::VectorXd& Expand(const Eigen::VectorXd& u_free);

  const DynamicModel& model_;
  bool finite_ = false;
  Eigen::VectorXd u_full_, f_full_;  // [m], [N], every dof
};

}  // namespace contact::internal
