#include "linear_solver.hpp"

#include <Eigen/KLUSupport>
#include <Eigen/LU>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>
#include <stdexcept>

namespace ncp::internal {
namespace {

/// Rank-revealing dense LU; singular when the numerical rank is below n. Allocates only
/// when n changes.
class DenseLUSolver final : public LinearSolver {
 public:
  bool Factorize(const SparseMatrix& J, bool /*pattern_changed*/) override {
    dense_ = J;
    lu_.compute(dense_);
    return lu_.isInvertible();
  }
  /// P J Q = L U, so x = Q U^-1 L^-1 P rhs: the steps of FullPivLU::solve for an
  /// invertible J, in the preallocated permuted_ instead of a temporary.
  bool Solve(const Vector& rhs, Vector* x) override {
    permuted_.noalias() = lu_.permutationP() * rhs;
    lu_.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(permuted_);
    lu_.matrixLU().triangularView<Eigen::Upper>().solveInPlace(permuted_);
    x->noalias() = lu_.permutationQ() * permuted_;
    return true;
  }
  LinearSolverType type() const override { return LinearSolverType::kDenseLU; }

 private:
  DenseMatrix dense_;
  Eigen::FullPivLU<DenseMatrix> lu_;
  Vector permuted_;
};

/// Any Eigen sparse LU with analyzePattern / factorize / solve / info.
template <typename Decomposition, LinearSolverType kType>
class SparseSolver final : public LinearSolver {
 public:
  bool Factorize(const SparseMatrix& J, bool pattern_changed) override {
    if (pattern_changed || !analyzed_) {
      lu_.analyzePattern(J);
      ++symbolic_factorizations_;
      analyzed_ = lu_.info() == Eigen::Success;
      if (!analyzed_) return false;
    }
    lu_.factorize(J);
    return lu_.info() == Eigen::Success;
  }
  bool Solve(const Vector& rhs, Vector* x) override {
    *x = lu_.solve(rhs);
    return lu_.info() == Eigen::Success;
  }
  LinearSolverType type() const override { return kType; }

 private:
  Decomposition lu_;
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
          SparseSolver<Eigen::UmfPackLU<SparseMatrix>, LinearSolverType::kUmfpack>>();
    case LinearSolverType::kKlu:
      return std::make_unique<SparseSolver<Eigen::KLU<SparseMatrix>, LinearSolverType::kKlu>>();
    case LinearSolverType::kAuto:
      break;
  }
  throw std::logic_error("MakeLinearSolver: kAuto must be resolved before construction");
}

}  // namespace ncp::internal
