// One mortar contact solve with Coulomb friction (bodies_contact.hpp), in the Delassus
// form of ncp::fc (ncp/fc/include/ncp/fc/problem.hpp). The mixed problem
//     S x + q = B' lambda + T' tau,
//     0 <= lambda_j  perp  g_j = g_base,j + (B x)_j >= 0,
//     |tau_j| <= mu_j lambda_j,  tau_j = -mu_j lambda_j s_j / |s_j| where s_j != 0,
//     s_j = s_base,j + (T x)_j,
// is condensed on the contact rows H = (B_j; T_j) interleaved per constraint j (normal,
// tangent), with G = S^-1 H' and W = H G (symmetric positive semidefinite):
//     u = (g_j, s_j)_j = W r + q_fc,   q_fc = -H S^-1 q + (g_base,j, s_base,j)_j,
//     x = -S^-1 q + G r,               r = (lambda_j, tau_j)_j,
// De Saxce's form C*_mu ∋ u + (mu |s|, 0) perp r ∈ C_mu solved by ncp::fc. The friction
// bound is implicit (this solve's lambda). S is factorized and W formed once; per solve
// only q, g_base and s_base change.
#pragma once

#include <Eigen/SparseCholesky>
#include <memory>

#include "contact/types.hpp"
#include "ncp/fc/solver.hpp"

namespace contact::internal {

class MortarFrictionSolve {
 public:
  /// S: n x n symmetric positive definite; B, T: m x n; mu: m coefficients >= 0.
  /// Throws std::invalid_argument on sizes that disagree or S not positive definite.
  MortarFrictionSolve(const SparseMatrix& S, const SparseMatrix& B, const SparseMatrix& T,
                      const Vector& mu);

  struct Outcome {
    Vector x, lambda, tau;  ///< in the units of S x + q (forces) and of x
    ncp::fc::Summary summary;
  };

  /// Solves from the previous call's forces. scale > 0: the displacement scale D
  /// [units of x]; the forces are scaled by F = D / max_i W_ii, and the solve is
  /// converged when the natural-map residual of (r / F, u / D) is <= tolerance.
  bool Solve(const Vector& q, const Vector& gap_base, const Vector& slip_base,
             double scale, double tolerance, Outcome* out);

 private:
  Eigen::SimplicialLDLT<SparseMatrix> factor_;
  Eigen::MatrixXd G_;  // S^-1 H'
  SparseMatrix H_;
  double w_max_ = 1.0;
  std::unique_ptr<ncp::fc::Solver> solver_;
  Vector r_;  // previous forces, scaled by 1 / F
};

}  // namespace contact::internal
