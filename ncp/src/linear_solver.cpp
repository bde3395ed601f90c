#include "linear_solver.hpp"

#include <Eigen/KLUSupport>
#include <Eigen/LU>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ncp::internal {

bool DenseLU::Factorize(const DenseMatrix& A) {
  full_pivoting_ = A.rows() <= kFullPivotingLimit;
  if (full_pivoting_) {
    full_.compute(A);
    return full_.isInvertible();
  }
  partial_.compute(A);
  // FullPivLU's test on the pivots of U: |u_ii| > n eps max_i |u_ii| (no allocation,
  // unlike PartialPivLU::rcond()).
  const auto pivots = partial_.matrixLU().diagonal().cwiseAbs();
  const double largest = pivots.maxCoeff();
  return std::isfinite(largest) && largest > 0.0 &&
         pivots.minCoeff() > static_cast<double>(A.rows()) * std::numeric_limits<double>::epsilon() * largest;
}

void DenseLU::Solve(const Vector& rhs, Vector* x) {
  // Full: P A Q = L U, x = Q U^-1 L^-1 P rhs. Partial: P A = L U, x = U^-1 L^-1 P rhs.
  const DenseMatrix& LU = full_pivoting_ ? full_.matrixLU() : partial_.matrixLU();
  permuted_.noalias() = (full_pivoting_ ? full_.permutationP() : partial_.permutationP()) * rhs;
  LU.triangularView<Eigen::UnitLower>().solveInPlace(permuted_);
  LU.triangularView<Eigen::Upper>().solveInPlace(permuted_);
  if (full_pivoting_) x->noalias() = full_.permutationQ() * permuted_;
  else *x = permuted_;
}

namespace {

/// DenseLU behind the sparse interface: the matrix is densified first.
class DenseLUSolver final : public LinearSolver {
 public:
  bool Analyze(const SparseMatrix& J, bool /*pattern_changed*/) override {
    rows_ = J.rows();
    return true;
  }
  double PredictedFactorizationFlops() const override { return DenseLU::PredictedFlops(rows_); }
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
/// uninitialized): read after a singular factorization it reported every later analysis as
/// failed, and a Solver kept across problems with SparseLU then never took a Newton step.
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

}  // namespace

std::unique_ptr<LinearSolver> MakeLinearSolver(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::kDenseLU:
      return std::make_unique<DenseLUSolver>();
    case LinearSolverType::kSparseLU:
      return std::make_unique<SparseSolver<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>,
                                           LinearSolverType::kSparseLU>>();
    case LinearSolverType::kUmfpack:
      return std::make_unique<
          SparseSolver<UmfPackLUWithInfo, LinearSolverType::kUmfpack>>();
    case LinearSolverType::kKlu:
      return std::make_unique<SparseSolver<KLUWithInfo, LinearSolverType::kKlu>>();
    case LinearSolverType::kAuto:
      break;
  }
  throw std::logic_error("MakeLinearSolver: kAuto must be resolved before construction");
}

}  // namespace ncp::internal
