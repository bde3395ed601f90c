#include "rank_revealing.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "linear_solver.hpp"
#include "ncp/types.hpp"
#include "petsc_support.hpp"

namespace ncp::petsc {
namespace {

MPI_Comm CommOf(Mat A) {
  MPI_Comm comm = MPI_COMM_NULL;
  NCP_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  return comm;
}

// max / min over the entries > 0 of v (its max-norms), reduced over the communicator: the
// serial Spread; 1 when there are none.
double Spread(MPI_Comm comm, Vec v) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  const PetscScalar* a = nullptr;
  NCP_PETSC_CHECK(VecGetArrayRead(v, &a));
  double local[2] = {0.0, -std::numeric_limits<double>::infinity()};  // max, -min
  for (PetscInt i = 0; i < n; ++i) {
    const double m = PetscRealPart(a[i]);
    if (!(m > 0.0)) continue;
    local[0] = std::max(local[0], m);
    local[1] = std::max(local[1], -m);
  }
  NCP_PETSC_CHECK(VecRestoreArrayRead(v, &a));
  double global[2] = {0.0, 0.0};
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, comm);
  return global[0] > 0.0 ? global[0] / -global[1] : 1.0;
}

// v_i <- InversePowerOfTwo(v_i), inverse_i <- 1 / v_i (a power of two: exact).
void ToScales(Vec v, Vec inverse) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  PetscScalar *a = nullptr, *b = nullptr;
  NCP_PETSC_CHECK(VecGetArray(v, &a));
  NCP_PETSC_CHECK(VecGetArray(inverse, &b));
  for (PetscInt i = 0; i < n; ++i) {
    a[i] = internal::InversePowerOfTwo(PetscRealPart(a[i]));
    b[i] = 1.0 / PetscRealPart(a[i]);
  }
  NCP_PETSC_CHECK(VecRestoreArray(inverse, &b));
  NCP_PETSC_CHECK(VecRestoreArray(v, &a));
}

void DestroyVecs(std::vector<Vec>* vecs) {
  for (Vec& v : *vecs) VecDestroy(&v);
  vecs->clear();
}

}  // namespace

DistributedEquilibration::~DistributedEquilibration() {
  for (Vec* v : {&row_, &column_, &inverse_row_, &inverse_column_})
    if (*v) VecDestroy(v);
}

// Row max-norms by MatGetRowMaxAbs; the column max-norms of diag(r) A as the row
// max-norms of A' diag(r) (MatTranspose: the columns of a distributed AIJ matrix are
// spread over the ranks).
bool DistributedEquilibration::Compute(Mat A) {
  const MPI_Comm comm = CommOf(A);
  for (Vec* v : {&row_, &column_, &inverse_row_, &inverse_column_})
    if (*v) VecDestroy(v);
  NCP_PETSC_CHECK(MatCreateVecs(A, &column_, &row_));
  NCP_PETSC_CHECK(VecDuplicate(row_, &inverse_row_));
  NCP_PETSC_CHECK(VecDuplicate(column_, &inverse_column_));
  NCP_PETSC_CHECK(MatGetRowMaxAbs(A, row_, nullptr));
  spread_ = Spread(comm, row_);
  ToScales(row_, inverse_row_);
  Mat transposed = nullptr;
  NCP_PETSC_CHECK(MatTranspose(A, MAT_INITIAL_MATRIX, &transposed));
  NCP_PETSC_CHECK(MatDiagonalScale(transposed, nullptr, row_));
  NCP_PETSC_CHECK(MatGetRowMaxAbs(transposed, column_, nullptr));
  MatDestroy(&transposed);
  spread_ = std::max(spread_, Spread(comm, column_));
  ToScales(column_, inverse_column_);
  return spread_ > internal::Equilibration::kSpreadThreshold;
}

void DistributedEquilibration::Scale(Mat A) const {
  NCP_PETSC_CHECK(MatDiagonalScale(A, row_, column_));
}

void DistributedEquilibration::Unscale(Mat A) const {
  NCP_PETSC_CHECK(MatDiagonalScale(A, inverse_row_, inverse_column_));
}

void ArmNullPivotDetection(Mat F, PetscInt n) {
  NCP_PETSC_CHECK(MatMumpsSetIcntl(F, 24, 1));
  NCP_PETSC_CHECK(MatMumpsSetIcntl(F, 13, 1));
  NCP_PETSC_CHECK(MatMumpsSetCntl(
      F, 3, static_cast<double>(n) * std::numeric_limits<double>::epsilon()));
}

int MumpsNullPivots(Mat F) {
  PetscInt k = 0;
  NCP_PETSC_CHECK(MatMumpsGetInfog(F, 28, &k));
  return static_cast<int>(k);
}

// Entry `index` of the deterministic probe vector v_j: uniform in [-1, 1) from a hash of
// (global index, j) (splitmix64), so every rank count builds the same vector.
double ProbeEntry(PetscInt index, int j) {
  std::uint64_t z = static_cast<std::uint64_t>(index) * 0x9E3779B97F4A7C15ull +
                    static_cast<std::uint64_t>(j + 1) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
}

// w = v_j - F^-1 A v_j for the factor F of A with its null pivots fixed: MUMPS' fixed
// factorization is that of A~ = A + E, E nonzero only on the k null-pivot rows, so w =
// A~^-1 E v_j lies in A~^-1 span(rows of E), a k-dimensional space that holds null(A)
// (A n = 0 gives n = A~^-1 E n) and equals it when E null(A) has rank k. k probes then
// span null(A) (generically). This replaces MUMPS' own null-space solves (ICNTL(25) = i),
// which it refuses with the distributed solution PETSc uses on more than one rank
// (INFOG(1) = -37).
void NullVector(Mat F, Mat A, int j, Vec* w) {
  Vec v = nullptr, Av = nullptr;
  NCP_PETSC_CHECK(MatCreateVecs(A, &v, &Av));
  NCP_PETSC_CHECK(VecDuplicate(v, w));
  PetscInt first = 0, last = 0;
  NCP_PETSC_CHECK(VecGetOwnershipRange(v, &first, &last));
  PetscScalar* a = nullptr;
  NCP_PETSC_CHECK(VecGetArray(v, &a));
  for (PetscInt i = first; i < last; ++i) a[i - first] = ProbeEntry(i, j);
  NCP_PETSC_CHECK(VecRestoreArray(v, &a));
  NCP_PETSC_CHECK(MatMult(A, v, Av));
  NCP_PETSC_CHECK(MatSolve(F, Av, *w));
  NCP_PETSC_CHECK(VecAYPX(*w, -1.0, v));
  VecDestroy(&v);
  VecDestroy(&Av);
}

// y <- y - N a with (N'N) a = N'y (N = basis, k columns): y made orthogonal to span(N).
// false when the Gram matrix N'N is not positive definite (dependent probes).
bool ProjectOntoComplement(std::vector<Vec>& basis, Vec y) {
  const auto k = static_cast<Eigen::Index>(basis.size());
  if (k == 0) return true;
  DenseMatrix gram(k, k);
  Vector projections(k);
  std::vector<PetscScalar> dots(basis.size());
  for (Eigen::Index i = 0; i < k; ++i) {
    NCP_PETSC_CHECK(VecMDot(basis[static_cast<size_t>(i)], static_cast<PetscInt>(k),
                            basis.data(), dots.data()));
    for (Eigen::Index j = 0; j < k; ++j)
      gram(i, j) = PetscRealPart(dots[static_cast<size_t>(j)]);
  }
  NCP_PETSC_CHECK(VecMDot(y, static_cast<PetscInt>(k), basis.data(), dots.data()));
  for (Eigen::Index j = 0; j < k; ++j)
    projections(j) = PetscRealPart(dots[static_cast<size_t>(j)]);
  const Eigen::LLT<DenseMatrix> llt(gram);
  if (llt.info() != Eigen::Success || !projections.allFinite()) return false;
  const Vector a = llt.solve(projections);
  std::vector<PetscScalar> minus_a(basis.size());
  for (Eigen::Index j = 0; j < k; ++j) minus_a[static_cast<size_t>(j)] = -a(j);
  NCP_PETSC_CHECK(VecMAXPY(y, static_cast<PetscInt>(k), minus_a.data(), basis.data()));
  return true;
}

// MUMPS through PETSc's factor matrix (MatGetFactor), one factorization per call (a
// fallback: the pattern is analysed afresh); the null space from k probes (NullVector).
bool MinimumNormSolver::Solve(Mat J, Vec rhs, Vec x) {
  const MPI_Comm comm = CommOf(J);
  PetscInt n = 0;
  NCP_PETSC_CHECK(MatGetSize(J, &n, nullptr));
  equilibration_.Compute(J);
  Mat scaled = nullptr, F = nullptr;
  NCP_PETSC_CHECK(MatDuplicate(J, MAT_COPY_VALUES, &scaled));
  equilibration_.Scale(scaled);
  NCP_PETSC_CHECK(MatGetFactor(scaled, MATSOLVERMUMPS, MAT_FACTOR_LU, &F));
  NCP_PETSC_CHECK(MatSetOptionsPrefix(F, prefix_.c_str()));
  ArmNullPivotDetection(F, n);
  MatFactorInfo info;
  NCP_PETSC_CHECK(MatFactorInfoInitialize(&info));
  bool ok = MatLUFactorSymbolic(F, scaled, nullptr, nullptr, &info) == 0 &&
            MatLUFactorNumeric(F, scaled, &info) == 0;
  MatFactorError error = MAT_FACTOR_NOERROR;
  if (ok) NCP_PETSC_CHECK(MatFactorGetError(F, &error));
  ok = ok && error == MAT_FACTOR_NOERROR;
  const bool any_failed = AnyRank(comm, !ok);
  null_pivots_ = -1;
  std::vector<Vec> basis;
  if (!any_failed) {
    const PetscInt k = MumpsNullPivots(F);
    null_pivots_ = static_cast<int>(k);
    Vec scaled_rhs = nullptr;
    NCP_PETSC_CHECK(VecDuplicate(rhs, &scaled_rhs));
    NCP_PETSC_CHECK(VecPointwiseMult(scaled_rhs, equilibration_.row(), rhs));
    NCP_PETSC_CHECK(MatSolve(F, scaled_rhs, x));  // y0
    basis.resize(static_cast<size_t>(k), nullptr);
    for (PetscInt i = 0; i < k; ++i)
      NullVector(F, scaled, static_cast<int>(i), &basis[static_cast<size_t>(i)]);
    VecDestroy(&scaled_rhs);
  }
  MatDestroy(&F);
  MatDestroy(&scaled);
  if (any_failed) return false;
  const bool projected = ProjectOntoComplement(basis, x);
  DestroyVecs(&basis);
  if (!projected) return false;
  NCP_PETSC_CHECK(VecPointwiseMult(x, x, equilibration_.column()));
  PetscReal norm = 0.0;
  NCP_PETSC_CHECK(VecNorm(x, NORM_INFINITY, &norm));
  return std::isfinite(norm);
}

}  // namespace ncp::petsc
