// |M| v for a distributed AIJ matrix, read in place (the round-off floor and the backward
// error of ncp::petsc::Solver need the product with the absolute values of F').
#pragma once

#include "petsc_support.hpp"

namespace ncp::petsc {

// out = |M| v for an AIJ matrix M and a Vec v >= 0 laid out like M's columns, from M's
// own arrays (no copy of M): on each rank the rows of its diagonal block times its part
// of v plus the rows of its off-diagonal block times the ghost entries of v, gathered
// by a scatter made once for M's pattern (Prepare).
class AbsoluteProduct {
 public:
  ~AbsoluteProduct() { Clear(); }
  AbsoluteProduct() = default;
  AbsoluteProduct(const AbsoluteProduct&) = delete;
  AbsoluteProduct& operator=(const AbsoluteProduct&) = delete;

  // For M's pattern (again whenever it or M changes).
  void Prepare(Mat M) {
    Clear();
    bool parallel = false;
    if (!IsAij(M, &parallel))
      throw std::invalid_argument(
          "ncp::petsc::Solver: the Jacobian matrix must be of type AIJ "
          "(MATSEQAIJ or MATMPIAIJ)");
    if (!parallel) return;
    Mat diagonal = nullptr, off_diagonal = nullptr;
    const PetscInt* ghost_columns = nullptr;  // global columns of the off-diagonal block
    NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &diagonal, &off_diagonal, &ghost_columns));
    PetscInt rows = 0, ghosts = 0;
    NCP_PETSC_CHECK(MatGetSize(off_diagonal, &rows, &ghosts));
    IS columns = nullptr;
    NCP_PETSC_CHECK(ISCreateGeneral(PETSC_COMM_SELF, ghosts, ghost_columns,
                                    PETSC_COPY_VALUES, &columns));
    NCP_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, ghosts, &ghost_values_));
    Vec layout = nullptr;
    NCP_PETSC_CHECK(MatCreateVecs(M, &layout, nullptr));
    NCP_PETSC_CHECK(VecScatterCreate(layout, columns, ghost_values_, nullptr, &scatter_));
    VecDestroy(&layout);
    ISDestroy(&columns);
  }

  void Mult(Mat M, Vec v, Vec out) {
    bool parallel = false;
    IsAij(M, &parallel);
    Mat blocks[2] = {M, nullptr};
    if (parallel) {
      NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &blocks[0], &blocks[1], nullptr));
      NCP_PETSC_CHECK(
          VecScatterBegin(scatter_, v, ghost_values_, INSERT_VALUES, SCATTER_FORWARD));
      NCP_PETSC_CHECK(
          VecScatterEnd(scatter_, v, ghost_values_, INSERT_VALUES, SCATTER_FORWARD));
    }
    NCP_PETSC_CHECK(VecSet(out, 0.0));
    LocalWrite o(out);
    {
      LocalRead local(v);
      AddBlockProduct(blocks[0], local, o);
    }
    if (parallel) {
      LocalRead ghost(ghost_values_);
      AddBlockProduct(blocks[1], ghost, o);
    }
  }

 private:
  // o += |B| x for a sequential AIJ block B (CSR arrays read in place).
  static void AddBlockProduct(Mat B, const LocalRead& x, LocalWrite& o) {
    PetscInt rows = 0;
    const PetscInt *start = nullptr, *column = nullptr;
    PetscBool done = PETSC_FALSE;
    NCP_PETSC_CHECK(
        MatGetRowIJ(B, 0, PETSC_FALSE, PETSC_FALSE, &rows, &start, &column, &done));
    if (!done) throw std::runtime_error("ncp::petsc::Solver: MatGetRowIJ gave no rows");
    const PetscScalar* values = nullptr;
    NCP_PETSC_CHECK(MatSeqAIJGetArrayRead(B, &values));
    for (PetscInt i = 0; i < rows; ++i) {
      double sum = 0.0;
      for (PetscInt k = start[i]; k < start[i + 1]; ++k)
        sum += std::abs(PetscRealPart(values[k])) * x[column[k]];
      o[i] += sum;
    }
    NCP_PETSC_CHECK(MatSeqAIJRestoreArrayRead(B, &values));
    NCP_PETSC_CHECK(
        MatRestoreRowIJ(B, 0, PETSC_FALSE, PETSC_FALSE, &rows, &start, &column, &done));
  }

  void Clear() {
    if (scatter_) VecScatterDestroy(&scatter_);
    if (ghost_values_) VecDestroy(&ghost_values_);
  }

  VecScatter scatter_ = nullptr;
  Vec ghost_values_ = nullptr;  // the off-diagonal block's columns of v
};

}  // namespace ncp::petsc
