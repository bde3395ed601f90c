#pragma once

#include <memory>

#include "ncp/types.hpp"

namespace ncp::internal {

/// Solves J d = rhs for a square sparse J. The symbolic analysis (ordering, elimination
/// tree) is done when Factorize() is told the pattern changed, and reused otherwise.
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Numeric factorization of J; false when singular or failed.
  virtual bool Factorize(const SparseMatrix& J, bool pattern_changed) = 0;
  /// x = J^-1 rhs with the last successful factorization; false on failure.
  virtual bool Solve(const Vector& rhs, Vector* x) = 0;
  virtual LinearSolverType type() const = 0;
  int symbolic_factorizations() const { return symbolic_factorizations_; }

 protected:
  int symbolic_factorizations_ = 0;
};

/// kAuto must be resolved by the caller.
std::unique_ptr<LinearSolver> MakeLinearSolver(LinearSolverType type);

}  // namespace ncp::internal
