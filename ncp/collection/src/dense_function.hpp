// Internal: base class for the small problems, whose Jacobians are dense.
#pragma once

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp::collection::internal {

/// A SquareFunction whose Jacobian is computed densely and handed out with all n^2
/// entries stored (explicit zeros included), so the sparsity pattern never changes.
class DenseJacobianFunction : public SquareFunction {
 public:
  explicit DenseJacobianFunction(int n) : n_(n), dense_(n, n) {}
  int NumVariables() const override { return n_; }

  bool Jacobian(const Vector& x, SparseMatrix* J) override {
    dense_.setZero();
    if (!DenseJacobian(x, &dense_)) return false;
    if (J->rows() != n_ || J->cols() != n_ || !J->isCompressed() ||
        J->nonZeros() != n_ * n_) {
      J->resize(n_, n_);
      J->reserve(Eigen::VectorXi::Constant(n_, n_));
      for (int j = 0; j < n_; ++j)
        for (int i = 0; i < n_; ++i) J->insert(i, j) = 0.0;
      J->makeCompressed();
    }
    // Column-major storage with every entry present: value k is (k % n, k / n).
    double* values = J->valuePtr();
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) values[i + n_ * j] = dense_(i, j);
    return true;
  }

 protected:
  /// dF/dx into *J (n x n, zeroed on entry).
  virtual bool DenseJacobian(const Vector& x, DenseMatrix* J) = 0;

 private:
  int n_;
  DenseMatrix dense_;
};

}  // namespace ncp::collection::internal
