// Shared-memory parallel loops (OpenMP) with results that do not depend on the number of
// threads: every output entry is written by exactly one thread, in the same order of
// floating-point operations as the serial loop. Without OpenMP everything runs serially.
#pragma once

#include <Eigen/SparseCore>
#include <algorithm>

namespace contact::internal {

/// Runs f(i) for i in [begin, end), split into contiguous chunks over the threads, or
/// serially when there are fewer than `serial_below` iterations (starting the threads
/// costs more than small loops, and idle threads spinning afterwards slow the serial code
/// on a busy machine). f must write only to locations that belong to i.
template <class F>
void ParallelFor(long begin, long end, long serial_below, const F& f) {
  if (end - begin < serial_below) {
    for (long i = begin; i < end; ++i) f(i);
    return;
  }
#pragma omp parallel for schedule(static)
  for (long i = begin; i < end; ++i) f(i);
}

/// y = A x for a symmetric A stored by columns (Eigen's default): y_i = sum_j A_ji x_j is
/// the dot product of column i with x, so rows are independent and need no reduction. The
/// product is bit-for-bit that of the serial loop for any number of threads. Small
/// matrices (< 20000 rows) run serially: the fork costs more than it saves.
inline void SymmetricMultiply(const Eigen::SparseMatrix<double>& A,
                              const Eigen::VectorXd& x, Eigen::VectorXd* y) {
  const long n = A.cols();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* values = A.valuePtr();
  y->resize(n);
  double* out = y->data();
  const double* in = x.data();
  const int* counts = A.innerNonZeroPtr();  // null when compressed
  auto row = [&](long i) {
    double sum = 0.0;
    const int end = counts ? outer[i] + counts[i] : outer[i + 1];
    for (int k = outer[i]; k < end; ++k) sum += values[k] * in[inner[k]];
    out[i] = sum;
  };
  ParallelFor(0, n, 20000, row);
}

/// Whether A equals its transpose to `relative_tolerance` times its largest entry (O(nnz
/// log), no allocation; inner indices sorted, as Eigen keeps them).
inline bool IsSymmetric(const Eigen::SparseMatrix<double>& A, double relative_tolerance) {
  if (A.rows() != A.cols()) return false;
  const int* outer = A.outerIndexPtr();
  const int* counts = A.innerNonZeroPtr();  // null when compressed
  auto end_of = [&](long j) { return counts ? outer[j] + counts[j] : outer[j + 1]; };
  const int* inner = A.innerIndexPtr();
  const double* values = A.valuePtr();
  double largest = 0.0;
  for (long j = 0; j < A.cols(); ++j)
    for (int k = outer[j]; k < end_of(j); ++k)
      largest = std::max(largest, std::abs(values[k]));
  const double tolerance = relative_tolerance * largest;
  for (long j = 0; j < A.cols(); ++j)
    for (int k = outer[j]; k < end_of(j); ++k) {
      const int i = inner[k];
      // A_ij: look for row j in column i.
      const int* begin = inner + outer[i];
      const int* end = inner + end_of(i);
      const int* it = std::lower_bound(begin, end, static_cast<int>(j));
      const double transposed = (it != end && *it == j) ? values[it - inner] : 0.0;
      if (std::abs(transposed - values[k]) > tolerance) return false;
    }
  return true;
}

}  // namespace contact::internal
