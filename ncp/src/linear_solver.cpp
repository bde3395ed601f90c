#include "linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/KLUSupport>
#include <Eigen/LU>
#include <Eigen/SPQRSupport>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace ncp::internal {

bool DenseLU::Factorize(const Eigen::Ref<const DenseMatrix>& A) {
  n_ = A.rows();
  full_pivoting_ = A.rows() <= kFullPivotingLimit;
  if (full_pivoting_) return FactorizeFullPivoting(A);
  partial_.compute(A);
  // FullPivLU's test on the pivots of U: |u_ii| > n eps max_i |u_ii| (no allocation,
  // unlike PartialPivLU::rcond()).
  const auto pivots = partial_.matrixLU().diagonal().cwiseAbs();
  const double largest = pivots.maxCoeff();
  return std::isfinite(largest) && largest > 0.0 &&
         pivots.minCoeff() > static_cast<double>(A.rows()) *
                                 std::numeric_limits<double>::epsilon() * largest;
}

// Eigen::FullPivLU::computeInPlace step by step: the pivot is the first entry of largest
// magnitude of the remaining corner in column-major order; rows and columns swapped; the
// column below divided by it; the corner updated by the outer product, column by column.
// Singular (Eigen's isInvertible) when fewer than n pivots exceed n eps max |pivot|, or
// when the corner becomes exactly zero. The search for the next pivot runs in the same
// pass as the update of the corner (one pass over it per step instead of two); it picks
// the pivot FullPivLU's separate search would: the first entry of largest magnitude, or
// the corner's first entry when that one is NaN (no entry compares greater than NaN).
bool DenseLU::FactorizeFullPivoting(const Eigen::Ref<const DenseMatrix>& A) {
  const Eigen::Index n = A.rows();
  if (lu_storage_.size() < n * n) lu_storage_.resize(n * n);
  Eigen::Map<DenseMatrix> lu = Lu();
  lu = A;
  row_swap_.resize(static_cast<size_t>(n));
  column_swap_.resize(static_cast<size_t>(n));
  double* const a = lu.data();  // column-major, leading dimension n
  auto at = [a, n](Eigen::Index r, Eigen::Index c) -> double& { return a[r + c * n]; };
  // The pivot of step 0: the whole matrix searched.
  Eigen::Index row = 0, column = 0;
  double biggest = n > 0 ? std::abs(at(0, 0)) : 0.0;
  for (Eigen::Index c = 0; c < n; ++c)
    for (Eigen::Index r = 0; r < n; ++r)
      if (std::abs(at(r, c)) > biggest) biggest = std::abs(at(r, c)), row = r, column = c;
  double largest_pivot = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (biggest == 0.0) return false;  // rank k < n
    largest_pivot = std::max(largest_pivot, biggest);
    row_swap_[static_cast<size_t>(k)] = row;
    column_swap_[static_cast<size_t>(k)] = column;
    if (row != k)
      for (Eigen::Index c = 0; c < n; ++c) std::swap(at(k, c), at(row, c));
    if (column != k)
      for (Eigen::Index r = 0; r < n; ++r) std::swap(at(r, k), at(r, column));
    const double pivot = at(k, k);
    double* const below = a + k * n;  // column k
    for (Eigen::Index r = k + 1; r < n; ++r) below[r] /= pivot;
    // The corner k+1.. updated column by column; the next pivot found on the way.
    row = column = k + 1;
    biggest = 0.0;
    for (Eigen::Index c = k + 1; c < n; ++c) {
      double* const col = a + c * n;
      const double u = col[k];
      for (Eigen::Index r = k + 1; r < n; ++r) {
        col[r] -= u * below[r];
        if (std::abs(col[r]) > biggest) biggest = std::abs(col[r]), row = r, column = c;
      }
    }
    if (k + 1 < n && std::isnan(at(k + 1, k + 1))) {
      row = column = k + 1;
      biggest = std::abs(at(k + 1, k + 1));
    }
  }
  const double threshold =
      largest_pivot * std::numeric_limits<double>::epsilon() * static_cast<double>(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(std::abs(at(i, i)) > threshold)) return false;
  return true;
}

void DenseLU::Reserve(Eigen::Index n) {
  if (permuted_.size() < n) permuted_.resize(n);
  if (n > kFullPivotingLimit) return;
  if (lu_storage_.size() < n * n) lu_storage_.resize(n * n);
  row_swap_.reserve(static_cast<size_t>(n));
  column_swap_.reserve(static_cast<size_t>(n));
}

void DenseLU::Solve(const Vector& rhs, Vector* x) {
  x->resize(n_);
  Solve(rhs, Eigen::Ref<Vector>(*x));
}

void DenseLU::Solve(const Eigen::Ref<const Vector>& rhs, Eigen::Ref<Vector> x) {
  const Eigen::Index n = n_;
  if (permuted_.size() < n) permuted_.resize(n);
  auto permuted = permuted_.head(n);
  if (!full_pivoting_) {  // P A = L U: x = U^-1 L^-1 P rhs
    permuted.noalias() = partial_.permutationP() * rhs;
    partial_.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(permuted);
    partial_.matrixLU().triangularView<Eigen::Upper>().solveInPlace(permuted);
    x = permuted;
    return;
  }
  // P A Q = L U: x = Q U^-1 L^-1 P rhs, P and Q applied as their transpositions.
  const Eigen::Map<DenseMatrix> lu = Lu();
  permuted = rhs;
  for (Eigen::Index k = 0; k < n; ++k)
    std::swap(permuted(k), permuted(row_swap_[static_cast<size_t>(k)]));
  lu.triangularView<Eigen::UnitLower>().solveInPlace(permuted);
  lu.triangularView<Eigen::Upper>().solveInPlace(permuted);
  for (Eigen::Index k = n - 1; k >= 0; --k)
    std::swap(permuted(k), permuted(column_swap_[static_cast<size_t>(k)]));
  x = permuted;
}

namespace {

// max/min over the entries of `norms` that are > 0 (1 when there are none).
double Spread(const Vector& norms) {
  double largest = 0.0, smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < norms.size(); ++i) {
    if (!(norms(i) > 0.0)) continue;
    largest = std::max(largest, norms(i));
    smallest = std::min(smallest, norms(i));
  }
  return largest > 0.0 ? largest / smallest : 1.0;
}

}  // namespace

// Two passes over A: row max-norms, then the column max-norms of diag(r) A.
bool Equilibration::Compute(const DenseMatrix& A) {
  row_.setZero(A.rows());
  column_.setZero(A.cols());
  for (Eigen::Index c = 0; c < A.cols(); ++c)
    for (Eigen::Index r = 0; r < A.rows(); ++r)
      row_(r) = std::max(row_(r), std::abs(A(r, c)));
  spread_ = Spread(row_);
  for (Eigen::Index r = 0; r < A.rows(); ++r) row_(r) = InversePowerOfTwo(row_(r));
  for (Eigen::Index c = 0; c < A.cols(); ++c)
    for (Eigen::Index r = 0; r < A.rows(); ++r)
      column_(c) = std::max(column_(c), row_(r) * std::abs(A(r, c)));
  return Finish();
}

bool Equilibration::Compute(const SparseMatrix& A) {
  row_.setZero(A.rows());
  column_.setZero(A.cols());
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it)
      row_(it.row()) = std::max(row_(it.row()), std::abs(it.value()));
  spread_ = Spread(row_);
  for (Eigen::Index r = 0; r < A.rows(); ++r) row_(r) = InversePowerOfTwo(row_(r));
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it)
      column_(c) = std::max(column_(c), row_(it.row()) * std::abs(it.value()));
  return Finish();
}

bool Equilibration::Finish() {
  spread_ = std::max(spread_, Spread(column_));
  for (Eigen::Index c = 0; c < column_.size(); ++c)
    column_(c) = InversePowerOfTwo(column_(c));
  return spread_ > kSpreadThreshold;
}

void Equilibration::Scale(const DenseMatrix& A, DenseMatrix* scaled) const {
  scaled->resize(A.rows(), A.cols());
  for (Eigen::Index c = 0; c < A.cols(); ++c)
    scaled->col(c) = column_(c) * row_.cwiseProduct(A.col(c));
}

void Equilibration::Scale(const SparseMatrix& A, SparseMatrix* scaled) const {
  *scaled = A;
  for (Eigen::Index c = 0; c < scaled->outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(*scaled, c); it; ++it)
      it.valueRef() *= row_(it.row()) * column_(c);
}

bool RankRevealingSolver::Solve(const DenseMatrix& J, const Vector& rhs, Vector* x) {
  equilibration_.Compute(J);
  equilibration_.Scale(J, &scaled_dense_);
  cod_.compute(scaled_dense_);
  rank_ = cod_.rank();
  scaled_rhs_ = equilibration_.row().cwiseProduct(rhs);
  y_ = cod_.solve(scaled_rhs_);
  *x = equilibration_.column().cwiseProduct(y_);
  return x->allFinite();
}

// Minimum norm through the QR of J' (SuiteSparseQR): J' P = Q R with rank r and R11 =
// R(1:r, 1:r), so rows E_i = P e_i of J satisfy J_{E_i} = (R' Q')_i. d = Q [z; 0] with
// R11' z = rhs_{E_1..E_r} solves the r independent rows with the least norm (d lies in
// range(J')); the other rows hold when the system is consistent (the caller checks).
bool RankRevealingSolver::Solve(const SparseMatrix& J, const Vector& rhs, Vector* x) {
  using LongMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  equilibration_.Compute(J);
  equilibration_.Scale(J, &scaled_sparse_);
  const LongMatrix transposed(scaled_sparse_.transpose());
  Eigen::SPQR<LongMatrix> qr;
  qr.compute(transposed);
  if (qr.info() != Eigen::Success) return false;
  rank_ = qr.rank();
  const auto permutation = qr.colsPermutation();
  scaled_rhs_ = equilibration_.row().cwiseProduct(rhs);
  Vector z(J.rows());
  for (Eigen::Index i = 0; i < rank_; ++i) z(i) = scaled_rhs_(permutation.indices()(i));
  const LongMatrix R = qr.matrixR();
  z.head(rank_) = R.topLeftCorner(rank_, rank_)
                      .transpose()
                      .triangularView<Eigen::Lower>()
                      .solve(z.head(rank_));
  z.tail(J.rows() - rank_).setZero();
  y_ = qr.matrixQ() * z;
  *x = equilibration_.column().cwiseProduct(y_);
  return x->allFinite();
}

namespace {

/// DenseLU behind the sparse interface: the matrix is densified first.
class DenseLUSolver final : public LinearSolver {
 public:
  bool Analyze(const SparseMatrix& J, bool /*pattern_changed*/) override {
    rows_ = J.rows();
    return true;
  }
  double PredictedFactorizationFlops() const override {
    return DenseLU::PredictedFlops(rows_);
  }
  double TypicalFlopRate() const override { return DenseLU::kTypicalFlopRate; }
  bool Factorize(const SparseMatrix& J) override {
    dense_ = J;
    return lu_.Factorize(dense_);
  }
  bool Solve(const Vector& rhs, Vector* x) override {
    lu_.Solve(rhs, x);
    return true;
  }
  LinearSolverType type() const override { return LinearSolverType::kDenseLU; }

 private:
  DenseMatrix dense_;
  Eigen::Index rows_ = 0;
  DenseLU lu_;
};

/// Eigen::UmfPackLU with the flop estimate of UMFPACK's symbolic analysis exposed
/// (UMFPACK user guide, Info[UMFPACK_FLOPS_ESTIMATE]: an upper bound on the flops of the
/// numeric factorization).
class UmfPackLUWithInfo : public Eigen::UmfPackLU<SparseMatrix> {
 public:
  double FlopsEstimate() const { return m_umfpackInfo(UMFPACK_FLOPS_ESTIMATE); }
};

/// Eigen::KLU with the flop estimate of KLU's symbolic analysis exposed (klu.h:
/// klu_symbolic::est_flops, computed when the AMD ordering is used, KLU's default).
class KLUWithInfo : public Eigen::KLU<SparseMatrix> {
 public:
  double FlopsEstimate() const {
    if (m_symbolic == nullptr || m_symbolic->ordering != 0 || m_symbolic->est_flops < 0)
      return std::numeric_limits<double>::quiet_NaN();
    return m_symbolic->est_flops;
  }
};

template <typename Decomposition>
double FlopsEstimate(const Decomposition&) {
  return std::numeric_limits<double>::quiet_NaN();
}
/// Estimated flops per second of wall time, random sparse P-LCP (RandomPLcp):
/// UMFPACK n = 10^4, 1.46e11 estimated flops in 3.06 s (its estimate is an upper bound);
/// KLU n = 4000, 4.29e9 in 1.91 s.
template <typename Decomposition>
double TypicalRate(const Decomposition&) {
  return std::numeric_limits<double>::quiet_NaN();
}
double TypicalRate(const UmfPackLUWithInfo&) { return 4.8e10; }
double TypicalRate(const KLUWithInfo&) { return 2.2e9; }
double FlopsEstimate(const UmfPackLUWithInfo& lu) { return lu.FlopsEstimate(); }
double FlopsEstimate(const KLUWithInfo& lu) { return lu.FlopsEstimate(); }

/// Whether analyzePattern succeeded. Eigen::SparseLU's analyzePattern has no failure mode
/// and does not set info(), which still holds the last factorization's result (or is
/// uninitialized): read after a singular factorization it reported every later analysis
/// as failed, and a Solver kept across problems with SparseLU then never took a Newton
/// step.
template <typename Decomposition>
bool AnalysisSucceeded(const Decomposition& lu) {
  return lu.info() == Eigen::Success;
}
bool AnalysisSucceeded(const Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>&) {
  return true;
}

/// Any Eigen sparse LU with analyzePattern / factorize / solve / info.
template <typename Decomposition, LinearSolverType kType>
class SparseSolver final : public LinearSolver {
 public:
  // A new pattern gets a new decomposition object, so that nothing of the previous
  // matrix's factorization survives into the new one.
  bool Analyze(const SparseMatrix& J, bool pattern_changed) override {
    if (pattern_changed || !analyzed_) {
      lu_ = std::make_unique<Decomposition>();
      lu_->analyzePattern(J);
      ++symbolic_factorizations_;
      analyzed_ = AnalysisSucceeded(*lu_);
    }
    return analyzed_;
  }
  double PredictedFactorizationFlops() const override { return FlopsEstimate(*lu_); }
  double TypicalFlopRate() const override { return TypicalRate(*lu_); }
  bool Factorize(const SparseMatrix& J) override {
    lu_->factorize(J);
    return lu_->info() == Eigen::Success;
  }
  bool Solve(const Vector& rhs, Vector* x) override {
    *x = lu_->solve(rhs);
    return lu_->info() == Eigen::Success;
  }
  LinearSolverType type() const override { return kType; }

 private:
  std::unique_ptr<Decomposition> lu_;  // made by Analyze
  bool analyzed_ = false;
};

using UmfpackSolver = SparseSolver<UmfPackLUWithInfo, LinearSolverType::kUmfpack>;

/// LinearSolverType::kCholmod. J d = rhs is reduced to a symmetric positive definite
/// system:
///  1. a row whose off-diagonal entries sum to at most eps |J_ii| fixes its variable,
///     d_i = rhs_i / J_ii (set F; e.g. a pair with dphi/db = 0; the dropped entries are a
///     perturbation at round-off level);
///  2. the other rows R get scales s_i of one sign per connected component of the graph
///  of
///     J_RR with s_i J_ij = s_j J_ji, propagated from s_i = 1 / J_ii at the component's
///     first node (J = Da + Db F' with F' symmetric gives s_i proportional to 1 / db_i,
///     and S J = diag(da / db) + F'; the thesis's FB has da, db <= 0);
///  3. K = S J_RR, with identity rows and columns for F kept in J's pattern so that one
///     symbolic analysis serves every iterate, is factored K = L L' by CHOLMOD (it reads
///     the lower triangle) and K d_R = S (rhs_R - J_RF d_F) solved.
/// When no consistent scaling exists (a one-sided entry, a sign change, or a mismatch
/// above kSymmetryTolerance relative) or K is not positive definite, J is factored by
/// UMFPACK instead and the fallback counted (after K was found indefinite, for the rest
/// of this pattern).
class SymmetrizedCholesky final : public LinearSolver {
 public:
  /// Relative mismatch of s_i J_ij and s_j J_ji accepted as round-off: the scales are
  /// products along paths of the graph (2D grid of 10^6 nodes: ~2000 factors, ~1e-13).
  static constexpr double kSymmetryTolerance = 1e-10;
  /// Common->fl (CHOLMOD's LL' flop count) per second, 2D 5-point Laplacian on the
  /// development machine: 1.82e10 flops in 1.9-2.1 s at 10^6 nodes (~9e9 flop/s), 4.7e8
  /// in 0.14-0.17 s at 9e4 (~3e9); between the two, so that small factorizations are not
  /// predicted far too short.
  static constexpr double kTypicalFlopRate = 5.0e9;

  bool Analyze(const SparseMatrix& J, bool pattern_changed) override {
    if (analyzed_ && !pattern_changed) return analysis_ok_;
    analyzed_ = true;
    indefinite_ = false;
    ++symbolic_factorizations_;
    fallback_.reset();
    symmetric_pattern_ = StoreMirrorPattern(J);
    if (!symmetric_pattern_) {
      analysis_ok_ = Fallback().Analyze(J, true);
      return analysis_ok_;
    }
    K_ = J;  // the pattern; values are written by Symmetrize
    cholesky_ =
        std::make_unique<Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>>();
    // Supernodal or simplicial as CHOLMOD's analysis finds cheaper (simplicial on a
    // band), always L L' so that a matrix that is not positive definite fails; no
    // messages: "not positive definite" is an answer here, not an error.
    cholmod_common& common = cholesky_->cholmod();
    common.supernodal = CHOLMOD_AUTO;
    common.final_asis = 0;
    common.final_ll = 1;
    common.print = 0;
    cholesky_->analyzePattern(K_);
    analysis_ok_ = cholesky_->cholmod().status >= CHOLMOD_OK;
    return analysis_ok_;
  }
  // The prediction is the Cholesky's while it is tried, the LU's once the pattern went to
  // it.
  double PredictedFactorizationFlops() const override {
    return TriesCholesky() ? cholesky_->cholmod().fl
                           : fallback_->PredictedFactorizationFlops();
  }
  double TypicalFlopRate() const override {
    return TriesCholesky() ? kTypicalFlopRate : fallback_->TypicalFlopRate();
  }
  bool Factorize(const SparseMatrix& J) override {
    use_fallback_ = !TriesCholesky() || !Symmetrize(J);
    if (!use_fallback_) {
      cholesky_->factorize(K_);
      // Not positive definite: LU from here on while the pattern stays, so that a problem
      // with a symmetric indefinite F' does not pay a failed Cholesky at every iteration.
      indefinite_ = use_fallback_ = cholesky_->info() != Eigen::Success;
    }
    if (!use_fallback_) return true;
    ++fallbacks_;
    if (symmetric_pattern_ && !fallback_) {
      ++symbolic_factorizations_;
      if (!Fallback().Analyze(J, true)) return false;
    }
    return fallback_->Factorize(J);
  }
  bool Solve(const Vector& rhs, Vector* x) override {
    if (use_fallback_) return fallback_->Solve(rhs, x);
    // d_F = rhs_F / J_FF, then rhs_R - J_RF d_F scaled by S; the rows of F in K are e_i'.
    reduced_rhs_ = rhs;
    for (Eigen::Index i = 0; i < rhs.size(); ++i)
      if (fixed_[static_cast<size_t>(i)]) reduced_rhs_(i) = rhs(i) / diagonal_(i);
    const int* outer = K_.outerIndexPtr();
    const int* inner = K_.innerIndexPtr();
    for (Eigen::Index c = 0; c < rhs.size(); ++c) {
      if (!fixed_[static_cast<size_t>(c)]) continue;
      for (int q = outer[c]; q < outer[c + 1]; ++q)
        if (!fixed_[static_cast<size_t>(inner[q])])
          reduced_rhs_(inner[q]) -= values_(q) * reduced_rhs_(c);
    }
    for (Eigen::Index i = 0; i < rhs.size(); ++i)
      if (!fixed_[static_cast<size_t>(i)]) reduced_rhs_(i) *= scale_(i);
    *x = cholesky_->solve(reduced_rhs_);
    if (cholesky_->info() != Eigen::Success) return false;
    for (Eigen::Index i = 0; i < rhs.size(); ++i)
      if (fixed_[static_cast<size_t>(i)]) (*x)(i) = reduced_rhs_(i);
    return true;
  }
  LinearSolverType type() const override { return LinearSolverType::kCholmod; }

 private:
  // The pattern is symmetric and no K of it was found indefinite (then the LU is
  // analysed).
  bool TriesCholesky() const { return symmetric_pattern_ && !indefinite_; }

  LinearSolver& Fallback() {
    if (!fallback_) fallback_ = std::make_unique<UmfpackSolver>();
    return *fallback_;
  }

  /// For every stored entry (r, c) of J the position of (c, r), and the diagonal's; false
  /// when the pattern is not symmetric or a diagonal entry is missing.
  bool StoreMirrorPattern(const SparseMatrix& J) {
    const int n = static_cast<int>(J.cols());
    const int* outer = J.outerIndexPtr();
    const int* inner = J.innerIndexPtr();
    mirror_.assign(static_cast<size_t>(J.nonZeros()), -1);
    diagonal_position_.assign(static_cast<size_t>(n), -1);
    for (int c = 0; c < n; ++c) {
      for (int q = outer[c]; q < outer[c + 1]; ++q) {
        const int r = inner[q];
        const int* begin = inner + outer[r];
        const int* end = inner + outer[r + 1];
        const int* found = std::lower_bound(begin, end, c);
        if (found == end || *found != c) return false;
        mirror_[static_cast<size_t>(q)] = outer[r] + static_cast<int>(found - begin);
        if (r == c) diagonal_position_[static_cast<size_t>(c)] = q;
      }
      if (diagonal_position_[static_cast<size_t>(c)] < 0) return false;
    }
    return true;
  }

  /// Steps 1-2 of the class comment and K's values; false when J has no symmetrizing
  /// scaling.
  bool Symmetrize(const SparseMatrix& J) {
    const int n = static_cast<int>(J.cols());
    const int* outer = J.outerIndexPtr();
    const int* inner = J.innerIndexPtr();
    values_ = Eigen::Map<const Vector>(J.valuePtr(), J.nonZeros());
    off_diagonal_.setZero(n);
    for (int c = 0; c < n; ++c)
      for (int q = outer[c]; q < outer[c + 1]; ++q)
        if (inner[q] != c) off_diagonal_(inner[q]) += std::abs(values_(q));
    diagonal_.resize(n);
    fixed_.assign(static_cast<size_t>(n), false);
    for (int i = 0; i < n; ++i) {
      diagonal_(i) = values_(diagonal_position_[static_cast<size_t>(i)]);
      fixed_[static_cast<size_t>(i)] =
          diagonal_(i) != 0.0 &&
          off_diagonal_(i) <=
              std::numeric_limits<double>::epsilon() * std::abs(diagonal_(i));
    }
    if (!PropagateScales(J)) return false;
    double* k = K_.valuePtr();
    for (int c = 0; c < n; ++c)
      for (int q = outer[c]; q < outer[c + 1]; ++q) {
        const int r = inner[q];
        const bool identity_part =
            fixed_[static_cast<size_t>(r)] || fixed_[static_cast<size_t>(c)];
        k[q] = identity_part ? (r == c ? 1.0 : 0.0) : scale_(r) * values_(q);
      }
    return true;
  }

  /// s over the graph of J_RR, breadth first: s_r = s_c J_cr / J_rc along each entry.
  bool PropagateScales(const SparseMatrix& J) {
    const int n = static_cast<int>(J.cols());
    const int* outer = J.outerIndexPtr();
    const int* inner = J.innerIndexPtr();
    scale_.setZero(n);
    queue_.clear();
    for (int root = 0; root < n; ++root) {
      if (fixed_[static_cast<size_t>(root)] || scale_(root) != 0.0) continue;
      if (diagonal_(root) == 0.0) return false;
      scale_(root) =
          1.0 / diagonal_(root);  // K_rr = 1: FB's J = Da + Db F' has da, db <= 0
      queue_.push_back(root);
      for (size_t head = queue_.size() - 1; head < queue_.size(); ++head) {
        const int c = queue_[head];
        for (int q = outer[c]; q < outer[c + 1]; ++q) {
          const int r = inner[q];
          if (r == c || fixed_[static_cast<size_t>(r)]) continue;
          const double j_rc = values_(q), j_cr = values_(mirror_[static_cast<size_t>(q)]);
          if (j_rc == 0.0 && j_cr == 0.0) continue;
          const double s = scale_(c) * j_cr / j_rc;  // s_r J_rc = s_c J_cr
          if (!(s * scale_(c) > 0.0) || !std::isfinite(s))
            return false;  // one sign per component
          if (scale_(r) == 0.0) {
            scale_(r) = s;
            queue_.push_back(r);
          } else if (std::abs(scale_(r) - s) > kSymmetryTolerance * std::abs(scale_(r))) {
            return false;
          }
        }
      }
    }
    return true;
  }

  std::unique_ptr<Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>> cholesky_;
  std::unique_ptr<LinearSolver> fallback_;  // UMFPACK, made on first need
  bool analyzed_ = false, analysis_ok_ = false, symmetric_pattern_ = false,
       use_fallback_ = false, indefinite_ = false;
  SparseMatrix K_;  // S J with identity rows/columns for F, J's pattern
  std::vector<int> mirror_, diagonal_position_, queue_;
  std::vector<bool> fixed_;
  Vector values_, off_diagonal_, diagonal_, scale_, reduced_rhs_;
};

}  // namespace

std::unique_ptr<LinearSolver> MakeLinearSolver(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::kDenseLU:
      return std::make_unique<DenseLUSolver>();
    case LinearSolverType::kSparseLU:
      return std::make_unique<
          SparseSolver<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>,
                       LinearSolverType::kSparseLU>>();
    case LinearSolverType::kUmfpack:
      return std::make_unique<UmfpackSolver>();
    case LinearSolverType::kCholmod:
      return std::make_unique<SymmetrizedCholesky>();
    case LinearSolverType::kKlu:
      return std::make_unique<SparseSolver<KLUWithInfo, LinearSolverType::kKlu>>();
    case LinearSolverType::kAuto:
      break;
  }
  throw std::logic_error("MakeLinearSolver: kAuto must be resolved before construction");
}

}  // namespace ncp::internal
