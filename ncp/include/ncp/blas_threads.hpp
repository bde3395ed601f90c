/// \file blas_threads.hpp
/// The thread count of the BLAS library the process runs with, set for a scope.
///
/// The sparse factorizations (UMFPACK, CHOLMOD, SPQR) call BLAS on small dense fronts; a
/// threaded OpenBLAS then wakes its threads for every call, and between calls they spin
/// (sched_yield) instead of sleeping - system time that grows with the number of calls
/// and costs every other process on the machine. ncp::Solver therefore runs its solves
/// with Options::blas_threads (1 by default).
///
/// The BLAS is found at run time (Debian's libblas.so.3 may be OpenBLAS or the reference
/// BLAS): OpenBLAS's openblas_get_num_threads / openblas_set_num_threads looked up in the
/// process, so there is no link dependency. With any other BLAS the guard does nothing
/// (BlasThreadsAdjustable() is false).
///
/// The count is a process-wide setting. Guards may nest and live in several threads at
/// once: the first one saves the count, each one lowers it to its own request if that is
/// smaller, the last one to end restores the saved count.
#pragma once

namespace ncp {

/// True when the BLAS's thread count can be read and set (OpenBLAS found in the process).
bool BlasThreadsAdjustable();

/// The BLAS's current thread count, or -1 when it cannot be read.
int BlasThreads();

/// At most `threads` BLAS threads while alive (threads >= 1; a smaller count already set
/// is kept); threads = 0 changes nothing. Throws std::invalid_argument for threads < 0.
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int threads);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  bool engaged_ = false;  ///< this guard counts in the process-wide nesting depth
};

}  // namespace ncp
