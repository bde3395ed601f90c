// A CHOLMOD Cholesky factor of a symmetric positive definite sparse matrix with solves
// that reuse their workspace (cholmod_solve2): after the first solve of a given size,
// Solve() allocates nothing - what the time loop of RunDynamics needs. (Eigen's
// CholmodDecomposition allocates the solution and workspace at every solve.)
#pragma once

#include <cholmod.h>

#include <Eigen/SparseCore>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "ncp/blas_threads.hpp"

namespace contact::internal {

/// One BLAS thread while alive (ncp::ScopedBlasThreads; OpenBLAS only). A solve with one
/// right-hand side calls BLAS on small supernodes, where OpenBLAS's threads cost more
/// than they give and spin against any other busy process: measured, 20 steps of the
/// sparse step on a 2700-dof slab (~120 solves per step) 9.9 s with OpenBLAS's 2 threads
/// next to another run, 0.55 s with one.
class SingleBlasThread : public ncp::ScopedBlasThreads {
 public:
  SingleBlasThread() : ncp::ScopedBlasThreads(1) {}
};

class CholmodFactor {
 public:
  /// Analyzes and factors A = L L' (simplicial below 2000 rows, else as CHOLMOD chooses).
  /// Only the lower triangle of A is read. ok() tells whether A was positive definite.
  explicit CholmodFactor(const Eigen::SparseMatrix<double>& A) : n_(A.rows()) {
    cholmod_start(&common_);
    // Small matrices: the simplicial factor, whose solves are plain loops; the supernodal
    // one calls BLAS per supernode, which costs more than it saves on small 3D meshes
    // (measured: the Table 1 run, 480 dofs, 42-47 ms supernodal vs 32-33 ms simplicial;
    // dt_crit at 5400 dofs 0.89 s simplicial vs 0.23 s supernodal).
    if (A.rows() < 2000) common_.supernodal = CHOLMOD_SIMPLICIAL;
    // LL', not CHOLMOD's default simplicial LDL': LDL' also factors symmetric indefinite
    // matrices, and ok() must tell that A is not positive definite.
    common_.final_ll = 1;
    common_.print = 0;  // failures are reported through ok(), not printed by CHOLMOD
    if (A.rows() != A.cols())
      throw std::invalid_argument("CholmodFactor: matrix is not square");
    cholmod_sparse view{};
    view.nrow = view.ncol = static_cast<size_t>(A.rows());
    view.nzmax = static_cast<size_t>(A.nonZeros());
    view.p = const_cast<int*>(A.outerIndexPtr());
    view.i = const_cast<int*>(A.innerIndexPtr());
    view.nz = const_cast<int*>(A.innerNonZeroPtr());
    view.x = const_cast<double*>(A.valuePtr());
    view.stype = -1;  // symmetric, lower triangle used
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = A.isCompressed() ? 1 : 0;
    factor_ = cholmod_analyze(&view, &common_);
    if (factor_) cholmod_factorize(&view, factor_, &common_);
    ok_ = factor_ && common_.status == CHOLMOD_OK && factor_->minor == factor_->n;
  }
  ~CholmodFactor() {
    cholmod_free_dense(&x_, &common_);
    cholmod_free_dense(&y_, &common_);
    cholmod_free_dense(&e_, &common_);
    cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  bool ok() const { return ok_; }
  /// Entries of the factor L (CHOLMOD's count after the analysis): a solve with one
  /// right-hand side takes about 4 of them flops (L and L' each once).
  double factor_nonzeros() const { return common_.lnz; }

  /// x = A^-1 b; x may not alias b. No allocation once x has size n (after the first
  /// call).
  void Solve(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    x->resize(n_);
    SolveColumns(b.data(), 1, x->data());
  }
  /// X = A^-1 B for k right-hand sides at once (BLAS-3 in the supernodal solves).
  void Solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) {
    X->resize(n_, B.cols());
    SolveColumns(B.data(), B.cols(), X->data());
  }

 private:
  // The n x k column-major b into the n x k column-major x.
  void SolveColumns(const double* b, Eigen::Index k, double* x) {
    if (!ok_) throw std::logic_error("CholmodFactor::Solve: the factorization failed");
    std::optional<SingleBlasThread> one_thread;
    if (k == 1) one_thread.emplace();
    cholmod_dense rhs{};
    rhs.nrow = rhs.d = static_cast<size_t>(n_);
    rhs.ncol = static_cast<size_t>(k);
    rhs.nzmax = static_cast<size_t>(n_ * k);
    rhs.x = const_cast<double*>(b);
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &x_, nullptr, &y_, &e_,
                        &common_))
      throw std::runtime_error("CholmodFactor::Solve: cholmod_solve2 failed");
    std::memcpy(x, x_->x, sizeof(double) * static_cast<size_t>(n_ * k));
  }

  Eigen::Index n_;
  cholmod_common common_{};
  cholmod_factor* factor_ = nullptr;
  cholmod_dense *x_ = nullptr, *y_ = nullptr, *e_ = nullptr;
  bool ok_ = false;
};

}  // namespace contact::internal
