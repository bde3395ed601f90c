// Internal helpers of ncp::petsc: the error check of the solver's own PETSc calls,
// reductions over the communicator, owned and locally accessed Vecs, norms and AIJ
// access.
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "format_number.hpp"
#include "ncp/petsc/solver.hpp"

namespace ncp::petsc {

using Clock = std::chrono::steady_clock;
using internal::FormatNumber;

inline double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// A PETSc call of the solver itself failed (out of memory, a PETSc bug): not a numerical
// event of the iteration, so it is thrown, naming the call.
inline void Check(PetscErrorCode code, const char* call) {
  if (code != 0)
    throw std::runtime_error(std::string("ncp::petsc::Solver: ") + call +
                             " failed with PETSc error " +
                             std::to_string(static_cast<int>(code)));
}
#define NCP_PETSC_CHECK(call) Check((call), #call)

// ---- reductions over the communicator ------------------------------------------------
inline bool AnyRank(MPI_Comm comm, bool local) {
  int in = local ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, comm);
  return out != 0;
}
inline long long SumRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_SUM, comm);
  return out;
}
inline long long MinRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_MIN, comm);
  return out;
}
// Several counts (or 0/1 flags) summed over the ranks in one MPI_Allreduce.
template <size_t N>
std::array<long long, N> SumRanks(MPI_Comm comm, const std::array<long long, N>& local) {
  std::array<long long, N> out{};
  MPI_Allreduce(local.data(), out.data(), static_cast<int>(N), MPI_LONG_LONG, MPI_SUM,
                comm);
  return out;
}
// The maxima of several local values over the ranks in one MPI_Allreduce (for values
// known to be finite: MPI_MAX need not keep a NaN).
template <size_t N>
std::array<double, N> MaxRanks(MPI_Comm comm, const std::array<double, N>& local) {
  std::array<double, N> out{};
  MPI_Allreduce(local.data(), out.data(), static_cast<int>(N), MPI_DOUBLE, MPI_MAX, comm);
  return out;
}

// ---- Vec and Mat helpers -------------------------------------------------------------
class OwnedVec {
 public:
  OwnedVec() = default;
  ~OwnedVec() {
    if (v_) VecDestroy(&v_);
  }
  OwnedVec(const OwnedVec&) = delete;
  OwnedVec& operator=(const OwnedVec&) = delete;
  void DuplicateOf(Vec layout) { NCP_PETSC_CHECK(VecDuplicate(layout, &v_)); }
  void Adopt(Vec v) {  // owned from now on
    if (v_) VecDestroy(&v_);
    v_ = v;
  }
  void Create(MPI_Comm comm, PetscInt local_size) {
    NCP_PETSC_CHECK(VecCreate(comm, &v_));
    NCP_PETSC_CHECK(VecSetSizes(v_, local_size, PETSC_DETERMINE));
    NCP_PETSC_CHECK(VecSetType(v_, VECSTANDARD));
  }
  operator Vec() const { return v_; }
  void Swap(OwnedVec& other) { std::swap(v_, other.v_); }

 private:
  Vec v_ = nullptr;
};

// Read access to the local part of a Vec for the lifetime of the object.
class LocalRead {
 public:
  explicit LocalRead(Vec v) : v_(v) { NCP_PETSC_CHECK(VecGetArrayRead(v_, &a_)); }
  ~LocalRead() { VecRestoreArrayRead(v_, &a_); }
  double operator[](PetscInt i) const { return PetscRealPart(a_[i]); }

 private:
  Vec v_;
  const PetscScalar* a_ = nullptr;
};
class LocalWrite {
 public:
  explicit LocalWrite(Vec v) : v_(v) { NCP_PETSC_CHECK(VecGetArray(v_, &a_)); }
  ~LocalWrite() { VecRestoreArray(v_, &a_); }
  PetscScalar& operator[](PetscInt i) { return a_[i]; }

 private:
  Vec v_;
  PetscScalar* a_ = nullptr;
};

// Whether every entry of the rank's part of v is finite (no reduction).
inline bool LocallyFinite(Vec v) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  LocalRead a(v);
  for (PetscInt i = 0; i < n; ++i)
    if (!std::isfinite(a[i])) return false;
  return true;
}
inline bool AllFinite(MPI_Comm comm, Vec v) { return !AnyRank(comm, !LocallyFinite(v)); }

// max |v_i| over the rank's entries (no reduction; exact, as VecNorm's local part);
// +inf when an entry is NaN.
inline double LocalNormInf(Vec v) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  LocalRead a(v);
  double largest = 0.0;
  for (PetscInt i = 0; i < n; ++i) {
    const double value = std::abs(a[i]);
    if (!(value <= largest))  // also NaN, which becomes +inf (MPI_MAX may drop a NaN)
      largest = std::isnan(value) ? std::numeric_limits<double>::infinity() : value;
  }
  return largest;
}

inline double NormInf(Vec v) {
  PetscReal norm = 0.0;
  NCP_PETSC_CHECK(VecNorm(v, NORM_INFINITY, &norm));
  return norm;
}
inline double Dot(Vec a, Vec b) {
  PetscScalar dot = 0.0;
  NCP_PETSC_CHECK(VecDot(a, b, &dot));
  return PetscRealPart(dot);
}

// a'b and ||v|| (of `type`) in one MPI_Allreduce by PETSc's split phase: each Begin
// computes its local part with the kernel of VecDot / VecNorm, the first End reduces
// both, so the values are those of VecDot and VecNorm. (No Vec may change between Begin
// and End: VecNormEnd caches the norm on the Vec.)
inline std::pair<double, double> DotAndNorm(Vec a, Vec b, Vec v, NormType type) {
  PetscScalar dot = 0.0;
  PetscReal norm = 0.0;
  NCP_PETSC_CHECK(VecDotBegin(a, b, &dot));
  NCP_PETSC_CHECK(VecNormBegin(v, type, &norm));
  NCP_PETSC_CHECK(VecDotEnd(a, b, &dot));
  NCP_PETSC_CHECK(VecNormEnd(v, type, &norm));
  return {PetscRealPart(dot), norm};
}

inline bool IsAij(Mat M, bool* parallel) {
  PetscBool seq = PETSC_FALSE, mpi = PETSC_FALSE;
  NCP_PETSC_CHECK(
      PetscObjectBaseTypeCompare(reinterpret_cast<PetscObject>(M), MATSEQAIJ, &seq));
  NCP_PETSC_CHECK(
      PetscObjectBaseTypeCompare(reinterpret_cast<PetscObject>(M), MATMPIAIJ, &mpi));
  *parallel = mpi == PETSC_TRUE;
  return seq == PETSC_TRUE || mpi == PETSC_TRUE;
}

// Calls f(value&) for every stored entry of the local rows of an AIJ matrix (the diagonal
// and off-diagonal blocks of MPIAIJ); read only (f(const value&)) when !kWrite.
template <bool kWrite, class Function>
void ForEachLocalValue(Mat M, Function&& f) {
  bool parallel = false;
  if (!IsAij(M, &parallel))
    throw std::invalid_argument(
        "ncp::petsc::Solver: the Jacobian matrix must be of type AIJ "
        "(MATSEQAIJ or MATMPIAIJ)");
  Mat blocks[2] = {M, nullptr};
  if (parallel) NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &blocks[0], &blocks[1], nullptr));
  for (Mat block : blocks) {
    if (!block) continue;
    MatInfo info;
    NCP_PETSC_CHECK(MatGetInfo(block, MAT_LOCAL, &info));
    const auto count = static_cast<PetscInt>(info.nz_used);
    if constexpr (kWrite) {
      PetscScalar* values = nullptr;
      NCP_PETSC_CHECK(MatSeqAIJGetArray(block, &values));
      for (PetscInt k = 0; k < count; ++k) f(values[k]);
      NCP_PETSC_CHECK(MatSeqAIJRestoreArray(block, &values));
    } else {
      const PetscScalar* values = nullptr;
      NCP_PETSC_CHECK(MatSeqAIJGetArrayRead(block, &values));
      for (PetscInt k = 0; k < count; ++k) f(values[k]);
      NCP_PETSC_CHECK(MatSeqAIJRestoreArrayRead(block, &values));
    }
  }
}

inline void DestroyMat(Mat* M) {
  if (*M) MatDestroy(M);
  *M = nullptr;
}

}  // namespace ncp::petsc
