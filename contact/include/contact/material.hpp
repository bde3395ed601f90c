/// \file material.hpp
/// Isotropic linear elastic material and the 2D (plane strain / plane stress) models.
#pragma once

#include "contact/types.hpp"

namespace contact {

/// Isotropic, homogeneous, linear elastic material (SI units).
struct IsotropicMaterial {
  double youngs_modulus = 0;  ///< E [Pa], must be > 0
  double poisson_ratio = 0;   ///< nu [-], must satisfy -1 < nu < 0.5
  double density = 0;         ///< rho [kg/m^3], must be > 0

  /// Throws std::invalid_argument naming the first offending value (expected vs actual).
  void Validate() const;
  /// Lame's first parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa] (3D and plane
  /// strain).
  double Lambda() const;
  /// Shear modulus mu = G = E / (2 (1 + nu)) [Pa].
  double ShearModulus() const;
};

/// How a 2D mesh represents a 3D body.
enum class PlaneModel {
  kPlaneStrain,  ///< eps_zz = 0: a slice of a long body; thickness = depth represented
  kPlaneStress,  ///< sigma_zz = 0: a thin plate of the given thickness
};

/// The 2D model of a body; ignored for 3D meshes.
struct PlaneSettings {
  PlaneModel model = PlaneModel::kPlaneStrain;
  /// Out-of-plane thickness h [m], > 0. Every 2D integral is h times the in-plane
  /// integral, so K [N/m], M [kg], loads [N] and boundary areas [m^2] are those of a slab
  /// of thickness h (h = 1: per metre of depth).
  double thickness = 1.0;

  /// Throws std::invalid_argument if thickness <= 0 or is not finite.
  void Validate() const;
};

/// The elasticity matrix D in Voigt notation: sigma = D eps with engineering shear
/// strains (l = lambda, m = mu).
///   2D: [eps_xx, eps_yy, gamma_xy];
///       plane strain: D = [[l + 2m, l, 0], [l, l + 2m, 0], [0, 0, m]],
///       plane stress: D = E / (1 - nu^2) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]].
///   3D: [eps_xx, eps_yy, eps_zz, gamma_yz, gamma_xz, gamma_xy];
///       D = l 1 1^T + m diag(2, 2, 2, 1, 1, 1) (1 = (1, 1, 1, 0, 0, 0)).
/// Validates the material.
DenseMatrix ElasticityMatrix(const IsotropicMaterial& material, int dim,
                             PlaneModel plane_model = PlaneModel::kPlaneStrain);

}  // namespace contact
