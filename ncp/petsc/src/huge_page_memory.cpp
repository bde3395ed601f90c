#include "huge_page_memory.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include "petsc_support.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ncp::petsc {
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;  // 2 MiB, x86-64 and arm64

// The block of a container: its memory and size (AllocateZeroed).
struct Block {
  void* data = nullptr;
  std::size_t bytes = 0;
};

PetscErrorCode FreeBlock(void* pointer) {
  auto* block = static_cast<Block*>(pointer);
  FreeZeroed(block->data, block->bytes);
  delete block;
  return 0;
}

// A container owning a block of `bytes` zero bytes at *data. Throws std::bad_alloc.
PetscContainer NewBlock(std::size_t bytes, void** data) {
  auto* block = new Block;
  block->bytes = bytes;
  try {
    block->data = AllocateZeroed(bytes);
  } catch (...) {
    delete block;
    throw;
  }
  PetscContainer container = nullptr;
  const PetscErrorCode code = PetscContainerCreate(PETSC_COMM_SELF, &container);
  if (code != 0) FreeBlock(block);
  Check(code, "PetscContainerCreate");
  NCP_PETSC_CHECK(PetscContainerSetPointer(container, block));
  NCP_PETSC_CHECK(PetscContainerSetUserDestroy(container, FreeBlock));
  *data = block->data;
  return container;
}

// `object` keeps `container` (and so the block) alive until it is destroyed.
void Keep(PetscObject object, PetscContainer container) {
  NCP_PETSC_CHECK(PetscObjectCompose(object, "ncp_petsc_huge_page_block",
                                     reinterpret_cast<PetscObject>(container)));
}

std::size_t CacheLines(std::size_t bytes) { return (bytes + 63) / 64 * 64; }

void MakeVecs(MPI_Comm comm, bool seq, PetscInt local, PetscInt global, int count,
              Vec* out);

// VECOP_DUPLICATE of the Vecs made here: duplicates in a block too (a KSP's work vectors
// are duplicates of its solution Vec, by VecDuplicateVecs, which calls VecDuplicate for
// each; PCMG's residuals are duplicates of its right-hand sides). A PETSc callback:
// errors are returned, not thrown.
PetscErrorCode DuplicateVecInBlock(Vec v, Vec* out) {
  PetscFunctionBeginUser;
  try {
    CreateVecsInBlock(v, 1, out);
  } catch (const std::exception&) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_MEM, "ncp::petsc: no memory for a work vector");
  }
  PetscFunctionReturn(0);
}

// MATOP_CREATE_VECS of the matrices given to CreateVecsOfMatInBlocks: MatCreateVecs'
// right (column layout) and left (row layout) Vecs, each in a block.
PetscErrorCode CreateVecsOfMat(Mat A, Vec* right, Vec* left) {
  PetscFunctionBeginUser;
  PetscMPIInt size = 0;
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscInt rows = 0, columns = 0, local_rows = 0, local_columns = 0;
  PetscCall(MatGetSize(A, &rows, &columns));
  PetscCall(MatGetLocalSize(A, &local_rows, &local_columns));
  try {
    if (right) MakeVecs(comm, size == 1, local_columns, columns, 1, right);
    if (left) MakeVecs(comm, size == 1, local_rows, rows, 1, left);
  } catch (const std::exception&) {
    SETERRQ(comm, PETSC_ERR_MEM, "ncp::petsc: no memory for a matrix's vectors");
  }
  PetscFunctionReturn(0);
}

void MakeVecs(MPI_Comm comm, bool seq, PetscInt local, PetscInt global, int count,
              Vec* out) {
  // Each array starts on a 64-byte boundary (a cache line).
  const std::size_t stride =
      CacheLines(static_cast<std::size_t>(local) * sizeof(PetscScalar)) /
      sizeof(PetscScalar);
  const std::size_t bytes =
      stride * static_cast<std::size_t>(count) * sizeof(PetscScalar);
  void* data = nullptr;
  PetscContainer container = NewBlock(bytes, &data);
  auto* scalars = static_cast<PetscScalar*>(data);
  for (int k = 0; k < count; ++k) {
    PetscScalar* array = scalars + stride * static_cast<std::size_t>(k);
    if (seq)
      NCP_PETSC_CHECK(VecCreateSeqWithArray(comm, 1, local, array, &out[k]));
    else
      NCP_PETSC_CHECK(VecCreateMPIWithArray(comm, 1, local, global, array, &out[k]));
    Keep(reinterpret_cast<PetscObject>(out[k]), container);
    NCP_PETSC_CHECK(VecSetOperation(
        out[k], VECOP_DUPLICATE, reinterpret_cast<void (*)(void)>(DuplicateVecInBlock)));
  }
  NCP_PETSC_CHECK(PetscContainerDestroy(&container));
}

// The CSR arrays (values, row starts, column indices) of one SeqAIJ block of the copy.
struct CsrArrays {
  PetscScalar* values = nullptr;
  PetscInt* starts = nullptr;
  PetscInt* columns = nullptr;
};

// The CSR structure of the SeqAIJ matrix `seq` while the object lives (MatGetRowIJ /
// MatRestoreRowIJ), and the layout of a copy of its arrays: values | row starts | column
// indices, each from a 64-byte boundary.
class RowIJ {
 public:
  explicit RowIJ(Mat seq) : seq_(seq) {
    PetscBool done = PETSC_FALSE;
    NCP_PETSC_CHECK(
        MatGetRowIJ(seq_, 0, PETSC_FALSE, PETSC_FALSE, &n_, &start_, &column_, &done));
    if (!done) throw std::runtime_error("ncp::petsc::Solver: MatGetRowIJ gave no rows");
    rows_ = static_cast<std::size_t>(n_);  // (MatRestoreRowIJ sets n_ to 0)
    nonzeros_ = static_cast<std::size_t>(start_[n_]);
  }
  ~RowIJ() {
    PetscBool done = PETSC_FALSE;
    MatRestoreRowIJ(seq_, 0, PETSC_FALSE, PETSC_FALSE, &n_, &start_, &column_, &done);
  }
  RowIJ(const RowIJ&) = delete;
  RowIJ& operator=(const RowIJ&) = delete;

  std::size_t StartsOffset() const { return CacheLines(nonzeros_ * sizeof(PetscScalar)); }
  std::size_t ColumnsOffset() const {
    return StartsOffset() + CacheLines((rows_ + 1) * sizeof(PetscInt));
  }
  std::size_t CopyBytes() const {
    return ColumnsOffset() + CacheLines(nonzeros_ * sizeof(PetscInt));
  }

  // Copies the row starts and column indices to their places in `base`; column k is
  // written as global_column[k] when global_column is given (the off-diagonal block of an
  // MPIAIJ matrix, whose columns are numbered locally), else as k.
  void CopyStructure(char* base, const PetscInt* global_column) const {
    auto* starts = reinterpret_cast<PetscInt*>(base + StartsOffset());
    auto* columns = reinterpret_cast<PetscInt*>(base + ColumnsOffset());
    std::memcpy(starts, start_, (rows_ + 1) * sizeof(PetscInt));
    if (global_column)
      for (std::size_t k = 0; k < nonzeros_; ++k) columns[k] = global_column[column_[k]];
    else
      std::memcpy(columns, column_, nonzeros_ * sizeof(PetscInt));
  }
  std::size_t nonzeros() const { return nonzeros_; }

 private:
  Mat seq_;
  PetscInt n_ = 0;
  const PetscInt* start_ = nullptr;
  const PetscInt* column_ = nullptr;
  std::size_t rows_ = 0, nonzeros_ = 0;
};

// Copies the CSR arrays of the SeqAIJ matrix `seq` to `base` (RowIJ::CopyBytes of room;
// global_column as in RowIJ::CopyStructure).
CsrArrays CopyCsr(Mat seq, char* base, const PetscInt* global_column) {
  const RowIJ ij(seq);
  ij.CopyStructure(base, global_column);
  const PetscScalar* a = nullptr;
  NCP_PETSC_CHECK(MatSeqAIJGetArrayRead(seq, &a));
  std::memcpy(base, a, ij.nonzeros() * sizeof(PetscScalar));
  NCP_PETSC_CHECK(MatSeqAIJRestoreArrayRead(seq, &a));
  return {reinterpret_cast<PetscScalar*>(base),
          reinterpret_cast<PetscInt*>(base + ij.StartsOffset()),
          reinterpret_cast<PetscInt*>(base + ij.ColumnsOffset())};
}

}  // namespace

void* AllocateZeroed(std::size_t bytes) {
#if defined(__linux__)
  if (bytes >= kHugePage) {
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    // Anonymous memory is zero. One huge page more is mapped to align the start to
    // 2 MiB, and the unaligned head and tail are unmapped again.
    const std::size_t mapped = rounded + kHugePage;
    void* start =
        mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (start == MAP_FAILED) throw std::bad_alloc();
    const auto address = reinterpret_cast<std::uintptr_t>(start);
    const std::uintptr_t aligned = (address + kHugePage - 1) / kHugePage * kHugePage;
    if (aligned > address) munmap(start, aligned - address);
    if (address + mapped > aligned + rounded)
      munmap(reinterpret_cast<void*>(aligned + rounded),
             address + mapped - aligned - rounded);
    void* data = reinterpret_cast<void*>(aligned);
#if defined(MADV_HUGEPAGE)
    // Advice only: refused (THP off, an old kernel) it leaves ordinary pages.
    (void)madvise(data, rounded, MADV_HUGEPAGE);
#endif
    return data;
  }
#endif
  void* data = std::calloc(std::max<std::size_t>(bytes, 1), 1);
  if (!data) throw std::bad_alloc();
  return data;
}

void FreeZeroed(void* data, std::size_t bytes) {
  if (!data) return;
#if defined(__linux__)
  if (bytes >= kHugePage) {
    munmap(data, (bytes + kHugePage - 1) / kHugePage * kHugePage);
    return;
  }
#endif
  std::free(data);
}

bool CreateVecsInBlock(Vec layout, int count, Vec* out) {
  PetscBool seq = PETSC_FALSE, mpi = PETSC_FALSE;
  NCP_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(layout), VECSEQ, &seq));
  NCP_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(layout), VECMPI, &mpi));
  // The same answer on every rank: the ranks' parts of a Vec have one type.
  if (!seq && !mpi) return false;
  PetscInt local = 0, global = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(layout, &local));
  NCP_PETSC_CHECK(VecGetSize(layout, &global));
  MakeVecs(PetscObjectComm(reinterpret_cast<PetscObject>(layout)), seq == PETSC_TRUE,
           local, global, count, out);
  return true;
}

void CreateVecsOfMatInBlocks(Mat A) {
  PetscBool aij = PETSC_FALSE;
  NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(A), &aij,
                                            MATSEQAIJ, MATMPIAIJ, ""));
  if (!aij) return;
  NCP_PETSC_CHECK(MatSetOperation(A, MATOP_CREATE_VECS,
                                  reinterpret_cast<void (*)(void)>(CreateVecsOfMat)));
}

Mat DuplicateAijInBlock(Mat A) {
  PetscBool seq = PETSC_FALSE, mpi = PETSC_FALSE, missing = PETSC_TRUE;
  NCP_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATSEQAIJ, &seq));
  NCP_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATMPIAIJ, &mpi));
  // The type is the same on every rank; a missing diagonal entry is agreed on below.
  if (!seq && !mpi) return nullptr;
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(A));
  PetscInt first_missing = 0, rows = 0, columns = 0, local_rows = 0, local_columns = 0;
  NCP_PETSC_CHECK(MatMissingDiagonal(A, &missing, &first_missing));
  int any_missing = missing ? 1 : 0;
  if (mpi)
    NCP_PETSC_CHECK(MPI_Allreduce(MPI_IN_PLACE, &any_missing, 1, MPI_INT, MPI_LOR, comm));
  if (any_missing) return nullptr;
  NCP_PETSC_CHECK(MatGetSize(A, &rows, &columns));
  NCP_PETSC_CHECK(MatGetLocalSize(A, &local_rows, &local_columns));
  // The diagonal block (columns numbered from the rank's first column) and, on several
  // ranks, the off-diagonal block (global column numbers, as
  // MatCreateMPIAIJWithSplitArrays takes them), both in one block.
  Mat diagonal = A, off_diagonal = nullptr;
  const PetscInt* global_column = nullptr;
  if (mpi)
    NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A, &diagonal, &off_diagonal, &global_column));
  const std::size_t diagonal_bytes = RowIJ(diagonal).CopyBytes();
  const std::size_t bytes = diagonal_bytes + (mpi ? RowIJ(off_diagonal).CopyBytes() : 0);
  void* data = nullptr;
  PetscContainer container = NewBlock(bytes, &data);
  auto* base = static_cast<char*>(data);
  const CsrArrays d = CopyCsr(diagonal, base, nullptr);
  Mat copy = nullptr;
  if (mpi) {
    const CsrArrays o = CopyCsr(off_diagonal, base + diagonal_bytes, global_column);
    // Its assembly renumbers the off-diagonal columns in place (in the block).
    NCP_PETSC_CHECK(MatCreateMPIAIJWithSplitArrays(comm, local_rows, local_columns, rows,
                                                   columns, d.starts, d.columns, d.values,
                                                   o.starts, o.columns, o.values, &copy));
  } else {
    NCP_PETSC_CHECK(MatCreateSeqAIJWithArrays(comm, rows, columns, d.starts, d.columns,
                                              d.values, &copy));
  }
  Keep(reinterpret_cast<PetscObject>(copy), container);
  NCP_PETSC_CHECK(PetscContainerDestroy(&container));
  return copy;
}

}  // namespace ncp::petsc
