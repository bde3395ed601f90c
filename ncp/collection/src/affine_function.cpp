#include "ncp_collection/affine_function.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace ncp::collection {

AffineFunction::AffineFunction(SparseMatrix M, Vector q)
    : M_(std::move(M)), q_(std::move(q)) {
  if (M_.rows() != M_.cols() || M_.rows() != q_.size()) {
    throw std::invalid_argument("AffineFunction: M is " + std::to_string(M_.rows()) +
                                " x " + std::to_string(M_.cols()) + " but q has size " +
                                std::to_string(q_.size()) +
                                "; expected square M, size(q) = rows(M)");
  }
  M_.makeCompressed();
}

bool AffineFunction::Evaluate(const Vector& x, Vector* F) {
  F->noalias() = M_ * x;
  *F += q_;
  return true;
}

bool AffineFunction::Jacobian(const Vector& /*x*/, SparseMatrix* J) {
  *J = M_;
  return true;
}

}  // namespace ncp::collection
