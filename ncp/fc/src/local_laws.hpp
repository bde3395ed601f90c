// The Coulomb law of one contact written as Phi(r, u) = 0, with its generalized Jacobian
// blocks A = dPhi/dr and B = dPhi/du (components: normal, tangent 1[, tangent 2]; in 2D
// the third row and column stay zero).
#pragma once

#include <Eigen/Core>

namespace ncp::fc::internal {

using Block = Eigen::Matrix3d;

/// Alart-Curnier (Alart & Curnier 1991; Christensen & Pang 1998), with s_N = r_N - rho_N
/// u_N, s_T = r_T - rho_T u_T, radius R = mu max(0, s_N):
///   Phi_N = r_N - max(0, s_N),   Phi_T = r_T - P_{B(0,R)}(s_T).
/// Jacobian: the element of the B-subdifferential that takes max'(0) = 0 and, on the disk
/// boundary |s_T| = R, the sticking branch.
void AlartCurnierLaw(int d, double mu, double rho_n, double rho_t, const double* r,
                     const double* u, double* phi, Block* A, Block* B);

/// Natural map of the De Saxce form (Siconos NSN_NM): u_hat = u + (mu |u_T|, 0, 0),
///   Phi = r - P_{C_mu}(r - rho u_hat),
/// A = I - J_P, B = rho J_P (I + mu e_N (0, u_T/|u_T|)'), J_P the Jacobian of the cone
/// projection (identity inside, zero in the polar cone, Hiriart-Urruty's formula
/// between).
void NaturalMapLaw(int d, double mu, double rho, const double* r, const double* u,
                   double* phi, Block* A, Block* B);

}  // namespace ncp::fc::internal
