/// \file error.hpp
/// Siconos' error measure of the frictional contact problem and the cone projection.
#pragma once

#include "ncp/fc/problem.hpp"

namespace ncp::fc {

/// Orthogonal projection of z = (z_N, z_T) onto C_mu = {|z_T| <= mu z_N} (dimension 2 or
/// 3): z if inside; 0 if in the polar cone (mu |z_T| <= -z_N); otherwise
/// ((z_N + mu |z_T|) / (1 + mu^2)) (1, mu z_T / |z_T|).
void ProjectOnCone(double mu, int dimension, double* z);

/// The natural-map error of Siconos (fc3d_compute_error):
///   u = W r + q,  e_alpha = r_alpha - P_{C_mu}(r_alpha - u_hat_alpha),
///   error = ||e||_2 / (1 + ||q||_2).
/// It is zero exactly at the solutions. Throws std::invalid_argument on a size mismatch.
double NaturalMapError(const FrictionProblem& problem, const Vector& r);

/// ||e||_2 of the natural map at forces r and relative motions u (not normalized, no
/// check of u = W r + q): for solvers that hold u. mu one entry per contact.
double NaturalMapResidual(int dimension, const Vector& mu, const Vector& r,
                          const Vector& u);

/// ||e||_2^2 of NaturalMapResidual (its square root is NaturalMapResidual, to the bit):
/// the part of the contacts given, summed over the parts of a distributed problem.
double NaturalMapSquaredResidual(int dimension, const Vector& mu, const Vector& r,
                                 const Vector& u);

}  // namespace ncp::fc
