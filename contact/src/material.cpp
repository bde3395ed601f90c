#include "contact/material.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "text_format.hpp"

namespace contact {
namespace {

using internal::Format;

}  // namespace

void IsotropicMaterial::Validate() const {
  if (!(std::isfinite(youngs_modulus) && youngs_modulus > 0))
    throw std::invalid_argument(
        "IsotropicMaterial: Young's modulus E must be finite and > 0, got E = " +
        Format(youngs_modulus));
  if (!(poisson_ratio > -1 && poisson_ratio < 0.5))
    throw std::invalid_argument(
        "IsotropicMaterial: Poisson ratio nu must satisfy -1 < nu < 0.5, got nu = " +
        Format(poisson_ratio));
  if (!(std::isfinite(density) && density > 0))
    throw std::invalid_argument(
        "IsotropicMaterial: density rho must be finite and > 0, got rho = " +
        Format(density));
}

double IsotropicMaterial::Lambda() const {
  return youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
}

double IsotropicMaterial::ShearModulus() const {
  return youngs_modulus / (2 * (1 + poisson_ratio));
}

void PlaneSettings::Validate() const {
  if (!(std::isfinite(thickness) && thickness > 0))
    throw std::invalid_argument(
        "PlaneSettings: thickness must be finite and > 0, got thickness = " +
        Format(thickness));
}

DenseMatrix ElasticityMatrix(const IsotropicMaterial& material, int dim,
                             PlaneModel plane_model) {
  material.Validate();
  const double mu = material.ShearModulus();
  if (dim == 2) {
    // Plane stress: lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2).
    const double lambda = plane_model == PlaneModel::kPlaneStrain
                              ? material.Lambda()
                              : material.youngs_modulus * material.poisson_ratio /
                                    (1 - material.poisson_ratio * material.poisson_ratio);
    DenseMatrix D(3, 3);
    D << lambda + 2 * mu, lambda, 0,  //
        lambda, lambda + 2 * mu, 0,   //
        0, 0, mu;
    return D;
  }
  if (dim == 3) {
    const double lambda = material.Lambda();
    DenseMatrix D = DenseMatrix::Zero(6, 6);
    D.topLeftCorner(3, 3).setConstant(lambda);
    for (int i = 0; i < 3; ++i) {
      D(i, i) += 2 * mu;
      D(3 + i, 3 + i) = mu;
    }
    return D;
  }
  throw std::invalid_argument("ElasticityMatrix: dim must be 2 or 3, got " +
                              std::to_string(dim));
}

}  // namespace contact
