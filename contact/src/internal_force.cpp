#include "internal_force.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "critical_time_step.hpp"
#include "parallel.hpp"

namespace contact::internal {

InternalForce::InternalForce(const DynamicModel& model) : model_(model) {
  finite_ =
      model.kinematics && model.kinematics->options().kinematics == Kinematics::kFinite;
}

const Eigen::VectorXd& InternalForce::Expand(const Eigen::VectorXd& u_free) {
  const DofMap& dofs = model_.kinematics->dofs();
  if (u_full_.size() != dofs.NumDofs()) u_full_.setZero(dofs.NumDofs());
  if (dofs.PrescribedValues().size() == dofs.NumDofs()) u_full_ = dofs.PrescribedValues();
  const std::vector<int>& free = dofs.FreeDofs();
  for (size_t i = 0; i < free.size(); ++i)
    u_full_(free[i]) = u_free(static_cast<Eigen::Index>(i));
  return u_full_;
}

void InternalForce::Check(int step, const Eigen::VectorXd& u, DynamicSummary* summary) {
  const BodyKinematics& k = *model_.kinematics;
  const StrainMeasure m = k.body().MeasureStrain(Expand(u));
  summary->max_rotation = std::max(summary->max_rotation, m.rotation);
  summary->max_spurious_strain =
      std::max(summary->max_spurious_strain, m.spurious_strain);
  if (k.SmallStrainValid(m) || summary->small_strain_invalid_step >= 0) return;
  summary->small_strain_invalid_step = step;
  if (k.options().kinematics == Kinematics::kAuto) finite_ = true;
}

bool InternalForce::Evaluate(int step, double time, const Eigen::VectorXd& u,
                             Eigen::VectorXd* Ku, double* W, DynamicSummary* summary) {
  if (model_.kinematics && !finite_) Check(step, u, summary);
  if (!finite_) {
    SymmetricMultiply(model_.K, u, Ku);
    *W = 0.5 * u.dot(*Ku);
    return true;
  }
  if (summary->finite_strain_from_step < 0) {
    summary->finite_strain_from_step = step;
    summary->kinematics = "finite";
    summary->material_model = ToString(model_.kinematics->FiniteModel());
  }
  const BodyKinematics& k = *model_.kinematics;
  const DofMap& dofs = k.dofs();
  const bool homogeneous = dofs.PrescribedValues().size() == 0 ||
                           dofs.PrescribedValues().lpNorm<Eigen::Infinity>() == 0.0;
  HyperelasticEvaluation r;
  if (homogeneous) {  // f_int,F(u) into the kept buffers (no K_FC u_C term)
    r = k.body().InternalForce(Expand(u), k.FiniteModel(), &f_full_);
    const std::vector<int>& free = dofs.FreeDofs();
    if (r.ok)
      for (size_t i = 0; i < free.size(); ++i)
        (*Ku)(static_cast<Eigen::Index>(i)) = f_full_(free[i]);
  } else {
    r = k.FiniteForce(u, Ku);
  }
  *W = r.energy;
  if (r.ok) return true;
  summary->status = DynamicStatus::kInvertedElement;
  char buffer[120];
  std::snprintf(buffer, sizeof buffer, "step %d (t = %.6g s): ", step, time);
  summary->message = buffer + r.message;
  return false;
}

bool InternalForce::RecheckCriticalStep(int step, const Eigen::VectorXd& u,
                                        const DynamicOptions& options, MassInverse* mass,
                                        DynamicSummary* summary) const {
  if (!finite_ || step % kRecheckSteps != 0) return true;
  const BodyKinematics& k = *model_.kinematics;
  SparseMatrix K_t;
  if (!k.body().TangentStiffness(k.dofs().Expand(u), k.FiniteModel(), &K_t).ok)
    return true;  // (Evaluate reports the inverted element)
  CriticalTimeStep crit =
      Lanczos(k.dofs().RestrictMatrix(K_t), model_.M, mass, 1e-3, 500);
  if (!(crit.dt_crit > 0.0) || !std::isfinite(crit.dt_crit)) return true;
  if (summary->critical_time_step > 0.0 && summary->critical_time_step < crit.dt_crit)
    return true;  // (not below the smallest estimate so far)
  const double previous = summary->critical_time_step;
  if (AcceptCriticalStep(crit, options, summary)) return true;
  char buffer[160];
  std::snprintf(
      buffer, sizeof buffer,
      "step %d, finite strain: the current tangent lowered dt_crit from %.6g s: ", step,
      previous);
  summary->message = buffer + summary->message;
  return false;
}

void InternalForce::SetFinalStatus(DynamicSummary* summary) {
  if (summary->small_strain_invalid_step < 0 || summary->finite_strain_from_step >= 0)
    return;
  char buffer[400];
  std::snprintf(buffer, sizeof buffer,
                "small strain was not valid from step %d: largest element rotation %.3g "
                "rad, spurious strain %.3g (theta^2/2) against the tolerance times the "
                "resolved strain; run with material.kinematics = \"auto\" or \"finite\"",
                summary->small_strain_invalid_step, summary->max_rotation,
                summary->max_spurious_strain);
  if (summary->status == DynamicStatus::kCompleted) {
    summary->status = DynamicStatus::kOutsideSmallStrain;
    summary->message = buffer;
  } else {
    summary->message += std::string("; ") + buffer;
  }
}

}  // namespace contact::internal
