/// \file fclib_hdf5.hpp
/// A checked reader of FCLIB HDF5 files (FrictionalContactLibrary/fclib, src/fclib.h),
/// written against the HDF5 C API so that a malformed file ends in an exception, never in
/// exit() or an out-of-bounds read (libfclib's reader exits on an HDF5 error and sizes
/// its buffers from the file's own m, n, nz without looking at the datasets).
///
/// Layout read (group / dataset, every integer a 1-element dataset or a scalar):
///   /fclib_local:  spacedim, W/, [V/, R/], vectors/{q, mu, [s]}, [info/]
///   /fclib_global: spacedim, M/, H/, [G/], vectors/{f, w, mu, [b]}, [info/]
///   /solution:     [v], u, r, [l]
/// A matrix group holds nzmax, m, n, nz and p, i, x in CSparse's convention:
///   nz >= 0  triplets:       i row indices, p column indices, x values (nz each);
///   nz == -1 compressed col: p column pointers (n + 1), i row indices, x (nzmax each);
///   nz == -2 compressed row: p row pointers (m + 1), i column indices, x (nzmax each).
/// info/ holds the strings title, description, math_info (each optional).
///
/// Every dataset's type class, rank and length are checked against the sizes the FCLIB
/// equations imply (local: W m x m, m = spacedim n_c, q m, mu n_c, V m x p, R p x p, s p;
/// global: M n x n, H n x m, G n x p, f n, w m, mu n_c, b p); every index is
/// range-checked, compressed pointers start at 0, do not decrease and end at most at
/// nzmax; every value is finite. Failures throw std::runtime_error naming the file, the
/// dataset and the defect. HDF5's own error printing is off while a file is read; reading
/// is serialized by a mutex (Debian's serial HDF5 is not thread-safe).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ncp/types.hpp"

namespace ncp::fc::internal {

/// An FCLIB sparse matrix as stored: the arrays exactly as in the file, after the checks.
struct FclibMatrix {
  int rows = 0;   ///< m
  int cols = 0;   ///< n
  int nzmax = 0;  ///< allocated entries (compressed forms: length of i and x)
  int nz = 0;     ///< >= 0 number of triplets; -1 compressed columns; -2 compressed rows
  std::vector<int> p, i;
  std::vector<double> x;

  /// The matrix as Eigen's sparse type (duplicate entries summed, as CSparse does).
  SparseMatrix ToSparse() const;
};

/// The optional info group of a problem.
struct FclibInfo {
  std::optional<std::string> title, description, math_info;
};

/// FCLIB local problem: u = W r + V lambda + q, V' r + R lambda + s = 0, Coulomb law with
/// mu.
struct FclibLocal {
  int spacedim = 0;
  FclibMatrix W;
  std::optional<FclibMatrix> V, R;  ///< present together or not at all
  Vector q, mu;
  std::optional<Vector> s;  ///< present with R
  std::optional<FclibInfo> info;
};

/// FCLIB global problem: M v = H r + G lambda + f, G' v + b = 0, u = H' v + w, Coulomb
/// law.
struct FclibGlobal {
  int spacedim = 0;
  FclibMatrix M, H;
  std::optional<FclibMatrix> G;
  Vector f, w, mu;
  std::optional<Vector> b;  ///< present with G
  std::optional<FclibInfo> info;
};

/// The /solution group: v for global problems, u and r always, l with constraints.
struct FclibSolution {
  std::optional<Vector> v, l;
  Vector u, r;
};

enum class FclibKind { kLocal, kGlobal, kGlobalRolling, kNone };

/// Which top-level problem group the file holds (local preferred when several are).
/// Throws when the file is not a readable HDF5 file.
FclibKind ReadFclibKind(const std::string& path);

/// The local problem of the file; throws (file, dataset, defect) on anything malformed.
FclibLocal ReadFclibLocalGroup(const std::string& path);

/// The global problem of the file; throws (file, dataset, defect) on anything malformed.
FclibGlobal ReadFclibGlobalGroup(const std::string& path);

/// The /solution group, sized by the file's problem; std::nullopt when there is none.
/// Throws on a malformed solution or problem.
std::optional<FclibSolution> ReadFclibSolutionGroup(const std::string& path);

}  // namespace ncp::fc::internal
