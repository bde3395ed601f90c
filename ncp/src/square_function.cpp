#include "ncp/square_function.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace ncp {

DenseSquareFunction::DenseSquareFunction(int n, ResidualFn residual, JacobianFn jacobian)
    : n_(n), residual_(std::move(residual)), jacobian_(std::move(jacobian)) {
  if (n < 0)
    throw std::invalid_argument("DenseSquareFunction: n must be >= 0, got " +
                                std::to_string(n));
  if (!residual_ || !jacobian_)
    throw std::invalid_argument(
        "DenseSquareFunction: residual and jacobian must be callable");
}

bool DenseSquareFunction::Jacobian(const Vector& x, SparseMatrix* J) {
  dense_.setZero(n_, n_);
  if (!jacobian_(x, &dense_)) return false;
  if (dense_.rows() != n_ || dense_.cols() != n_)
    throw std::invalid_argument("DenseSquareFunction: jacobian returned " +
                                std::to_string(dense_.rows()) + " x " +
                                std::to_string(dense_.cols()) + ", expected " +
                                std::to_string(n_) + " x " + std::to_string(n_));
  // Full pattern (explicit zeros kept) so the symbolic analysis is done once.
  if (J->rows() != n_ || J->cols() != n_ ||
      J->nonZeros() != static_cast<Eigen::Index>(n_) * n_) {
    std::vector<Eigen::Triplet<double, int>> t;
    t.reserve(static_cast<size_t>(n_) * static_cast<size_t>(n_));
    for (int c = 0; c < n_; ++c)
      for (int r = 0; r < n_; ++r) t.emplace_back(r, c, 1.0);
    J->resize(n_, n_);
    J->setFromTriplets(t.begin(), t.end());
    J->makeCompressed();
  }
  // Column-major full pattern: value k is entry (k % n, k / n), same as the dense
  // storage.
  std::copy(dense_.data(), dense_.data() + static_cast<Eigen::Index>(n_) * n_,
            J->valuePtr());
  return true;
}

}  // namespace ncp
