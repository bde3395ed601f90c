// Work vectors (the solver's, and its KSP's and PCMG's), a matrix copy and per-row arrays
// whose memory is advised for transparent huge pages.
//
// Why: a solve on a new grid first-touches all of its fresh arrays, and on Linux every
// 4 KiB page of fresh anonymous memory is a page fault. Where the kernel's transparent
// huge pages are in `madvise` mode (/sys/kernel/mm/transparent_hugepage/enabled), a block
// advised with MADV_HUGEPAGE is faulted in 2 MiB pages instead, 512 times fewer faults
// (measured on the benchmark machine: benchmarks/results/petsc/solver/README.md). In
// `always` mode the advice changes nothing, in `never` mode it is ignored. On Linux a
// block of 2 MiB or more is an anonymous mmap (zero without a pass over it, aligned to 2
// MiB); smaller blocks, and all elsewhere, come from calloc (a huge page for a small Vec
// would zero 2 MiB, and glibc recycles small freed blocks without new page faults).
//
// The block of Vecs or of a matrix is owned by a PetscContainer composed with every
// object whose arrays lie in it, so it is freed when the last of them is destroyed (also
// when a KSP or PC holds the last reference); a LocalArray owns its memory like a
// std::vector.
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <cstddef>
#include <vector>

namespace ncp::petsc {

// `bytes` zero bytes: from 2 MiB up (Linux) an anonymous mmap, 2 MiB aligned and advised
// for huge pages; smaller, or elsewhere, from calloc. Throws std::bad_alloc.
void* AllocateZeroed(std::size_t bytes);
// Frees what AllocateZeroed(bytes) gave (nullptr: nothing).
void FreeZeroed(void* data, std::size_t bytes);

// A std::allocator on AllocateZeroed, for the solver's own arrays of one entry per local
// row (LocalArray).
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(AllocateZeroed(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) { FreeZeroed(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }
};
template <class T>
using LocalArray = std::vector<T, HugePageAllocator<T>>;

// `count` Vecs of the type and layout of `layout`, zero, their arrays side by side in one
// block. Only for the standard types VECSEQ and VECMPI: false (nothing made) for another
// type of `layout`, whose Vecs the caller makes by VecDuplicate. Their VecDuplicate (and
// so VecDuplicateVecs) makes Vecs in blocks too (so a KSP's work vectors, duplicates of
// its solution Vec, do).
bool CreateVecsInBlock(Vec layout, int count, Vec* out);

// MatCreateVecs(A) from now on makes its Vecs in blocks (as CreateVecsInBlock): the
// vectors PCMG and its smoothers create for a level whose operator is A. For MATSEQAIJ
// and MATMPIAIJ; other types are left as they are.
void CreateVecsOfMatInBlocks(Mat A);

// A copy of the matrix A (pattern and values) whose CSR arrays lie in one block: for A of
// type MATSEQAIJ (MatCreateSeqAIJWithArrays) or MATMPIAIJ (its diagonal and off-diagonal
// blocks' arrays, MatCreateMPIAIJWithSplitArrays) with every diagonal entry stored, else
// nullptr (the caller duplicates A by MatDuplicate). Collective on A's communicator. New
// nonzeros cannot be added to the copy.
Mat DuplicateAijInBlock(Mat A);

}  // namespace ncp::petsc
