#include "ncp/fc/io.hpp"

#include <Eigen/SparseCholesky>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "ncp_fc_config.hpp"

#if NCP_FC_HAVE_HDF5
#include "fclib_hdf5.hpp"
#endif

namespace ncp::fc {

namespace {

/// Whitespace-separated numbers of a text file, read one at a time with context in
/// errors.
class NumberStream {
 public:
  explicit NumberStream(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw std::runtime_error("cannot open '" + path + "'");
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
  int NextInt(const char* what, int min_value) {
    const double v = Next(what);
    if (v != static_cast<int>(v) || v < min_value)
      throw std::runtime_error("'" + path_ + "': " + what + " must be an integer >= " +
                               std::to_string(min_value) + ", got " + std::to_string(v));
    return static_cast<int>(v);
  }

 private:
  std::string path_;
  std::ifstream in_;
  long count_ = 0;
};

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
  const int num_blocks = in.NextInt("nbblocks", 0);
  if (num_blocks == 0) return;
  const int block_rows = in.NextInt("blocknumber0", 1),
            block_cols = in.NextInt("blocknumber1", 1);
  std::vector<int> row_end(block_rows), col_end(block_cols);  // cumulative sizes
  for (int& v : row_end) v = in.NextInt("blocksize0", 1);
  for (int& v : col_end) v = in.NextInt("blocksize1", 1);
  if (row_end.back() != n || col_end.back() != n)
    throw std::runtime_error("sparse-block W must be " + std::to_string(n) + " x " +
                             std::to_string(n) + ", its blocks cover " +
                             std::to_string(row_end.back()) + " x " +
                             std::to_string(col_end.back()));
  const int filled1 = in.NextInt("filled1", 1), filled2 = in.NextInt("filled2", 0);
  if (filled1 != block_rows + 1 || filled2 != num_blocks)
    throw std::runtime_error("sparse-block W: filled1 = " + std::to_string(filled1) +
                             " (expected " + std::to_string(block_rows + 1) +
                             "), filled2 = " + std::to_string(filled2) + " (expected " +
                             std::to_string(num_blocks) + ")");
  std::vector<int> row_ptr(filled1), block_col(filled2);
  for (int& v : row_ptr) v = in.NextInt("index1_data", 0);
  for (int& v : block_col) v = in.NextInt("index2_data", 0);
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
  p.dimension = in.NextInt("the dimension", 2);
  if (p.dimension > 3)
    throw std::runtime_error("'" + path + "': dimension must be 2 or 3");
  p.num_contacts = in.NextInt("the number of contacts", 0);
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

bool HaveFclib() { return NCP_FC_HAVE_HDF5 != 0; }

#if !NCP_FC_HAVE_HDF5

FrictionProblem ReadFclib(const std::string& path) {
  throw std::runtime_error("'" + path + "': built without HDF5 (Debian libhdf5-dev)");
}
std::optional<Vector> ReadFclibSolution(const std::string&) { return std::nullopt; }

#else

namespace {

/// Global to local: M v = H r + f, u = H' v + w  =>  u = H' M^-1 H r + (H' M^-1 f + w).
FrictionProblem ReduceGlobal(const internal::FclibGlobal& g, const std::string& path) {
  if (g.G && g.G->cols > 0)
    throw std::runtime_error("'" + path +
                             "': global problem with equality constraints G " +
                             "is not supported");
  const SparseMatrix M = g.M.ToSparse(), H = g.H.ToSparse();
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(M);
  if (ldlt.info() != Eigen::Success)
    throw std::runtime_error("'" + path +
                             "': the mass matrix M is not positive definite");
  const Eigen::MatrixXd MinvH = ldlt.solve(Eigen::MatrixXd(H));
  const Vector Minvf = ldlt.solve(g.f);
  FrictionProblem p;
  p.dimension = g.spacedim;
  p.num_contacts = static_cast<int>(H.cols()) / g.spacedim;
  const Eigen::MatrixXd W = Eigen::MatrixXd(H.transpose()) * MinvH;
  p.W = W.sparseView();
  p.q = H.transpose() * Minvf + g.w;
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
      p = ReduceGlobal(internal::ReadFclibGlobalGroup(path), path);
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

std::optional<Vector> ReadFclibSolution(const std::string& path) {
  const auto solution = internal::ReadFclibSolutionGroup(path);
  if (!solution) return std::nullopt;
  return solution->r;
}

#endif

}  // namespace ncp::fc
