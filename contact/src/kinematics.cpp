// Small or finite strain on the free dofs of a run (contact/kinematics.hpp).
#include "contact/kinematics.hpp"

#include <cmath>
#include <stdexcept>

#include "text_format.hpp"

namespace contact {

const char* ToString(Kinematics k) {
  switch (k) {
    case Kinematics::kAuto:
      return "auto";
    case Kinematics::kSmall:
      return "small";
    case Kinematics::kFinite:
      return "finite";
  }
  return "unknown";
}

Kinematics KinematicsFromString(const std::string& name) {
  for (Kinematics k : {Kinematics::kAuto, Kinematics::kSmall, Kinematics::kFinite})
    if (name == ToString(k)) return k;
  throw std::invalid_argument(
      "material.kinematics must be \"auto\", \"small\" or \"finite\", got \"" + name +
      "\"");
}

void KinematicsOptions::Validate() const {
  if (!(tolerance > 0.0 && tolerance <= 1.0))
    throw std::invalid_argument(
        "material.kinematics_tolerance must be in (0, 1] (a fraction of the resolved "
        "strain), got " +
        internal::Format(tolerance));
  if (kinematics == Kinematics::kSmall && model != MaterialModel::kLinear)
    throw std::invalid_argument(
        std::string("material.model = \"") + ToString(model) +
        "\" is a finite-strain model: it needs material.kinematics "
        "= \"auto\" or \"finite\", got \"small\"");
}

BodyKinematics::BodyKinematics(const ElasticBody& body, DofMap dofs,
                               KinematicsOptions options)
    : body_(body), dofs_(std::move(dofs)), options_(options) {
  options_.Validate();
  if (dofs_.NumDofs() != body_.NumDofs())
    throw std::invalid_argument("BodyKinematics: the dof map has " +
                                std::to_string(dofs_.NumDofs()) + " dofs, the body " +
                                std::to_string(body_.NumDofs()));
  if (dofs_.PrescribedValues().size() &&
      dofs_.PrescribedValues().lpNorm<Eigen::Infinity>() > 0.0)
    coupling_ = dofs_.RestrictVector(body_.StiffnessMatrix() * dofs_.PrescribedValues());
}

MaterialModel BodyKinematics::FiniteModel() const {
  return options_.model == MaterialModel::kLinear ? MaterialModel::kSaintVenantKirchhoff
                                                  : options_.model;
}

HyperelasticEvaluation BodyKinematics::FiniteForce(const Eigen::VectorXd& u_free,
                                                   Eigen::VectorXd* f) const {
  Vector f_full;
  HyperelasticEvaluation r =
      body_.InternalForce(dofs_.Expand(u_free), FiniteModel(), &f_full);
  if (!r.ok) return r;
  *f = dofs_.RestrictVector(f_full);
  if (coupling_.size()) {
    *f -= coupling_;
    r.energy -= coupling_.dot(u_free);
  }
  return r;
}

StrainMeasure BodyKinematics::Measure(const Eigen::VectorXd& u_free) const {
  return body_.MeasureStrain(dofs_.Expand(u_free));
}

bool BodyKinematics::SmallStrainValid(const StrainMeasure& m) const {
  return m.spurious_strain <= options_.tolerance * m.resolved_strain;
}

}  // namespace contact
