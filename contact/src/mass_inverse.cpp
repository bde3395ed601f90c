#include "mass_inverse.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace contact::internal {

bool IsDiagonal(const Eigen::SparseMatrix<double>& A) {
  for (int col = 0; col < A.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it)
      if (it.row() != it.col() && it.value() != 0.0) return false;
  return true;
}

double MaxAbsEntry(const Eigen::SparseMatrix<double>& A) {
  double m = 0.0;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    m = std::max(m, std::abs(A.valuePtr()[k]));
  return m;
}

MassInverse::MassInverse(const Eigen::SparseMatrix<double>& M, const std::string& who)
    : diagonal_(M.diagonal()) {
  if (IsDiagonal(M)) {
    if (!(diagonal_.size() == 0 || diagonal_.minCoeff() > 0.0))
      throw std::invalid_argument(who + "the mass matrix is not positive definite");
    return;
  }
  factor_ = std::make_unique<CholmodFactor>(M);
  if (!factor_->ok())
    throw std::invalid_argument(
        who + "the mass matrix is not positive definite (Cholesky failed)");
}

void MassInverse::Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  const auto start = std::chrono::steady_clock::now();
  if (factor_)
    factor_->Solve(b, x);
  else
    *x = b.cwiseQuotient(diagonal_);
  solve_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++solves_;
}

double MassInverse::factor_nonzeros() const {
  return factor_ ? factor_->factor_nonzeros() : static_cast<double>(diagonal_.size());
}

void MassInverse::Solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) {
  if (factor_)
    factor_->Solve(B, X);
  else
    *X = diagonal_.cwiseInverse().asDiagonal() * B;
}

}  // namespace contact::internal
