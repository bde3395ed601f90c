#include "ncp/fc/io.hpp"

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

#include "ncp/fc/global.hpp"
#include "ncp_fc_config.hpp"

#if NCP_FC_HAVE_HDF5
#include "fclib_hdf5.hpp"
#endif

namespace ncp::fc {

namespace {

/// Whitespace-separated numbers (and, in CSparse's printout, words) of a text file, read
/// one at a time with context in errors.
class NumberStream {
 public:
  explicit NumberStream(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw std::runtime_error("cannot open '" + path + "'");
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    // A number takes at least one character and a separator: no count of numbers still to
    // come can exceed half the file's size (and n = dimension x contacts stays an int).
    max_count_ =
        error ? 0 : static_cast<int>(std::min<std::uintmax_t>(bytes / 2, kMaxInt / 3));
  }
  const std::string& path() const { return path_; }
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
                               std::to_string(min_value) + ", " +
                               std::to_string(max_value) + "], got " + Format(v));
    return static_cast<int>(v);
  }
  /// The next whitespace-separated word, which must equal `expected` (CSparse's labels).
  void Expect(const char* expected) {
    std::string word;
    if (!(in_ >> word) || word != expected)
      throw std::runtime_error("'" + path_ + "': expected '" + expected +
                               "' in the CSparse " + "matrix printout, got '" + word +
                               "'");
  }
  /// How many whitespace-separated words are left, counting at most `limit`.
  int WordsLeft(int limit) {
    std::string word;
    int count = 0;
    while (count < limit && in_ >> word) ++count;
    return count;
  }
  /// The rest of the current line (without its newline).
  std::string Line() {
    std::string line;
    std::getline(in_, line);
    return line;
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

/// Cumulative block sizes (Siconos blocksize0/1): strictly increasing, the last one
/// `size` (the matrix's rows or columns).
std::vector<int> ReadCumulativeSizes(NumberStream& in, const char* what, int count,
                                     int size) {
  std::vector<int> end(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k)
    end[k] = in.NextInt(what, k == 0 ? 1 : end[k - 1] + 1, size);
  if (end.back() != size)
    in.Fail(std::string("sparse-block matrix with ") + std::to_string(size) +
            " rows/columns: its " + what + " end at " + std::to_string(end.back()));
  return end;
}

using Triplets = std::vector<Eigen::Triplet<double>>;

void ReadDense(NumberStream& in, int rows, int cols, Triplets* entries) {
  const int m = in.NextInt("dense rows", 0), n = in.NextInt("dense columns", 0);
  if (m != rows || n != cols)
    throw std::runtime_error("'" + in.path() + "': dense matrix stated " +
                             std::to_string(rows) + " x " + std::to_string(cols) +
                             ", its data says " + std::to_string(m) + " x " +
                             std::to_string(n));
  for (int j = 0; j < cols; ++j)  // column by column
    for (int i = 0; i < rows; ++i) {
      const double w = in.Next("a dense entry");
      if (w != 0.0) entries->emplace_back(i, j, w);
    }
}

void ReadSparseBlock(NumberStream& in, int rows, int cols, Triplets* entries) {
  const int num_blocks = in.NextCount("nbblocks", 0);
  if (num_blocks == 0) return;
  const int block_rows = in.NextInt("blocknumber0", 1, std::max(rows, 1)),
            block_cols = in.NextInt("blocknumber1", 1, std::max(cols, 1));
  const std::vector<int> row_end =
                             ReadCumulativeSizes(in, "blocksize0", block_rows, rows),
                         col_end =
                             ReadCumulativeSizes(in, "blocksize1", block_cols, cols);
  const int filled1 = in.NextCount("filled1", 1), filled2 = in.NextCount("filled2", 0);
  if (filled1 != block_rows + 1 || filled2 != num_blocks)
    throw std::runtime_error("sparse-block W: filled1 = " + std::to_string(filled1) +
                             " (expected " + std::to_string(block_rows + 1) +
                             "), filled2 = " + std::to_string(filled2) + " (expected " +
                             std::to_string(num_blocks) + ")");
  // Block-row pointers: from 0, non-decreasing, up to nbblocks.
  std::vector<int> row_ptr(filled1), block_col(filled2);
  for (int k = 0; k < filled1; ++k)
    row_ptr[k] =
        in.NextInt("index1_data", k == 0 ? 0 : row_ptr[k - 1], k == 0 ? 0 : num_blocks);
  if (row_ptr.back() != num_blocks)
    in.Fail("sparse-block W: the last block-row pointer is " +
            std::to_string(row_ptr.back()) +
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

/// Siconos' storage 2 (NumericsSparseMatrix, NSM_write_in_file): its origin (1 triplet,
/// 2 CSC, 3 CSR, 4 half triplet), then CSparse's printout (cs_print / Siconos'
/// CSparseMatrix_print_in_file): a version line, "[triplet: |csr: ]M-by-N, nzmax: Z
/// nnz: K[, 1-norm: x]", then either K lines "i j : x" (triplet) or per column (row)
/// "col j : locations a to b" followed by b - a + 1 lines "i : x". Values are printed
/// with 6 significant digits (%g).
void ReadCompressedSparse(NumberStream& in, int rows, int cols, Triplets* entries) {
  const int origin =
      in.NextInt("the sparse origin (1 triplet, 2 CSC, 3 CSR, 4 half triplet)", 1);
  if (origin > 4)
    throw std::runtime_error("'" + in.path() + "': sparse origin " +
                             std::to_string(origin) +
                             " unknown (1 triplet, 2 CSC, 3 CSR, 4 half triplet)");
  in.Line();  // the rest of the origin's line
  const std::string version = in.Line();
  const std::string header = in.Line();
  const auto by = header.find("-by-");
  const auto nnz_at = header.find("nnz:");
  if (version.find("CSparse") == std::string::npos || by == std::string::npos ||
      nnz_at == std::string::npos)
    throw std::runtime_error("'" + in.path() +
                             "': expected CSparse's printout of a sparse " +
                             "matrix (version line, 'M-by-N, nzmax: Z nnz: K'), got '" +
                             version + "' / '" + header + "'");
  const auto size_start = header.find_last_of(' ', by) == std::string::npos
                              ? 0
                              : header.find_last_of(' ', by) + 1;
  const int m = std::stoi(header.substr(size_start, by - size_start));
  const int n = std::stoi(header.substr(by + 4));
  const long nnz = std::stol(header.substr(nnz_at + 4));
  if (m != rows || n != cols)
    throw std::runtime_error("'" + in.path() + "': sparse matrix stated " +
                             std::to_string(rows) + " x " + std::to_string(cols) +
                             ", CSparse's header says " + std::to_string(m) + " x " +
                             std::to_string(n));
  auto add = [&](int i, int j, double x) {
    if (i < 0 || i >= rows || j < 0 || j >= cols)
      throw std::runtime_error("'" + in.path() + "': sparse entry (" + std::to_string(i) +
                               ", " + std::to_string(j) + ") outside " +
                               std::to_string(rows) + " x " + std::to_string(cols));
    if (x != 0.0) entries->emplace_back(i, j, x);
  };
  const bool triplet = origin == 1 || origin == 4;
  long read = 0;
  while (read < nnz) {
    if (triplet) {
      const int i = in.NextInt("a triplet row", 0), j = in.NextInt("a triplet column", 0);
      in.Expect(":");
      add(i, j, in.Next("a triplet value"));
      if (origin == 4 && i != j) add(j, i, entries->back().value());  // half: symmetric
      ++read;
      continue;
    }
    in.Expect(origin == 2 ? "col" : "row");
    const int outer = in.NextInt(origin == 2 ? "a column index" : "a row index", 0);
    in.Expect(":");
    in.Expect("locations");
    const long first = in.NextCount("a first location", 0);
    in.Expect("to");
    const long last = in.NextCount("a last location", -1);
    for (long k = first; k <= last; ++k, ++read) {
      const int inner = in.NextInt("an inner index", 0);
      in.Expect(":");
      const double x = in.Next("a sparse value");
      if (origin == 2)
        add(inner, outer, x);
      else
        add(outer, inner, x);
    }
  }
}

/// A matrix in Siconos' NumericsMatrix text form (NM_write_in_file): storage (0 dense,
/// 1 sparse-block, 2 sparse), rows, columns, then the storage's data.
SparseMatrix ReadNumericsMatrix(NumberStream& in, const char* name) {
  const int storage = in.NextInt("the storage type", 0);
  const int rows = in.NextCount("the matrix rows", 0),
            cols = in.NextCount("the matrix columns", 0);
  Triplets entries;
  if (storage == 0) {
    ReadDense(in, rows, cols, &entries);
  } else if (storage == 1) {
    ReadSparseBlock(in, rows, cols, &entries);
  } else if (storage == 2) {
    ReadCompressedSparse(in, rows, cols, &entries);
  } else {
    throw std::runtime_error("'" + in.path() + "': storage type " +
                             std::to_string(storage) + " of " + name +
                             " not supported (0 dense, 1 sparse-block, 2 sparse)");
  }
  SparseMatrix A(rows, cols);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

Vector ReadVector(NumberStream& in, Eigen::Index size, const char* what) {
  Vector v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = in.Next(what);
  return v;
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
  p.W = ReadNumericsMatrix(in, "W");
  if (p.W.rows() != n || p.W.cols() != n)
    throw std::runtime_error("'" + path + "': W must be " + std::to_string(n) + " x " +
                             std::to_string(n) + ", the file says " +
                             std::to_string(p.W.rows()) + " x " +
                             std::to_string(p.W.cols()) + " (a global problem, M " +
                             "first? Read it as one: fc-solve --global)");
  p.q = ReadVector(in, n, "q");
  p.mu.resize(p.num_contacts);
  for (int a = 0; a < p.num_contacts; ++a) p.mu[a] = in.Next("mu");
  // Siconos' text files do not state their form: a global problem (M, H, q, b, mu) read
  // as a local one would parse as a smaller, wrong problem and leave its data behind.
  // (Files written by older Siconos versions end in one more integer after mu: allowed.)
  if (in.WordsLeft(2) > 1)
    throw std::runtime_error(
        "'" + path + "': data left after mu of a local problem with " +
        std::to_string(p.num_contacts) + " contacts: is it a global " +
        "problem (M, H, q, b, mu)? Read it as one (fc-solve --global)");
  p.Validate();
  return p;
}

GlobalFrictionProblem ReadSiconosGlobalDat(const std::string& path) {
  NumberStream in(path);
  GlobalFrictionProblem g;
  g.name = path.substr(path.find_last_of('/') + 1);
  g.dimension = in.NextInt("the dimension", 2, 3);
  g.num_contacts = in.NextCount("the number of contacts", 0);
  g.M = ReadNumericsMatrix(in, "M");
  g.H = ReadNumericsMatrix(in, "H");
  if (g.M.rows() != g.M.cols() || g.H.rows() != g.M.rows() || g.H.cols() != g.size())
    throw std::runtime_error(
        "'" + path + "': a global problem needs M n x n and H n x m (m = " +
        std::to_string(g.size()) + " = dimension x contacts), the file has M " +
        std::to_string(g.M.rows()) + " x " + std::to_string(g.M.cols()) + ", H " +
        std::to_string(g.H.rows()) + " x " + std::to_string(g.H.cols()) +
        " (is it a local problem? then read it without --global)");
  g.q = ReadVector(in, g.M.rows(), "q");
  g.b = ReadVector(in, g.H.cols(), "b");
  g.mu = ReadVector(in, g.num_contacts, "mu");
  g.Validate();
  return g;
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

namespace {
bool IsHdf5(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  char signature[4] = {0, 0, 0, 0};
  in.read(signature, 4);
  return in.gcount() == 4 && signature[0] == '\x89' && signature[1] == 'H' &&
         signature[2] == 'D' && signature[3] == 'F';
}
}  // namespace

GlobalFrictionProblem ReadGlobalProblem(const std::string& path) {
  return IsHdf5(path) ? ReadFclibGlobal(path) : ReadSiconosGlobalDat(path);
}

bool HaveFclib() { return NCP_FC_HAVE_HDF5 != 0; }

#if !NCP_FC_HAVE_HDF5

FrictionProblem ReadFclib(const std::string& path) {
  throw std::runtime_error("'" + path + "': built without HDF5 (Debian libhdf5-dev)");
}
GlobalFrictionProblem ReadFclibGlobal(const std::string& path) {
  throw std::runtime_error("'" + path + "': built without HDF5 (Debian libhdf5-dev)");
}
bool IsFclibGlobal(const std::string&) { return false; }
std::optional<Vector> ReadFclibSolution(const std::string&) { return std::nullopt; }

#else

namespace {

/// FCLIB's global problem M v = H r + f, u = H' v + w in Siconos' names (q = f, b = w).
GlobalFrictionProblem ToGlobal(const internal::FclibGlobal& g, const std::string& path) {
  if (g.G && g.G->cols > 0)
    throw std::runtime_error("'" + path +
                             "': global problem with equality constraints G " +
                             "is not supported");
  GlobalFrictionProblem p;
  p.name = path.substr(path.find_last_of('/') + 1);
  p.M = g.M.ToSparse();
  p.H = g.H.ToSparse();
  p.dimension = g.spacedim;
  p.num_contacts = static_cast<int>(p.H.cols()) / g.spacedim;
  p.q = g.f;
  p.b = g.w;
  p.mu = g.mu;
  return p;
}

FrictionProblem FromLocal(const internal::FclibLocal& local, const std::string& path) {
  if (local.R && local.R->rows > 0)
    throw std::runtime_error("'" + path +
                             "': local problem with constraints R not supported");
  FrictionProblem p;
  p.dimension = local.spacedim;
  p.W = local.W.ToSparse();
  p.num_contacts = static_cast<int>(p.W.rows()) / local.spacedim;
  p.q = local.q;
  p.mu = local.mu;
  return p;
}

}  // namespace

FrictionProblem ReadFclib(const std::string& path) {
  FrictionProblem p;
  switch (internal::ReadFclibKind(path)) {
    case internal::FclibKind::kLocal:
      p = FromLocal(internal::ReadFclibLocalGroup(path), path);
      break;
    case internal::FclibKind::kGlobal:
      p = ReduceToLocal(ToGlobal(internal::ReadFclibGlobalGroup(path), path));
      break;
    case internal::FclibKind::kGlobalRolling:
      throw std::runtime_error("'" + path + "': FCLIB global rolling-friction problems " +
                               "are not supported");
    case internal::FclibKind::kNone:
      throw std::runtime_error("'" + path +
                               "': neither an FCLIB local nor global problem");
  }
  p.name = path.substr(path.find_last_of('/') + 1);
  p.Validate();
  return p;
}

bool IsFclibGlobal(const std::string& path) {
  return IsHdf5(path) && internal::ReadFclibKind(path) == internal::FclibKind::kGlobal;
}

GlobalFrictionProblem ReadFclibGlobal(const std::string& path) {
  GlobalFrictionProblem p = ToGlobal(internal::ReadFclibGlobalGroup(path), path);
  p.Validate();
  return p;
}

std::optional<Vector> ReadFclibSolution(const std::string& path) {
  const auto solution = internal::ReadFclibSolutionGroup(path);
  if (!solution) return std::nullopt;
  return solution->r;
}

#endif

}  // namespace ncp::fc
