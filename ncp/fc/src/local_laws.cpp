#include "local_laws.hpp"

#include <cmath>

#include "ncp/fc/error.hpp"

namespace ncp::fc::internal {

namespace {

/// The tangential part of a d-vector as a 3-vector (third entry 0 in 2D).
Eigen::Vector3d Tangent(int d, const double* v) {
  return Eigen::Vector3d(0.0, v[1], d == 3 ? v[2] : 0.0);
}

/// Selector of the tangential components: diag(0, 1[, 1]).
Block TangentSelector(int d) {
  Block E = Block::Zero();
  for (int i = 1; i < d; ++i) E(i, i) = 1.0;
  return E;
}

/// Jacobian of the projection onto C_mu at s (see ProjectOnCone). With t = |s_T|,
/// n = s_T / t, a = (s_N + mu t) / (1 + mu^2), between the cones:
///   J_P = [1, mu n'; mu n, mu^2 n n'] / (1 + mu^2) + (mu a / t) (E_T - n n').
Block ConeProjectionJacobian(int d, double mu, const Eigen::Vector3d& s) {
  const Eigen::Vector3d sT = Tangent(d, s.data());
  const double t = sT.norm();
  if (t <= mu * s[0])
    return d == 3 ? Block::Identity() : Block(Eigen::Vector3d(1, 1, 0).asDiagonal());
  if (mu * t <= -s[0]) return Block::Zero();
  const Eigen::Vector3d n = sT / t;
  const double a = (s[0] + mu * t) / (1.0 + mu * mu);
  Eigen::Vector3d v = mu * n;  // (1, mu n) / sqrt(1 + mu^2) is the boundary direction
  v[0] = 1.0;
  Block J = v * v.transpose() / (1.0 + mu * mu);
  J += (mu * a / t) * (TangentSelector(d) - n * n.transpose());
  return J;
}

}  // namespace

void AlartCurnierLaw(int d, double mu, double rho_n, double rho_t, const double* r,
                     const double* u, double* phi, Block* A, Block* B) {
  A->setZero();
  B->setZero();
  const Block ET = TangentSelector(d);
  const double sN = r[0] - rho_n * u[0];
  const bool open = sN > 0.0;  // normal force active
  if (open) {
    phi[0] = rho_n * u[0];
    (*B)(0, 0) = rho_n;
  } else {
    phi[0] = r[0];
    (*A)(0, 0) = 1.0;
  }
  const Eigen::Vector3d rT = Tangent(d, r), sT = rT - rho_t * Tangent(d, u);
  const double radius = mu * std::max(0.0, sN), t = sT.norm();
  if (t <= radius) {  // sticking: Phi_T = rho_t u_T
    for (int i = 1; i < d; ++i) phi[i] = rho_t * u[i];
    B->bottomRows<2>() += rho_t * ET.bottomRows<2>();
    return;
  }
  // sliding: Phi_T = r_T - R n, n = s_T / t;
  // dP = (R / t)(E_T - n n') ds_T + n dR, ds_T = E_T (dr - rho_t du), dR = mu [s_N > 0]
  // ds_N.
  const Eigen::Vector3d n = sT / t;
  for (int i = 1; i < d; ++i) phi[i] = r[i] - radius * n[i];
  const Block Pt = (radius / t) * (ET - n * n.transpose());
  *A += ET - Pt;
  *B += rho_t * Pt;
  if (open) {
    A->col(0) -= mu * n;
    B->col(0) += mu * rho_n * n;
  }
}

void NaturalMapLaw(int d, double mu, double rho, const double* r, const double* u,
                   double* phi, Block* A, Block* B) {
  const Eigen::Vector3d uT = Tangent(d, u);
  const double ut = uT.norm();
  Eigen::Vector3d s = Eigen::Vector3d::Zero(), P;
  s[0] = r[0] - rho * (u[0] + mu * ut);
  for (int i = 1; i < d; ++i) s[i] = r[i] - rho * u[i];
  const Block JP = ConeProjectionJacobian(d, mu, s);
  P = s;
  ProjectOnCone(mu, d, P.data());
  for (int i = 0; i < d; ++i) phi[i] = r[i] - P[i];
  Block I = Block::Identity();
  if (d == 2) I(2, 2) = 0.0;
  Block D = I;  // d u_hat / d u
  if (ut > 0.0) D.row(0) += mu * (uT / ut).transpose();
  *A = I - JP;
  *B = rho * JP * D;
}

}  // namespace ncp::fc::internal
