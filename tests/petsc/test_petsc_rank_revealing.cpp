// ncp/petsc/src/rank_revealing.* against the serial kernels they stand for
// (ncp/src/linear_solver.hpp) on 1, 2 and 4 ranks: DistributedEquilibration gives the
// serial Equilibration's scales and spread to the bit, and MinimumNormSolver the serial
// RankRevealingSolver's least-norm solution of a consistent singular system.
#define CATCH_CONFIG_RUNNER
#include <petscmat.h>
#include <petscsys.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "catch_on_ranks.hpp"
#include "distributed_function.hpp"
#include "linear_solver.hpp"
#include "ncp/types.hpp"
#include "rank_revealing.hpp"

using ncp::DenseMatrix;
using ncp::SparseMatrix;
using ncp::Vector;
using ncp::test::MakeVec;

namespace {

// A Mat on PETSC_COMM_WORLD with the entries of A (rows laid out as MakeVec's).
Mat MakeMat(const SparseMatrix& A) {
  const auto n = static_cast<PetscInt>(A.rows());
  Mat M = nullptr;
  MatCreateAIJ(PETSC_COMM_WORLD, PETSC_DECIDE, PETSC_DECIDE, n, n, n, nullptr, n, nullptr,
               &M);
  PetscInt first = 0, last = 0;
  MatGetOwnershipRange(M, &first, &last);
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows(A);
  for (PetscInt i = first; i < last; ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(rows, i); it;
         ++it) {
      const PetscInt j = it.col();
      const PetscScalar v = it.value();
      MatSetValues(M, 1, &i, 1, &j, &v, INSERT_VALUES);
    }
  MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY);
  return M;
}

// Every entry of v on every rank.
Vector Gather(Vec v) {
  VecScatter to_all = nullptr;
  Vec all = nullptr;
  VecScatterCreateToAll(v, &to_all, &all);
  VecScatterBegin(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD);
  VecScatterEnd(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD);
  PetscInt n = 0;
  VecGetSize(all, &n);
  const PetscScalar* a = nullptr;
  VecGetArrayRead(all, &a);
  Vector out(n);
  for (PetscInt i = 0; i < n; ++i) out(i) = PetscRealPart(a[i]);
  VecRestoreArrayRead(all, &a);
  VecScatterDestroy(&to_all);
  VecDestroy(&all);
  return out;
}

// A random sparse n x n matrix (about 8 entries a row plus the diagonal, seed fixed)
// whose rows and columns are scaled by 2^e, e in [-12, 12]: a spread above 2^20.
// singular: column 5 = column 3 + column 7 and row 10 = row 2 - row 4 (rank n - 1, a
// one-dimensional null space that is not a unit vector).
SparseMatrix TestMatrix(int n, bool singular) {
  std::mt19937 generator(26);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> column(0, n - 1), exponent(-12, 12);
  DenseMatrix A = DenseMatrix::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    A(i, i) = 4.0 + value(generator);
    for (int k = 0; k < 8; ++k) A(i, column(generator)) = value(generator);
  }
  if (singular) {
    A.col(5) = A.col(3) + A.col(7);
    A.row(10) = A.row(2) - A.row(4);
  }
  for (int i = 0; i < n; ++i) A.row(i) *= std::ldexp(1.0, exponent(generator));
  for (int j = 0; j < n; ++j) A.col(j) *= std::ldexp(1.0, exponent(generator));
  return A.sparseView();
}

}  // namespace

TEST_CASE("DistributedEquilibration: the serial scales and spread to the bit",
          "[petsc][mpi]") {
  const SparseMatrix A = TestMatrix(60, false);
  ncp::internal::Equilibration serial;
  const bool serial_applies = serial.Compute(A);
  Mat M = MakeMat(A);
  ncp::petsc::DistributedEquilibration distributed;
  const bool applies = distributed.Compute(M);
  CHECK(serial_applies);
  CHECK(applies == serial_applies);
  CHECK(distributed.spread() == serial.spread());
  CHECK(Gather(distributed.row()) == serial.row());
  CHECK(Gather(distributed.column()) == serial.column());

  // Scale then Unscale restores every entry exactly (powers of two).
  Mat copy = nullptr;
  MatDuplicate(M, MAT_COPY_VALUES, &copy);
  distributed.Scale(copy);
  PetscBool equal = PETSC_TRUE;
  MatEqual(copy, M, &equal);
  CHECK(equal == PETSC_FALSE);
  distributed.Unscale(copy);
  MatEqual(copy, M, &equal);
  CHECK(equal == PETSC_TRUE);
  MatDestroy(&copy);
  MatDestroy(&M);
}

TEST_CASE("MinimumNormSolver: the serial least-norm solution of a singular system",
          "[petsc][mpi]") {
  const int n = 60;
  const SparseMatrix J = TestMatrix(n, true);
  Vector x_true(n);
  for (int i = 0; i < n; ++i) x_true(i) = std::sin(1.0 + i);
  const Vector rhs = J * x_true;  // consistent

  ncp::internal::RankRevealingSolver serial;
  Vector x_dense, x_sparse;
  REQUIRE(serial.Solve(DenseMatrix(J), rhs, &x_dense));
  CHECK(serial.rank() == n - 1);
  REQUIRE(serial.Solve(J, rhs, &x_sparse));
  CHECK(serial.rank() == n - 1);

  Mat M = MakeMat(J);
  Vec b = MakeVec(PETSC_COMM_WORLD, rhs), x = nullptr;
  VecDuplicate(b, &x);
  ncp::petsc::MinimumNormSolver solver("rr_mn_");
  REQUIRE(solver.Solve(M, b, x));
  CHECK(solver.null_pivots() == 1);
  const Vector x_petsc = Gather(x);

  // The same vector as both serial backends (the least-norm solution in the scaled
  // unknowns y = x / c is unique; compared there, where the entries are of one size),
  // and a solution: ||J x - rhs|| at round-off of |J||x|.
  ncp::internal::Equilibration e;
  e.Compute(J);
  const Vector y_dense = x_dense.cwiseQuotient(e.column()),
               y_sparse = x_sparse.cwiseQuotient(e.column()),
               y_petsc = x_petsc.cwiseQuotient(e.column());
  const double scale = y_dense.lpNorm<Eigen::Infinity>();
  INFO("dense " << y_dense.transpose().head(8) << "\nPETSc "
                << y_petsc.transpose().head(8) << "\nsparse "
                << y_sparse.transpose().head(8));
  CHECK((y_petsc - y_dense).lpNorm<Eigen::Infinity>() <= 1e-10 * scale);
  CHECK((y_sparse - y_dense).lpNorm<Eigen::Infinity>() <= 1e-10 * scale);
  const Vector terms = J.cwiseAbs() * x_petsc.cwiseAbs();
  CHECK((J * x_petsc - rhs).lpNorm<Eigen::Infinity>() <=
        1e-12 * terms.lpNorm<Eigen::Infinity>());
  // Not the basic solution MUMPS gives before the projection: x_true differs from it by
  // a multiple of the null vector, and so does the least-norm solution.
  CHECK((y_petsc - x_true.cwiseQuotient(e.column())).lpNorm<Eigen::Infinity>() >
        1e-6 * scale);

  VecDestroy(&x);
  VecDestroy(&b);
  MatDestroy(&M);
}

int main(int argc, char** argv) { return RunTestsOnRanks(argc, argv); }
