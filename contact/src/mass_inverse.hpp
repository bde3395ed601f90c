// M^-1 for the time integrator: elementwise for a diagonal (lumped) mass, else one
// CHOLMOD factor - computed once per run and shared by the critical step, the prescribed
// start and the condensed step.
#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <string>

#include "cholmod_factor.hpp"

namespace contact::internal {

/// True if every off-diagonal stored entry of A is zero.
bool IsDiagonal(const Eigen::SparseMatrix<double>& A);
/// max_ij |A_ij| over the stored entries (m_max of the step scaling S = M / m_max).
double MaxAbsEntry(const Eigen::SparseMatrix<double>& A);

class MassInverse {
 public:
  /// Throws std::invalid_argument starting with `who` if M is not positive definite.
  MassInverse(const Eigen::SparseMatrix<double>& M, const std::string& who);
  /// x = M^-1 b (no allocation once x is sized).
  void Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x);
  /// X = M^-1 B.
  void Solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X);

  /// M is diagonal (lumped): Solve divides by its diagonal.
  bool diagonal() const { return !factor_; }
  /// Entries of M's Cholesky factor L (the diagonal's size for a diagonal M): one solve
  /// costs about 4 factor_nonzeros() flops.
  double factor_nonzeros() const;
  /// Time [s] in, and number of, the solves with one right-hand side so far.
  double solve_seconds() const { return solve_seconds_; }
  long solves() const { return solves_; }

 private:
  Eigen::VectorXd diagonal_;
  std::unique_ptr<CholmodFactor> factor_;
  double solve_seconds_ = 0.0;
  long solves_ = 0;
};

}  // namespace contact::internal
