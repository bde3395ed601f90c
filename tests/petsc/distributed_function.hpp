// A serial ncp::SquareFunction seen through ncp::petsc's callbacks: every rank gathers x,
// evaluates F redundantly and keeps its own rows of F(x) and F'(x). (Only for tests: it
// lets the PETSc solver and the serial ncp::Solver run on literally the same F.)
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <stdexcept>
#include <vector>

#include "ncp/petsc/solver.hpp"
#include "ncp/square_function.hpp"

namespace ncp::test {

class DistributedFunction {
 public:
  /// x_layout: a Vec of size F.NumVariables() whose layout the problem takes. The
  /// Jacobian's pattern is that of F'(x_pattern).
  DistributedFunction(SquareFunction& F, Vec x_layout, const Vector& x_pattern) : F_(F) {
    n_ = F.NumVariables();
    VecGetOwnershipRange(x_layout, &first_, &last_);
    VecScatterCreateToAll(x_layout, &to_all_, &all_);
    SparseMatrix J;
    if (!F_.Jacobian(x_pattern, &J))
      throw std::runtime_error("DistributedFunction: no Jacobian at x_pattern");
    Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows = J;
    std::vector<PetscInt> diagonal, off_diagonal;
    for (PetscInt i = first_; i < last_; ++i) {
      PetscInt d = 0, o = 0;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(rows, i);
           it; ++it)
        (it.col() >= first_ && it.col() < last_ ? d : o) += 1;
      diagonal.push_back(d + 1);  // (+1: room for a diagonal entry)
      off_diagonal.push_back(o);
    }
    MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(x_layout));
    MatCreateAIJ(comm, last_ - first_, last_ - first_, n_, n_, 0, diagonal.data(), 0,
                 off_diagonal.data(), &J_);
    MatSetOption(J_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE);
    Insert(J);
  }
  ~DistributedFunction() {
    MatDestroy(&J_);
    VecScatterDestroy(&to_all_);
    VecDestroy(&all_);
  }
  DistributedFunction(const DistributedFunction&) = delete;
  DistributedFunction& operator=(const DistributedFunction&) = delete;

  Mat matrix() const { return J_; }
  int evaluations() const { return evaluations_; }

  ncp::petsc::BoxMcp Problem(Vec lower, Vec upper) {
    ncp::petsc::BoxMcp p;
    p.residual = [this](Vec x, Vec f) { return Residual(x, f); };
    p.jacobian = [this](Vec x, Mat J) { return Jacobian(x, J); };
    p.jacobian_matrix = J_;
    p.lower = lower;
    p.upper = upper;
    return p;
  }

  PetscErrorCode Residual(Vec x, Vec f) {
    ++evaluations_;
    const Vector x_all = Gather(x);
    Vector F(n_);  // (SquareFunction::Evaluate writes into a vector of size n)
    if (!F_.Evaluate(x_all, &F)) return 1;
    PetscScalar* a = nullptr;
    VecGetArray(f, &a);
    for (PetscInt i = first_; i < last_; ++i) a[i - first_] = F(i);
    VecRestoreArray(f, &a);
    return 0;
  }

  PetscErrorCode Jacobian(Vec x, Mat J) {
    SparseMatrix S;
    if (!F_.Jacobian(Gather(x), &S)) return 1;
    if (J != J_) return 1;
    Insert(S);
    return 0;
  }

  /// x on every rank.
  Vector Gather(Vec x) {
    VecScatterBegin(to_all_, x, all_, INSERT_VALUES, SCATTER_FORWARD);
    VecScatterEnd(to_all_, x, all_, INSERT_VALUES, SCATTER_FORWARD);
    const PetscScalar* a = nullptr;
    VecGetArrayRead(all_, &a);
    Vector out(n_);
    for (PetscInt i = 0; i < n_; ++i) out(i) = a[i];
    VecRestoreArrayRead(all_, &a);
    return out;
  }

 private:
  void Insert(const SparseMatrix& S) {
    Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows = S;
    for (PetscInt i = first_; i < last_; ++i) {
      std::vector<PetscInt> cols;
      std::vector<PetscScalar> values;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(rows, i);
           it; ++it) {
        cols.push_back(it.col());
        values.push_back(it.value());
      }
      MatSetValues(J_, 1, &i, static_cast<PetscInt>(cols.size()), cols.data(),
                   values.data(), INSERT_VALUES);
    }
    MatAssemblyBegin(J_, MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(J_, MAT_FINAL_ASSEMBLY);
  }

  SquareFunction& F_;
  PetscInt n_ = 0, first_ = 0, last_ = 0;
  VecScatter to_all_ = nullptr;
  Vec all_ = nullptr;
  Mat J_ = nullptr;
  int evaluations_ = 0;
};

/// Each rank's owned entries of out set from v (v indexed in the global numbering).
inline void SetOwnedEntries(const Vector& v, Vec out) {
  PetscInt first = 0, last = 0;
  VecGetOwnershipRange(out, &first, &last);
  PetscScalar* a = nullptr;
  VecGetArray(out, &a);
  for (PetscInt i = first; i < last; ++i) a[i - first] = v(i);
  VecRestoreArray(out, &a);
}

/// A Vec on comm with the entries of v (PETSc chooses the layout).
inline Vec MakeVec(MPI_Comm comm, const Vector& v) {
  Vec out = nullptr;
  VecCreateMPI(comm, PETSC_DECIDE, static_cast<PetscInt>(v.size()), &out);
  SetOwnedEntries(v, out);
  return out;
}

}  // namespace ncp::test
