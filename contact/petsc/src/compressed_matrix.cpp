#include "compressed_matrix.hpp"

#include <vector>

#include "petsc_check.hpp"

namespace contact::petsc::internal {
namespace {

// Visits the kept entries of A's local rows: f(local row, global row, columns, values).
template <typename F>
void ForKeptRows(Mat A, F&& f) {
  PetscInt first = 0, last = 0;
  CONTACT_PETSC_CHECK(MatGetOwnershipRange(A, &first, &last));
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  for (PetscInt row = first; row < last; ++row) {
    PetscInt count = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    CONTACT_PETSC_CHECK(MatGetRow(A, row, &count, &cols, &vals));
    columns.clear();
    values.clear();
    for (PetscInt k = 0; k < count; ++k)
      if (vals[k] != 0.0 || cols[k] == row) {
        columns.push_back(cols[k]);
        values.push_back(vals[k]);
      }
    CONTACT_PETSC_CHECK(MatRestoreRow(A, row, &count, &cols, &vals));
    f(row - first, row, columns, values);
  }
}

}  // namespace

Mat CopyWithoutZeros(Mat A) {
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  PetscInt rows = 0, columns = 0, local_rows = 0, local_columns = 0;
  CONTACT_PETSC_CHECK(MatGetSize(A, &rows, &columns));
  CONTACT_PETSC_CHECK(MatGetLocalSize(A, &local_rows, &local_columns));
  PetscInt column_first = 0, column_last = 0;  // the columns of the diagonal block
  CONTACT_PETSC_CHECK(MatGetOwnershipRangeColumn(A, &column_first, &column_last));
  // Preallocation: per local row, the kept entries in the diagonal and off-diagonal
  // blocks.
  std::vector<PetscInt> diagonal(static_cast<size_t>(local_rows), 0),
      off_diagonal(static_cast<size_t>(local_rows), 0);
  ForKeptRows(A, [&](PetscInt i, PetscInt, const std::vector<PetscInt>& cols,
                     const std::vector<PetscScalar>&) {
    for (const PetscInt c : cols)
      ++(c >= column_first && c < column_last ? diagonal
                                              : off_diagonal)[static_cast<size_t>(i)];
  });
  Mat B = nullptr;
  CONTACT_PETSC_CHECK(MatCreate(comm, &B));
  CONTACT_PETSC_CHECK(MatSetSizes(B, local_rows, local_columns, rows, columns));
  CONTACT_PETSC_CHECK(MatSetType(B, MATAIJ));
  CONTACT_PETSC_CHECK(MatSeqAIJSetPreallocation(B, 0, diagonal.data()));
  CONTACT_PETSC_CHECK(
      MatMPIAIJSetPreallocation(B, 0, diagonal.data(), 0, off_diagonal.data()));
  ForKeptRows(A, [&](PetscInt, PetscInt row, const std::vector<PetscInt>& cols,
                     const std::vector<PetscScalar>& vals) {
    CONTACT_PETSC_CHECK(MatSetValues(B, 1, &row, static_cast<PetscInt>(cols.size()),
                                     cols.data(), vals.data(), INSERT_VALUES));
  });
  CONTACT_PETSC_CHECK(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY));
  CONTACT_PETSC_CHECK(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY));
  PetscBool set = PETSC_FALSE, flag = PETSC_FALSE;
  CONTACT_PETSC_CHECK(MatIsSymmetricKnown(A, &set, &flag));
  if (set) CONTACT_PETSC_CHECK(MatSetOption(B, MAT_SYMMETRIC, flag));
  CONTACT_PETSC_CHECK(MatIsSPDKnown(A, &set, &flag));
  if (set) CONTACT_PETSC_CHECK(MatSetOption(B, MAT_SPD, flag));
  return B;
}

}  // namespace contact::petsc::internal
