/// \file kinematics.hpp
/// Small or finite strain in a dynamic run (docs/finite-strain.md): the internal force of
/// the body on the free dofs, K u (small strain) or f_int(u) (finite strain, total
/// Lagrangian), and the check that chooses between them.
#pragma once

#include <string>

#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/hyperelastic_material.hpp"

namespace contact {

/// material.kinematics.
enum class Kinematics {
  /// Small strain while the linear model is valid (KinematicsOptions::tolerance), finite
  /// strain from the first step at which it is not, to the end of the run.
  kAuto,
  kSmall,   ///< K u throughout; a run that leaves validity ends kOutsideSmallStrain
  kFinite,  ///< f_int(u) throughout
};
/// "auto", "small", "finite".
const char* ToString(Kinematics k);
/// The inverse of ToString; throws std::invalid_argument naming the accepted names.
Kinematics KinematicsFromString(const std::string& name);

struct KinematicsOptions {
  Kinematics kinematics = Kinematics::kAuto;
  MaterialModel model = MaterialModel::kLinear;
  /// The linear model is valid at u while StrainMeasure::spurious_strain <= tolerance *
  /// StrainMeasure::resolved_strain: the strain term the linear model drops (theta^2/2
  /// for a rotation theta) at most this fraction of the largest strain it represents.
  double tolerance = 1e-2;
  /// Throws std::invalid_argument naming material.kinematics_tolerance (accepted
  /// (0, 1]) or a model that needs finite kinematics ("small" with a hyperelastic
  /// model: the model is the stored energy of finite strain).
  void Validate() const;
};

/// The body's internal force on the free dofs of a DofMap. The body must outlive it.
class BodyKinematics {
 public:
  BodyKinematics(const ElasticBody& body, DofMap dofs, KinematicsOptions options);

  const KinematicsOptions& options() const { return options_; }
  const ElasticBody& body() const { return body_; }
  const DofMap& dofs() const { return dofs_; }

  /// The finite-strain internal force on the free dofs at u_free [m]:
  ///   f = f_int,F(u) - K_FC u_C [N]
  /// (u the full vector with the prescribed values u_C; K_FC u_C is the part of the
  /// small-strain force the scene's load vector already carries), and the matching
  /// stored energy W(u) - (K_FC u_C) . u_F [J] into evaluation.energy, so that f is its
  /// gradient. In the small-strain limit f = K_FF u_F.
  HyperelasticEvaluation FiniteForce(const Eigen::VectorXd& u_free,
                                     Eigen::VectorXd* f) const;
  /// The strain measure at u_free, and whether the linear model is valid there.
  StrainMeasure Measure(const Eigen::VectorXd& u_free) const;
  bool SmallStrainValid(const StrainMeasure& m) const;
  /// The material model that finite strain evaluates (kLinear runs as Saint
  /// Venant-Kirchhoff, its geometrically exact form).
  MaterialModel FiniteModel() const;

 private:
  const ElasticBody& body_;
  DofMap dofs_;
  KinematicsOptions options_;
  Eigen::VectorXd coupling_;  // K_FC u_C [N] (empty when u_C = 0)
};

}  // namespace contact
