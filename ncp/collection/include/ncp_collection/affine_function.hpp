/// \file affine_function.hpp
/// F(x) = M x + q with a sparse M: the function of a linear complementarity problem.
#pragma once

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp::collection {

/// F(x) = M x + q. The Jacobian is M, the same matrix (and pattern) at every x.
class AffineFunction : public SquareFunction {
 public:
  /// M must be square and q of matching size (throws std::invalid_argument otherwise).
  AffineFunction(SparseMatrix M, Vector q);

  int NumVariables() const override { return static_cast<int>(q_.size()); }
  bool Evaluate(const Vector& x, Vector* F) override;
  bool Jacobian(const Vector& x, SparseMatrix* J) override;
  bool IsAffine() const override { return true; }

  const SparseMatrix& M() const { return M_; }
  const Vector& q() const { return q_; }

 private:
  SparseMatrix M_;
  Vector q_;
};

}  // namespace ncp::collection
