// IsotropicMaterial validation and the elasticity matrices.
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/material.hpp>

namespace contact {
namespace {

using Catch::Matchers::WithinRel;

TEST_CASE("invalid material values are named with the offending value", "[material]") {
  CHECK_THROWS_WITH(
      (IsotropicMaterial{0.0, 0.3, 1000}.Validate()),
      Catch::Contains("Young's modulus E must be finite and > 0, got E = 0"));
  CHECK_THROWS_WITH((IsotropicMaterial{-2e9, 0.3, 1000}.Validate()),
                    Catch::Contains("got E = -2000000000"));
  CHECK_THROWS_WITH((IsotropicMaterial{1e9, 0.5, 1000}.Validate()),
                    Catch::Contains("-1 < nu < 0.5, got nu = 0.5"));
  CHECK_THROWS_WITH((IsotropicMaterial{1e9, -1.0, 1000}.Validate()),
                    Catch::Contains("got nu = -1"));
  CHECK_THROWS_WITH((IsotropicMaterial{1e9, 0.3, 0.0}.Validate()),
                    Catch::Contains("density rho must be finite and > 0, got rho = 0"));
  CHECK_THROWS_AS((IsotropicMaterial{1e9, 0.3, std::nan("")}.Validate()),
                  std::invalid_argument);
  CHECK_THROWS_WITH(
      (PlaneSettings{PlaneModel::kPlaneStress, 0.0}.Validate()),
      Catch::Contains("thickness must be finite and > 0, got thickness = 0"));
  CHECK_NOTHROW((IsotropicMaterial{1e9, -0.99, 1.0}.Validate()));
}

TEST_CASE("elasticity matrices in Voigt notation", "[material]") {
  const IsotropicMaterial steel{200e9, 0.25, 7800};
  const double mu = 80e9,
               lambda = 80e9;  // E nu / ((1 + nu)(1 - 2 nu)) = 200e9 * 0.25 / 0.625
  CHECK_THAT(steel.ShearModulus(), WithinRel(mu, 1e-15));
  CHECK_THAT(steel.Lambda(), WithinRel(lambda, 1e-15));

  const DenseMatrix strain = ElasticityMatrix(steel, 2, PlaneModel::kPlaneStrain);
  CHECK_THAT(strain(0, 0), WithinRel(lambda + 2 * mu, 1e-15));
  CHECK_THAT(strain(0, 1), WithinRel(lambda, 1e-15));
  CHECK_THAT(strain(2, 2), WithinRel(mu, 1e-15));

  // Plane stress: E / (1 - nu^2) = 200e9 / 0.9375.
  const DenseMatrix stress = ElasticityMatrix(steel, 2, PlaneModel::kPlaneStress);
  CHECK_THAT(stress(1, 1), WithinRel(200e9 / 0.9375, 1e-15));
  CHECK_THAT(stress(0, 1), WithinRel(0.25 * 200e9 / 0.9375, 1e-15));
  CHECK_THAT(stress(2, 2), WithinRel(mu, 1e-15));
  // Uniaxial plane stress: eps = D^-1 [1, 0, 0] gives eps_yy = -nu eps_xx.
  const Eigen::Vector3d eps = stress.inverse() * Eigen::Vector3d(1, 0, 0);
  CHECK_THAT(eps(1) / eps(0), WithinRel(-0.25, 1e-14));

  const DenseMatrix three = ElasticityMatrix(steel, 3);
  CHECK(three.rows() == 6);
  CHECK_THAT(three(2, 2), WithinRel(lambda + 2 * mu, 1e-15));
  CHECK_THAT(three(1, 2), WithinRel(lambda, 1e-15));
  CHECK_THAT(three(4, 4), WithinRel(mu, 1e-15));
  CHECK(three(0, 4) == 0.0);
  CHECK_THROWS_WITH(ElasticityMatrix(steel, 1),
                    Catch::Contains("dim must be 2 or 3, got 1"));
}

}  // namespace
}  // namespace contact
