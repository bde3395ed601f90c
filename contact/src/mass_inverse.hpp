// M^-1 for the time integrator: elementwise for a diagonal (lumped) mass, else one CHOLMOD
// factor - computed once per run and shared by the critical step, the prescribed start and
// the condensed step.
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

 private:
  Eigen::VectorXd diagonal_;
  std::unique_ptr<CholmodFactor> factor_;
};

}  // namespace contact::internal
