#include "ncp/fc/io.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "ncp_fc_config.hpp"

#if NCP_FC_HAVE_FCLIB
#include <hdf5.h>
extern "C" {  // fclib.h has no C++ guards
#include <fclib.h>
}
#endif

namespace ncp::fc {

namespace {

/// Whitespace-separated numbers of a text file, read one at a time with context in
/// errors.
class NumberStream {
 public:
  explicit NumberStream(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw std::runtime_error("cannot open '" + path + "'");
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    // A number takes at least one character and a separator: no count of numbers still to
    // come can exceed half the file's size (and n = dimension x contacts stays an int).
    max_count_ = error ? 0 : static_cast<int>(std::min<std::uintmax_t>(bytes / 2, kMaxInt / 3));
  }
  double Next(const char* what) {
    double value;
    if (!(in_ >> value))
      throw std::runtime_error("'" + path_ + "': expected a number for " + what +
                               " (number " + std::to_string(count_ + 1) +
                               " in the file)");
    ++count_;
    return value;
  }
  /// An integer in [min_value, max_value] (range-checked as a double before the cast).
  int NextInt(const char* what, int min_value, int max_value = kMaxInt) {
    const double v = Next(what);
    if (!(v >= min_value && v <= max_value) || v != std::floor(v))
      throw std::runtime_error("'" + path_ + "': " + what + " must be an integer in [" +
                               std::to_string(min_value) + ", " + std::to_string(max_value) +
                               "], got " + Format(v));
    return static_cast<int>(v);
  }
  /// The number of items the file still has to hold (at most max_count_, see above).
  int NextCount(const char* what, int min_value) {
    return NextInt(what, min_value, std::max(min_value, max_count_));
  }
  static std::string Format(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error("'" + path_ + "': " + what);
  }

 private:
  std::string path_;
  std::ifstream in_;
  long count_ = 0;
  int max_count_ = 0;
  static constexpr int kMaxInt = std::numeric_limits<int>::max();
};

/// Cumulative block sizes (Siconos blocksize0/1): strictly increasing, the last one n.
std::vector<int> ReadCumulativeSizes(NumberStream& in, const char* what, int count, int n) {
  std::vector<int> end(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) {
    end[k] = in.NextInt(what, k == 0 ? 1 : end[k - 1] + 1, n);
  }
  if (end.back() != n)
    in.Fail(std::string("sparse-block W must be ") + std::to_string(n) + " x " + std::to_string(n) +
            ", its " + what + " end at " + std::to_string(end.back()));
  return end;
}

void ReadDense(NumberStream& in, int n, std::vector<Eigen::Triplet<double>>* entries) {
  const int m = in.NextInt("dense rows", 0), cols = in.NextInt("dense columns", 0);
  if (m != n || cols != n)
    throw std::runtime_error("dense W must be " + std::to_string(n) + " x " +
                             std::to_string(n) + ", the file says " + std::to_string(m) +
                             " x " + std::to_string(cols));
  for (int j = 0; j < n; ++j)  // column by column
    for (int i = 0; i < n; ++i) {
      const double w = in.Next("a dense entry of W");
      if (w != 0.0) entries->emplace_back(i, j, w);
    }
}

void ReadSparseBlock(NumberStream& in, int n,
                     std::vector<Eigen::Triplet<double>>* entries) {
  const int num_blocks = in.NextCount("nbblocks", 0);
  if (num_blocks == 0) return;
  const int block_rows = in.NextInt("blocknumber0", 1, n),
            block_cols = in.NextInt("blocknumber1", 1, n);
  const std::vector<int> row_end = ReadCumulativeSizes(in, "blocksize0", block_rows, n),
                         col_end = ReadCumulativeSizes(in, "blocksize1", block_cols, n);
  const int filled1 = in.NextCount("filled1", 1), filled2 = in.NextCount("filled2", 0);
  if (filled1 != block_rows + 1 || filled2 != num_blocks)
    throw std::runtime_error("sparse-block W: filled1 = " + std::to_string(filled1) +
                             " (expected " + std::to_string(block_rows + 1) +
                             "), filled2 = " + std::to_string(filled2) + " (expected " +
                             std::to_string(num_blocks) + ")");
  // Block-row pointers: from 0, non-decreasing, up to nbblocks.
  std::vector<int> row_ptr(filled1), block_col(filled2);
  for (int k = 0; k < filled1; ++k)
    row_ptr[k] = in.NextInt("index1_data", k == 0 ? 0 : row_ptr[k - 1], k == 0 ? 0 : num_blocks);
  if (row_ptr.back() != num_blocks)
    in.Fail("sparse-block W: the last block-row pointer is " + std::to_string(row_ptr.back()) +
            ", expected nbblocks = " + std::to_string(num_blocks));
  for (int& v : block_col) v = in.NextInt("index2_data", 0, block_cols - 1);
  for (int br = 0; br < block_rows; ++br) {
    const int r0 = br == 0 ? 0 : row_end[br - 1], nr = row_end[br] - r0;
    for (int b = row_ptr[br]; b < row_ptr[br + 1]; ++b) {
      if (b >= num_blocks || block_col[b] >= block_cols)
        throw std::runtime_error("sparse-block W: block index out of range");
      if (in.NextInt("block number", 0) != b)
        throw std::runtime_error("sparse-block W: blocks out of order at block " +
                                 std::to_string(b));
      const int bc = block_col[b];
      const int c0 = bc == 0 ? 0 : col_end[bc - 1], nc = col_end[bc] - c0;
      for (int j = 0; j < nc; ++j)
        for (int i = 0; i < nr; ++i) {
          const double w = in.Next("a block entry of W");
          if (w != 0.0) entries->emplace_back(r0 + i, c0 + j, w);
        }
    }
  }
}

}  // namespace

FrictionProblem ReadSiconosDat(const std::string& path) {
  NumberStream in(path);
  FrictionProblem p;
  p.name = path.substr(path.find_last_of('/') + 1);
  p.dimension = in.NextInt("the dimension", 2, 3);
  if (p.dimension > 3)
    throw std::runtime_error("'" + path + "': dimension must be 2 or 3");
  p.num_contacts = in.NextCount("the number of contacts", 0);
  const int n = p.size();
  const int storage = in.NextInt("the storage type", 0);
  const int size0 = in.NextInt("the matrix rows", 0),
            size1 = in.NextInt("the matrix columns", 0);
  if (size0 != n || size1 != n)
    throw std::runtime_error("'" + path + "': W must be " + std::to_string(n) + " x " +
                             std::to_string(n) + ", the file says " +
                             std::to_string(size0) + " x " + std::to_string(size1));
  std::vector<Eigen::Triplet<double>> entries;
  if (storage == 0) {
    ReadDense(in, n, &entries);
  } else if (storage == 1) {
    ReadSparseBlock(in, n, &entries);
  } else {
    throw std::runtime_error("'" + path + "': storage type " + std::to_string(storage) +
                             " not supported (0 dense, 1 sparse-block)");
  }
  p.W.resize(n, n);
  p.W.setFromTriplets(entries.begin(), entries.end());
  p.q.resize(n);
  for (int i = 0; i < n; ++i) p.q[i] = in.Next("q");
  p.mu.resize(p.num_contacts);
  for (int a = 0; a < p.num_contacts; ++a) p.mu[a] = in.Next("mu");
  p.Validate();
  return p;
}

void WriteSiconosDat(const FrictionProblem& p, const std::string& path) {
  p.Validate();
  const int d = p.dimension, nc = p.num_contacts, n = p.size();
  // block (row, col) -> d x d entries, column by column; block rows in order
  std::vector<std::map<int, std::vector<double>>> rows(nc);
  for (int k = 0; k < p.W.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(p.W, k); it; ++it) {
      auto& block = rows[it.row() / d][static_cast<int>(it.col()) / d];
      block.resize(d * d, 0.0);
      block[(it.col() % d) * d + it.row() % d] = it.value();
    }
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
  out << std::setprecision(17) << d << '\n' << nc << "\n1\n" << n << ' ' << n << '\n';
  std::vector<int> row_ptr{0}, block_col;
  for (const auto& row : rows) {
    for (const auto& entry : row) block_col.push_back(entry.first);
    row_ptr.push_back(static_cast<int>(block_col.size()));
  }
  out << block_col.size() << '\n' << nc << ' ' << nc << '\n';
  for (int side = 0; side < 2; ++side) {  // cumulative block sizes, rows then columns
    for (int a = 1; a <= nc; ++a) out << a * d << ' ';
    out << '\n';
  }
  out << nc + 1 << ' ' << block_col.size() << '\n';
  for (int v : row_ptr) out << v << ' ';
  out << '\n';
  for (int v : block_col) out << v << ' ';
  out << '\n';
  int number = 0;
  for (const auto& row : rows)
    for (const auto& entry : row) {
      out << number++ << '\n';
      for (double w : entry.second) out << w << '\n';
    }
  for (int i = 0; i < n; ++i) out << p.q[i] << '\n';
  for (int a = 0; a < nc; ++a) out << p.mu[a] << '\n';
  if (!out) throw std::runtime_error("writing '" + path + "' failed");
}

FrictionProblem ReadProblem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  char signature[4] = {0, 0, 0, 0};
  in.read(signature, 4);
  if (in.gcount() == 4 && signature[0] == '\x89' && signature[1] == 'H' &&
      signature[2] == 'D' && signature[3] == 'F')
    return ReadFclib(path);
  return ReadSiconosDat(path);
}

bool HaveFclib() { return NCP_FC_HAVE_FCLIB != 0; }

#if !NCP_FC_HAVE_FCLIB

FrictionProblem ReadFclib(const std::string& path) {
  throw std::runtime_error("'" + path + "': built without FCLIB (Debian libfclib-dev)");
}
std::optional<Vector> ReadFclibSolution(const std::string&) { return std::nullopt; }

#else

namespace {

/// fclib_matrix (nz >= 0: triplets with p the columns; nz = -1: CSC; nz = -2: CSR), every
/// index checked against the sizes the file states (nzmax entries stored).
SparseMatrix ToSparse(const fclib_matrix& m) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("FCLIB matrix " + std::to_string(m.m) + " x " + std::to_string(m.n) +
                             " (nz " + std::to_string(m.nz) + ", nzmax " + std::to_string(m.nzmax) +
                             "): " + what);
  };
  if (m.m < 0 || m.n < 0 || m.nzmax < 0 || m.nz < -2) fail("negative size");
  if (m.nzmax > 0 && (!m.i || !m.x || !m.p)) fail("missing index or value arrays");
  std::vector<Eigen::Triplet<double>> entries;
  if (m.nz >= 0) {
    if (m.nz > m.nzmax) fail("more triplets than stored entries");
    for (int k = 0; k < m.nz; ++k) {
      if (m.i[k] < 0 || m.i[k] >= m.m || m.p[k] < 0 || m.p[k] >= m.n) fail("triplet index out of range");
      entries.emplace_back(m.i[k], m.p[k], m.x[k]);
    }
  } else {
    const bool csc = m.nz == -1;
    const int outer = csc ? m.n : m.m, inner = csc ? m.m : m.n;
    if (!m.p) fail("missing pointer array");
    if (m.p[0] != 0) fail("the first pointer is not 0");
    for (int o = 0; o < outer; ++o) {
      if (m.p[o + 1] < m.p[o] || m.p[o + 1] > m.nzmax) fail("pointers decrease or pass nzmax");
      for (int k = m.p[o]; k < m.p[o + 1]; ++k) {
        if (m.i[k] < 0 || m.i[k] >= inner) fail("index out of range");
        entries.emplace_back(csc ? m.i[k] : o, csc ? o : m.i[k], m.x[k]);
      }
    }
  }
  SparseMatrix A(m.m, m.n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

Vector ToVector(const double* x, int n) {
  if (!x) throw std::runtime_error("FCLIB: missing vector");
  return Eigen::Map<const Vector>(x, n);
}

/// Global to local: M v = H r + f, u = H' v + w  =>  u = H' M^-1 H r + (H' M^-1 f + w).
FrictionProblem ReduceGlobal(const fclib_global& g, const std::string& path) {
  if (g.G && g.G->n > 0)
    throw std::runtime_error("'" + path +
                             "': global problem with equality constraints G " +
                             "is not supported");
  const SparseMatrix M = ToSparse(*g.M), H = ToSparse(*g.H);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(M);
  if (ldlt.info() != Eigen::Success)
    throw std::runtime_error("'" + path +
                             "': the mass matrix M is not positive definite");
  const Eigen::MatrixXd MinvH = ldlt.solve(Eigen::MatrixXd(H));
  const Vector Minvf = ldlt.solve(ToVector(g.f, M.rows()));
  FrictionProblem p;
  p.dimension = g.spacedim;
  p.num_contacts = static_cast<int>(H.cols()) / g.spacedim;
  const Eigen::MatrixXd W = Eigen::MatrixXd(H.transpose()) * MinvH;
  p.W = W.sparseView();
  p.q = H.transpose() * Minvf + ToVector(g.w, H.cols());
  p.mu = ToVector(g.mu, p.num_contacts);
  return p;
}

/// Whether the HDF5 file has the top-level group (FCLIB writes "fclib_local" or
/// "fclib_global").
bool HasGroup(const std::string& path, const char* group) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // a failure is reported by the caller
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("'" + path + "': not a readable HDF5 file");
  const bool found = H5Lexists(file, group, H5P_DEFAULT) > 0;
  H5Fclose(file);
  return found;
}

}  // namespace

FrictionProblem ReadFclib(const std::string& path) {
  FrictionProblem p;
  const bool is_local = HasGroup(path, "fclib_local");
  if (fclib_local* local = is_local ? fclib_read_local(path.c_str()) : nullptr) {
    p.dimension = local->spacedim;
    p.W = ToSparse(*local->W);
    p.num_contacts = static_cast<int>(p.W.rows()) / local->spacedim;
    p.q = ToVector(local->q, p.W.rows());
    p.mu = ToVector(local->mu, p.num_contacts);
    const bool has_constraints = local->R && local->R->m > 0;
    fclib_delete_local(local);
    if (has_constraints)
      throw std::runtime_error("'" + path +
                               "': local problem with constraints R not supported");
  } else if (fclib_global* global = HasGroup(path, "fclib_global")
                                        ? fclib_read_global(path.c_str())
                                        : nullptr) {
    try {
      p = ReduceGlobal(*global, path);
    } catch (...) {
      fclib_delete_global(global);
      throw;
    }
    fclib_delete_global(global);
  } else {
    throw std::runtime_error("'" + path + "': neither an FCLIB local nor global problem");
  }
  p.name = path.substr(path.find_last_of('/') + 1);
  p.Validate();
  return p;
}

std::optional<Vector> ReadFclibSolution(const std::string& path) {
  if (!HasGroup(path, "fclib_local")) return std::nullopt;
  fclib_local* local = fclib_read_local(path.c_str());
  if (!local) return std::nullopt;
  const int m = local->W->m;
  fclib_delete_local(local);
  fclib_solution* s = fclib_read_solution(path.c_str());
  if (!s) return std::nullopt;
  std::optional<Vector> r;
  if (s->r) r = Eigen::Map<const Vector>(s->r, m);
  fclib_delete_solutions(s, 1);
  return r;
}

#endif

}  // namespace ncp::fc
