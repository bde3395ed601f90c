/// \file hyperelastic_material.hpp
/// The constitutive models of ElasticBody at finite strain and the results of its
/// finite-strain evaluations (docs/finite-strain.md has the formulas).
///
/// Total Lagrangian: F = I + Grad u (Grad with respect to the reference coordinates X),
/// C = F' F, Green-Lagrange strain E = (C - I) / 2, second Piola-Kirchhoff stress
/// S = dW/dE, first Piola-Kirchhoff P = F S, Cauchy stress sigma = F S F' / J,
/// J = det F. Lame parameters lambda, mu [Pa] of the IsotropicMaterial.
#pragma once

#include <Eigen/Core>
#include <string>

namespace contact {

/// The strain energy density W(E) [J/m^3].
enum class MaterialModel {
  /// Linear elasticity (Hooke). Under small kinematics the stiffness K of the body;
  /// under finite kinematics its geometrically exact extension, Saint Venant-Kirchhoff.
  kLinear,
  /// W = lambda/2 (tr E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E.
  kSaintVenantKirchhoff,
  /// Compressible neo-Hookean (Bonet and Wood, Nonlinear Continuum Mechanics, eq. 6.27):
  /// W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
  /// S = mu (I - C^-1) + lambda ln(J) C^-1.
  kNeoHookean,
};
/// "linear", "saint-venant-kirchhoff", "neo-hookean".
const char* ToString(MaterialModel m);
/// The inverse of ToString; throws std::invalid_argument naming the accepted names.
MaterialModel MaterialModelFromString(const std::string& name);

/// The outcome of a finite-strain evaluation over the body. Never thrown: an element
/// with det F <= 0 (inverted) at a quadrature point makes ok false and names it.
struct HyperelasticEvaluation {
  bool ok = true;
  double energy = 0.0;         ///< stored energy h int W dV_0 [J] (when ok)
  int inverted_element = -1;   ///< the first element with det F <= 0 (when !ok)
  double det_F = 1.0;          ///< its det F [-]
  std::string message = "ok";  ///< names the element and det F when !ok
};

/// How far the displacement u is from the small-strain regime, from the displacement
/// gradient H = Grad u at the centre of every element:
///   rotation: the infinitesimal rotation |skew H| (2D: |H_yx - H_xy| / 2; 3D: the norm
///       of the axial vector) [rad], the largest over the elements;
///   spurious_strain: max over elements of max_ij |(H' H)_ij| / 2, the term the linear
///       strain sym(H) drops from E = sym(H) + H' H / 2 (theta^2/2 for a rigid rotation
///       by theta) [-];
///   resolved_strain: max over elements of max_ij |sym(H)_ij|, the strain the linear
///       model represents [-].
struct StrainMeasure {
  double rotation = 0.0, spurious_strain = 0.0, resolved_strain = 0.0;
  int rotation_element = -1;  ///< the element of the largest rotation
};

}  // namespace contact
