#pragma once

#include <Eigen/LU>
#include <memory>

#include "ncp/types.hpp"

namespace ncp::internal {

/// Dense LU of an n x n matrix, allocation-free once sized. Up to kFullPivotingLimit
/// unknowns with full pivoting (rank-revealing: singular when the numerical rank is below
/// n); above, with partial pivoting (blocked, an order of magnitude faster at n = 1000),
/// singular when a pivot of U is below n eps times the largest.
class DenseLU {
 public:
  static constexpr Eigen::Index kFullPivotingLimit = 100;
  /// Eigen::PartialPivLU, n = 2000: 0.415 s for 5.3e9 flops.
  static constexpr double kTypicalFlopRate = 1.3e10;
  /// LU of an n x n matrix: 2/3 n^3 flops (Golub and Van Loan, 4th ed., sec. 3.2.5).
  static double PredictedFlops(Eigen::Index n) {
    const double r = static_cast<double>(n);
    return 2.0 / 3.0 * r * r * r;
  }
  /// false when A is (numerically) singular.
  bool Factorize(const DenseMatrix& A);
  /// x = A^-1 rhs with the last factorization.
  void Solve(const Vector& rhs, Vector* x);

 private:
  bool full_pivoting_ = true;
  Eigen::FullPivLU<DenseMatrix> full_;
  Eigen::PartialPivLU<DenseMatrix> partial_;
  Vector permuted_;
};

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
  /// kCholmod: factorizations handed to the LU fallback (J not symmetrizable or not
  /// positive definite); 0 for the other backends.
  int fallbacks() const { return fallbacks_; }

 protected:
  int symbolic_factorizations_ = 0;
  int fallbacks_ = 0;
};

/// kAuto must be resolved by the caller.
std::unique_ptr<LinearSolver> MakeLinearSolver(LinearSolverType type);

}  // namespace ncp::internal
