#pragma once

#include <memory>

#include "ncp/types.hpp"

namespace ncp::internal {

/// Solves J d = rhs for a square sparse J in two phases: Analyze() does the symbolic
/// analysis (ordering, elimination tree) when told the pattern changed and reuses it
/// otherwise; Factorize() is the numeric factorization. Between the two the caller can
/// ask for the predicted cost of the factorization and decide not to start it.
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Symbolic analysis of J's pattern if pattern_changed or never done; false on failure.
  virtual bool Analyze(const SparseMatrix& J, bool pattern_changed) = 0;
  /// Floating-point operations the next Factorize() is predicted to take, from the
  /// symbolic analysis (UMFPACK: Info[UMFPACK_FLOPS_ESTIMATE], an upper bound; KLU:
  /// est_flops of its AMD analysis; dense LU: 2/3 n^3). NaN when the backend gives no
  /// prediction (Eigen::SparseLU, whose analysis happens inside the factorization).
  virtual double PredictedFactorizationFlops() const = 0;
  /// Rate [flop/s] that turns PredictedFactorizationFlops() into seconds before any
  /// factorization has been timed, measured on the development machine (2 shared cores,
  /// load ~8): NaN when there is no prediction.
  virtual double TypicalFlopRate() const = 0;
  /// Numeric factorization of J after Analyze(); false when singular or failed.
  virtual bool Factorize(const SparseMatrix& J) = 0;
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
