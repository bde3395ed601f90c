#pragma once

#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <memory>
#include <vector>

#include "ncp/types.hpp"

namespace ncp::internal {

/// Dense LU of an n x n matrix, allocation-free once sized. Up to kFullPivotingLimit
/// unknowns with full pivoting (rank-revealing: singular when the numerical rank is below
/// n); above, with partial pivoting (blocked, an order of magnitude faster at n = 1000),
/// singular when a pivot of U is below n eps times the largest. The full-pivoting LU is
/// Eigen::FullPivLU's algorithm (same pivots, same operations, the same factors to the
/// bit) written for the small matrices it serves: Eigen's spends most of its time
/// outside the arithmetic there (an extra pass for the 1-norm, expression overhead per
/// step, permutation matrices).
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
  /// false when A is (numerically) singular. The full-pivoting factors live in storage
  /// that only grows: factorizing a matrix no larger than an earlier one allocates
  /// nothing, whatever the order of sizes (a reduced system whose size follows an active
  /// set). Partial pivoting (n > kFullPivotingLimit) reallocates when n changes.
  bool Factorize(const Eigen::Ref<const DenseMatrix>& A);
  /// Storage for matrices up to n x n (full pivoting: n <= kFullPivotingLimit), so that
  /// no later Factorize or Solve of such a matrix allocates.
  void Reserve(Eigen::Index n);
  /// x = A^-1 rhs with the last factorization (x resized to n).
  void Solve(const Vector& rhs, Vector* x);
  /// The same into x of n entries (nothing allocated within the storage's capacity).
  void Solve(const Eigen::Ref<const Vector>& rhs, Eigen::Ref<Vector> x);

 private:
  bool FactorizeFullPivoting(const Eigen::Ref<const DenseMatrix>& A);
  /// The full-pivoting factors: n_ x n_, column-major in the first n_^2 entries.
  Eigen::Map<DenseMatrix> Lu() { return {lu_storage_.data(), n_, n_}; }

  bool full_pivoting_ = true;
  Eigen::Index n_ = 0;
  // Full pivoting: P A Q = L U in Lu() (L unit lower), P and Q as the transpositions
  // applied at step k (rows k <-> row_swap_[k], columns k <-> column_swap_[k]).
  Vector lu_storage_;
  std::vector<Eigen::Index> row_swap_, column_swap_;
  Eigen::PartialPivLU<DenseMatrix> partial_;
  Vector permuted_;  // its first n entries; grown only
};

/// 2^-e for 2^e <= m < 2^(e+1): the scale of a row or column of max-norm m in
/// Equilibration (and in its distributed counterpart, ncp/petsc); 1 for m = 0 or not
/// finite (nothing to scale by).
inline double InversePowerOfTwo(double m) {
  if (!(m > 0.0) || !std::isfinite(m)) return 1.0;
  return std::ldexp(1.0, -std::ilogb(m));
}

/// Row and column scaling of a square matrix by powers of two (exact in floating point):
/// As = diag(r) A diag(c), r_i = 2^-e with 2^e <= max_j |a_ij| < 2^(e+1), then c_j the
/// same on the columns of diag(r) A (LAPACK's xGEEQU rounded to powers of two, as
/// xGEEQUB does). A x = b  <=>  As y = diag(r) b, x = diag(c) y: the solution is the
/// same, only the pivots (and the singularity test on them) see rows and columns of
/// one size. Zero rows and columns keep the scale 1. Allocation-free once sized.
class Equilibration {
 public:
  /// Applied when the largest row (or column) max-norm exceeds the smallest nonzero one
  /// by more than this factor: 2^20 ~ 1e6, far below 1 / (n eps) where a rank test
  /// relative to the largest pivot starts to call a well-posed system singular, and far
  /// above the spread of a Newton matrix whose rows are in consistent units.
  static constexpr double kSpreadThreshold = 1048576.0;
  /// Computes r and c for A; returns whether the spread exceeds kSpreadThreshold.
  bool Compute(const DenseMatrix& A);
  bool Compute(const SparseMatrix& A);
  /// *scaled = diag(r) A diag(c) (the A given to Compute).
  void Scale(const DenseMatrix& A, DenseMatrix* scaled) const;
  void Scale(const SparseMatrix& A, SparseMatrix* scaled) const;
  const Vector& row() const { return row_; }
  const Vector& column() const { return column_; }
  /// max/min of the nonzero row max-norms and column max-norms of the last Compute.
  double spread() const { return spread_; }

 private:
  bool Finish();  // r, c from the max-norms in row_, column_; sets spread_
  Vector row_, column_;
  double spread_ = 1.0;
};

/// Solution of a square J x = rhs that may be singular, from a rank-revealing
/// factorization of J equilibrated (Equilibration, always; the rank tolerance then
/// compares rows and columns of one size, and x is minimal in the scaled unknowns).
/// Dense: the minimum-norm least-squares solution of a complete orthogonal decomposition
/// (Eigen::CompleteOrthogonalDecomposition: column-pivoted Householder QR, then RZ).
/// Sparse: SuiteSparseQR (Davis 2011, rank-revealing multifrontal QR, MATLAB's tolerance
/// 20 (m + n) eps max_j ||J_j||_2) of J', which gives the minimum-norm solution of the
/// rank(J) rows it finds independent (the least-norm solution of J x = rhs when that
/// system is consistent; the caller checks). The sparse path copies J' (SPQR takes
/// 64-bit indices) and allocates inside SPQR: a fallback, not the rule.
class RankRevealingSolver {
 public:
  bool Solve(const DenseMatrix& J, const Vector& rhs, Vector* x);
  bool Solve(const SparseMatrix& J, const Vector& rhs, Vector* x);
  /// Numerical rank found by the last Solve.
  Eigen::Index rank() const { return rank_; }

 private:
  Equilibration equilibration_;
  Eigen::CompleteOrthogonalDecomposition<DenseMatrix> cod_;
  DenseMatrix scaled_dense_;
  SparseMatrix scaled_sparse_;
  Vector scaled_rhs_, y_;
  Eigen::Index rank_ = 0;
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
