// ncp::petsc::Solver: Algorithm 1 of the thesis (section 3.1), the globalized semismooth
// Newton method of De Luca, Facchinei and Kanzow (1996), over distributed PETSc Vec/Mat.
//
// The box MCP l <= x <= u perp F(x) is written row by row as the serial solver's mixed
// form (ncp/src/box_mcp.cpp):
//
//   free  (l = -inf, u = +inf): Phi_i = F_i(x)                J_i = F'_i
//   fixed (l = u):              Phi_i = x_i - l_i             J_i = e_i'
//   lower (l finite, u = +inf): Phi_i = phi(x_i - l_i, F_i)   J_i = da e_i' + db F'_i
//   upper (l = -inf, u finite): Phi_i = phi(u_i - x_i, -F_i)  J_i = -da e_i' - db F'_i
//   two-sided (l < u finite):   Phi_i = F_i(x) - w_k + v_k    J_i = F'_i - e_w' + e_v'
//                               Phi_w = phi(x_i - l_i, w_k)   J_w = da e_i' + db e_w'
//                               Phi_v = phi(u_i - x_i, v_k)   J_v = -da e_i' + db e_v'
//
// with the slack unknowns w_k, v_k (the positive and negative parts of F_i at a solution)
// of box_mcp.cpp. The unknowns are y = [x; w; v] rank by rank: each rank owns its rows of
// x followed by the slacks of its two-sided components, so the pair variable of every
// pair row is the row's own unknown and all rows of a component live on one rank. Without
// two-sided bounds y is x itself. The Newton matrix is
//
//   J = diag(c_F) G + diag(c_I) + (c_A at (w, i) and (v, i))
//
// with G = F' (columns renumbered for y, plus the constant -1, +1 of the split rows and 1
// at (w, w), (v, v)), assembled by MatCopy + MatDiagonalScale + MatDiagonalSet on the
// pattern of G.
//
// Every decision (z-vector rule, descent test, Armijo, restarts, stopping tests) is taken
// by the functions of ncp/src/globalization.hpp and ncp_function_internal.hpp, the serial
// solver's own, from norms and dot products reduced over the communicator: every rank
// takes the same decision, so no rank can wait in a collective call the others skipped.

#include "ncp/petsc/solver.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "globalization.hpp"
#include "ncp_function_internal.hpp"
#include "strategy.hpp"

namespace ncp::petsc {
namespace {

using Clock = std::chrono::steady_clock;
using internal::FormatNumber;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// A PETSc call of the solver itself failed (out of memory, a PETSc bug): not a numerical
// event of the iteration, so it is thrown, naming the call.
void Check(PetscErrorCode code, const char* call) {
  if (code != 0)
    throw std::runtime_error(std::string("ncp::petsc::Solver: ") + call +
                             " failed with PETSc error " +
                             std::to_string(static_cast<int>(code)));
}
#define NCP_PETSC_CHECK(call) Check((call), #call)

// ---- reductions over the communicator ------------------------------------------------
bool AnyRank(MPI_Comm comm, bool local) {
  int in = local ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, comm);
  return out != 0;
}
long long SumRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_SUM, comm);
  return out;
}
long long MinRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_MIN, comm);
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

bool AllFinite(MPI_Comm comm, Vec v) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  bool finite = true;
  {
    LocalRead a(v);
    for (PetscInt i = 0; i < n && finite; ++i) finite = std::isfinite(a[i]);
  }
  return !AnyRank(comm, !finite);
}

double NormInf(Vec v) {
  PetscReal norm = 0.0;
  NCP_PETSC_CHECK(VecNorm(v, NORM_INFINITY, &norm));
  return norm;
}
double Dot(Vec a, Vec b) {
  PetscScalar dot = 0.0;
  NCP_PETSC_CHECK(VecDot(a, b, &dot));
  return PetscRealPart(dot);
}

bool IsAij(Mat M, bool* parallel) {
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

void DestroyMat(Mat* M) {
  if (*M) MatDestroy(M);
  *M = nullptr;
}

// out = |M| v for an AIJ matrix M and a Vec v >= 0 laid out like M's columns, from M's
// own arrays (no copy of M): on each rank the rows of its diagonal block times its part
// of v plus the rows of its off-diagonal block times the ghost entries of v, gathered
// by a scatter made once for M's pattern (Prepare).
class AbsoluteProduct {
 public:
  ~AbsoluteProduct() { Clear(); }
  AbsoluteProduct() = default;
  AbsoluteProduct(const AbsoluteProduct&) = delete;
  AbsoluteProduct& operator=(const AbsoluteProduct&) = delete;

  // For M's pattern (again whenever it or M changes).
  void Prepare(Mat M) {
    Clear();
    bool parallel = false;
    if (!IsAij(M, &parallel))
      throw std::invalid_argument(
          "ncp::petsc::Solver: the Jacobian matrix must be of type AIJ "
          "(MATSEQAIJ or MATMPIAIJ)");
    if (!parallel) return;
    Mat diagonal = nullptr, off_diagonal = nullptr;
    const PetscInt* ghost_columns = nullptr;  // global columns of the off-diagonal block
    NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &diagonal, &off_diagonal, &ghost_columns));
    PetscInt rows = 0, ghosts = 0;
    NCP_PETSC_CHECK(MatGetSize(off_diagonal, &rows, &ghosts));
    IS columns = nullptr;
    NCP_PETSC_CHECK(ISCreateGeneral(PETSC_COMM_SELF, ghosts, ghost_columns,
                                    PETSC_COPY_VALUES, &columns));
    NCP_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, ghosts, &ghost_values_));
    Vec layout = nullptr;
    NCP_PETSC_CHECK(MatCreateVecs(M, &layout, nullptr));
    NCP_PETSC_CHECK(VecScatterCreate(layout, columns, ghost_values_, nullptr, &scatter_));
    VecDestroy(&layout);
    ISDestroy(&columns);
  }

  void Mult(Mat M, Vec v, Vec out) {
    bool parallel = false;
    IsAij(M, &parallel);
    Mat blocks[2] = {M, nullptr};
    if (parallel) {
      NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &blocks[0], &blocks[1], nullptr));
      NCP_PETSC_CHECK(
          VecScatterBegin(scatter_, v, ghost_values_, INSERT_VALUES, SCATTER_FORWARD));
      NCP_PETSC_CHECK(
          VecScatterEnd(scatter_, v, ghost_values_, INSERT_VALUES, SCATTER_FORWARD));
    }
    NCP_PETSC_CHECK(VecSet(out, 0.0));
    LocalWrite o(out);
    {
      LocalRead local(v);
      AddBlockProduct(blocks[0], local, o);
    }
    if (parallel) {
      LocalRead ghost(ghost_values_);
      AddBlockProduct(blocks[1], ghost, o);
    }
  }

 private:
  // o += |B| x for a sequential AIJ block B (CSR arrays read in place).
  static void AddBlockProduct(Mat B, const LocalRead& x, LocalWrite& o) {
    PetscInt rows = 0;
    const PetscInt *start = nullptr, *column = nullptr;
    PetscBool done = PETSC_FALSE;
    NCP_PETSC_CHECK(
        MatGetRowIJ(B, 0, PETSC_FALSE, PETSC_FALSE, &rows, &start, &column, &done));
    if (!done) throw std::runtime_error("ncp::petsc::Solver: MatGetRowIJ gave no rows");
    const PetscScalar* values = nullptr;
    NCP_PETSC_CHECK(MatSeqAIJGetArrayRead(B, &values));
    for (PetscInt i = 0; i < rows; ++i) {
      double sum = 0.0;
      for (PetscInt k = start[i]; k < start[i + 1]; ++k)
        sum += std::abs(PetscRealPart(values[k])) * x[column[k]];
      o[i] += sum;
    }
    NCP_PETSC_CHECK(MatSeqAIJRestoreArrayRead(B, &values));
    NCP_PETSC_CHECK(
        MatRestoreRowIJ(B, 0, PETSC_FALSE, PETSC_FALSE, &rows, &start, &column, &done));
  }

  void Clear() {
    if (scatter_) VecScatterDestroy(&scatter_);
    if (ghost_values_) VecDestroy(&ghost_values_);
  }

  VecScatter scatter_ = nullptr;
  Vec ghost_values_ = nullptr;  // the off-diagonal block's columns of v
};

// The kind of row r of the mixed form (file comment): kSplit is the equation F_i - w + v
// of a two-sided component, kLowerSlack / kUpperSlack its pairs (x_i - l_i, w) and
// (u_i - x_i, v).
enum class Row : char { kFree, kFixed, kLower, kUpper, kSplit, kLowerSlack, kUpperSlack };

bool IsSlackRow(Row row) { return row == Row::kLowerSlack || row == Row::kUpperSlack; }

double NormalizeBound(double bound, double infinite_bound) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  return bound >= infinite_bound ? kInf : bound <= -infinite_bound ? -kInf : bound;
}

// The first lower.size() local entries x of v <- mid(l, u, x), the projection onto the
// box; returns how many moved on this rank and (in *largest) by how much at most.
long long ProjectOntoBox(const std::vector<double>& lower,
                         const std::vector<double>& upper, Vec v,
                         double* largest = nullptr) {
  long long moved = 0;
  double most = 0.0;
  LocalWrite a(v);
  for (size_t i = 0; i < lower.size(); ++i) {
    const auto ii = static_cast<PetscInt>(i);
    const double value = PetscRealPart(a[ii]);
    const double projected = std::max(lower[i], std::min(upper[i], value));
    if (projected == value) continue;
    ++moved;
    most = std::max(most, std::abs(projected - value));
    a[ii] = projected;
  }
  if (largest) *largest = most;
  return moved;
}

// The rows of the mixed form owned by this rank, in the order of its unknowns y: its
// `components` rows of x, then the slacks w of its two-sided components, then their v.
struct MixedLayout {
  std::vector<Row> rows;  // kind of row r of y and of Phi
  // kSplit: its slack k; kLowerSlack, kUpperSlack: its component i; otherwise r itself.
  std::vector<PetscInt> link;
  std::vector<double> lower, upper;  // bounds of the rank's components, normalized
  PetscInt components = 0, slacks = 0;
  PetscInt total_slacks = 0;  // over all ranks

  // The rows of components with the (normalized) bounds lower, upper.
  MixedLayout(MPI_Comm comm, std::vector<double> lower_bounds,
              std::vector<double> upper_bounds)
      : lower(std::move(lower_bounds)), upper(std::move(upper_bounds)) {
    components = static_cast<PetscInt>(lower.size());
    std::vector<PetscInt> two_sided;
    for (PetscInt i = 0; i < components; ++i) {
      const auto ii = static_cast<size_t>(i);
      const bool lo = std::isfinite(lower[ii]), up = std::isfinite(upper[ii]);
      Row row = !lo && !up ? Row::kFree
                : lo && up ? (lower[ii] == upper[ii] ? Row::kFixed : Row::kSplit)
                : lo       ? Row::kLower
                           : Row::kUpper;
      rows.push_back(row);
      link.push_back(row == Row::kSplit ? static_cast<PetscInt>(two_sided.size()) : i);
      if (row == Row::kSplit) two_sided.push_back(i);
    }
    slacks = static_cast<PetscInt>(two_sided.size());
    for (Row slack_row : {Row::kLowerSlack, Row::kUpperSlack})
      for (PetscInt i : two_sided) {
        rows.push_back(slack_row);
        link.push_back(i);
      }
    total_slacks = static_cast<PetscInt>(SumRanks(comm, slacks));
  }

  PetscInt LocalRows() const { return components + 2 * slacks; }
  Row row(PetscInt r) const { return rows[static_cast<size_t>(r)]; }
  PetscInt Link(PetscInt r) const { return link[static_cast<size_t>(r)]; }
  PetscInt WRow(PetscInt k) const { return components + k; }
  PetscInt VRow(PetscInt k) const { return components + slacks + k; }
  // The unknown of the A side of row r (x_i - l_i or u_i - x_i): r, or the component of a
  // slack row.
  PetscInt AColumn(PetscInt r) const { return IsSlackRow(row(r)) ? Link(r) : r; }
};

// G of the file comment for a layout with slacks: F' with its columns renumbered from x
// to y, the split rows' -1 at w and +1 at v, 1 at (w, w) and (v, v), and zeros at (w, i),
// (v, i) and on a diagonal F' lacks (the positions J needs). Refresh copies the values of
// F' into it; the rest is constant.
class SlackMatrix {
 public:
  ~SlackMatrix() { DestroyMat(&G_); }
  Mat matrix() const { return G_; }
  void Clear() { DestroyMat(&G_); }

  void Build(MPI_Comm comm, Mat F, const MixedLayout& layout) {
    DestroyMat(&G_);
    int size = 0;
    MPI_Comm_size(comm, &size);
    const PetscInt* x_ranges = nullptr;  // size + 1 entries
    NCP_PETSC_CHECK(MatGetOwnershipRangesColumn(F, &x_ranges));
    PetscInt local_y = layout.LocalRows();
    std::vector<PetscInt> y_ranges(static_cast<size_t>(size) + 1, 0);
    MPI_Allgather(&local_y, 1, MPIU_INT, y_ranges.data() + 1, 1, MPIU_INT, comm);
    for (size_t p = 1; p < y_ranges.size(); ++p) y_ranges[p] += y_ranges[p - 1];
    auto to_y = [&](PetscInt j) {  // column j of x -> column of y (same owner)
      const auto p = std::upper_bound(x_ranges, x_ranges + size + 1, j) - x_ranges - 1;
      return y_ranges[static_cast<size_t>(p)] + (j - x_ranges[p]);
    };
    PetscInt first_x = 0, last_x = 0;
    NCP_PETSC_CHECK(MatGetOwnershipRange(F, &first_x, &last_x));
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    first_y_ = y_ranges[static_cast<size_t>(rank)];
    const PetscInt last_y = first_y_ + local_y;

    // Columns of F''s rows in y and the preallocation of every row of G.
    row_start_.assign(1, 0);
    columns_.clear();
    has_diagonal_.clear();
    std::vector<PetscInt> diagonal(static_cast<size_t>(local_y), 0),
        off_diagonal(static_cast<size_t>(local_y), 0);
    for (PetscInt r = 0; r < layout.components; ++r) {
      PetscInt count = 0;
      const PetscInt* cols = nullptr;
      NCP_PETSC_CHECK(MatGetRow(F, first_x + r, &count, &cols, nullptr));
      bool diagonal_present = false;
      for (PetscInt e = 0; e < count; ++e) {
        const PetscInt c = to_y(cols[e]);
        columns_.push_back(c);
        diagonal_present = diagonal_present || c == first_y_ + r;
        ++(c >= first_y_ && c < last_y ? diagonal : off_diagonal)[static_cast<size_t>(r)];
      }
      NCP_PETSC_CHECK(MatRestoreRow(F, first_x + r, &count, &cols, nullptr));
      row_start_.push_back(static_cast<PetscInt>(columns_.size()));
      has_diagonal_.push_back(diagonal_present);
      diagonal[static_cast<size_t>(r)] +=
          (diagonal_present ? 0 : 1) + (layout.row(r) == Row::kSplit ? 2 : 0);
    }
    for (PetscInt r = layout.components; r < local_y; ++r)
      diagonal[static_cast<size_t>(r)] = 2;
    const PetscInt total = y_ranges.back();
    NCP_PETSC_CHECK(MatCreateAIJ(comm, local_y, local_y, total, total, 0, diagonal.data(),
                                 0, off_diagonal.data(), &G_));
    NCP_PETSC_CHECK(MatSetOption(G_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));

    // The constant entries; F''s are set by Refresh.
    for (PetscInt r = 0; r < local_y; ++r) {
      const PetscInt row = first_y_ + r;
      if (r < layout.components && !has_diagonal_[static_cast<size_t>(r)])
        Set(row, row, 0.0);
      if (layout.row(r) == Row::kSplit) {
        Set(row, first_y_ + layout.WRow(layout.Link(r)), -1.0);
        Set(row, first_y_ + layout.VRow(layout.Link(r)), 1.0);
      }
      if (IsSlackRow(layout.row(r))) {
        Set(row, first_y_ + layout.Link(r), 0.0);
        Set(row, row, 1.0);
      }
    }
    Refresh(F, layout);
  }

  // The values of F' (same pattern as at Build) into G.
  void Refresh(Mat F, const MixedLayout& layout) {
    PetscInt first_x = 0, last_x = 0;
    NCP_PETSC_CHECK(MatGetOwnershipRange(F, &first_x, &last_x));
    for (PetscInt r = 0; r < layout.components; ++r) {
      PetscInt count = 0;
      const PetscScalar* values = nullptr;
      NCP_PETSC_CHECK(MatGetRow(F, first_x + r, &count, nullptr, &values));
      const auto start = static_cast<size_t>(row_start_[static_cast<size_t>(r)]);
      const PetscInt row = first_y_ + r;
      if (count !=
          row_start_[static_cast<size_t>(r) + 1] - row_start_[static_cast<size_t>(r)])
        throw std::runtime_error(
            "ncp::petsc::Solver: the Jacobian matrix changed its pattern without "
            "changing its nonzero state");
      NCP_PETSC_CHECK(MatSetValues(G_, 1, &row, count, columns_.data() + start, values,
                                   INSERT_VALUES));
      NCP_PETSC_CHECK(MatRestoreRow(F, first_x + r, &count, nullptr, &values));
    }
    NCP_PETSC_CHECK(MatAssemblyBegin(G_, MAT_FINAL_ASSEMBLY));
    NCP_PETSC_CHECK(MatAssemblyEnd(G_, MAT_FINAL_ASSEMBLY));
  }

 private:
  void Set(PetscInt row, PetscInt col, double value) {
    NCP_PETSC_CHECK(MatSetValue(G_, row, col, value, INSERT_VALUES));
  }

  Mat G_ = nullptr;
  PetscInt first_y_ = 0;
  std::vector<PetscInt> row_start_, columns_;  // F''s local rows: their columns in y
  std::vector<bool> has_diagonal_;
};

}  // namespace

Mat GridInterpolation(DM coarse, DM fine) {
  PetscInt64 id = 0;
  NCP_PETSC_CHECK(PetscObjectGetId(reinterpret_cast<PetscObject>(coarse), &id));
  const std::string key = "ncp_petsc_interpolation_from_" + std::to_string(id);
  PetscObject kept = nullptr;
  NCP_PETSC_CHECK(
      PetscObjectQuery(reinterpret_cast<PetscObject>(fine), key.c_str(), &kept));
  // Made collectively when any rank lacks it (DMCreateInterpolation is collective).
  if (!AnyRank(PetscObjectComm(reinterpret_cast<PetscObject>(fine)), kept == nullptr))
    return reinterpret_cast<Mat>(kept);
  Mat P = nullptr;
  NCP_PETSC_CHECK(DMCreateInterpolation(coarse, fine, &P, nullptr));
  NCP_PETSC_CHECK(PetscObjectCompose(reinterpret_cast<PetscObject>(fine), key.c_str(),
                                     reinterpret_cast<PetscObject>(P)));
  Mat borrowed = P;
  NCP_PETSC_CHECK(MatDestroy(&P));  // `fine` holds it now
  return borrowed;
}

namespace {

// PCMG for the reduced Newton system of the symmetric mode (Iteration::Symmetrize) on a
// structured grid, as a reduced-space active-set method restricts its multigrid to the
// inactive set: the hierarchy is made once by coarsening the user's grid (DMCoarsen,
// DMCreateInterpolation: P_l from level l - 1 to l), and at every Newton step the coarse
// operators are the Galerkin products of the reduced system alone,
//
//   A_{l-1} = P_l,r' A_l P_l,r = P_l' A_l,0 P_l,   P_l,r = diag(m_l) P_l,
//
// with m_l = 1 on the unknowns left in the system at level l and 0 on the eliminated
// ones, whose rows and columns in A_l are zero but for a 1 on the diagonal (A_l,0: that
// 1 removed for the product). A coarse node whose column of P_l,r is zero (no kept fine
// node near it) has a zero row and column in A_{l-1}: it gets a 1 on the diagonal, is
// decoupled, and m_{l-1} = 0 there. PCMG interpolates with P_l itself: the values it
// puts on a decoupled row are overwritten by the post-smoother (SOR solves an identity
// row exactly) and reach no other row, so the V-cycle is that of P_l,r.
class InactiveSetMultigrid {
 public:
  ~InactiveSetMultigrid() { Clear(); }
  DM grid() const { return grid_; }
  bool attached() const { return attached_; }

  void SetGrid(DM grid) {
    Clear();
    if (grid) NCP_PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(grid)));
    grid_ = grid;
  }

  // Levels from PCMG `pc` (its -pc_mg_levels), the hierarchy from the grid; PCMG
  // computes no Galerkin operators itself.
  void Attach(PC pc) {
    PetscInt levels = 1;
    NCP_PETSC_CHECK(PCMGGetLevels(pc, &levels));
    const auto count = static_cast<size_t>(std::max<PetscInt>(levels, 1));
    dms_.assign(count, nullptr);
    interpolation_.assign(count, nullptr);
    coarse_.assign(count, nullptr);
    decoupled_.assign(count, nullptr);
    NCP_PETSC_CHECK(PetscObjectReference(reinterpret_cast<PetscObject>(grid_)));
    dms_[count - 1] = grid_;
    const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(grid_));
    for (size_t l = count - 1; l >= 1; --l) {
      // The grid this one was refined from (DMGetCoarseDM, e.g. the previous grid of a
      // nested iteration) with its interpolation made once (GridInterpolation), else a
      // coarsening made here.
      DM refined_from = nullptr;
      NCP_PETSC_CHECK(DMGetCoarseDM(dms_[l], &refined_from));
      if (!AnyRank(comm, refined_from == nullptr)) {
        NCP_PETSC_CHECK(
            PetscObjectReference(reinterpret_cast<PetscObject>(refined_from)));
        dms_[l - 1] = refined_from;
        interpolation_[l] = GridInterpolation(refined_from, dms_[l]);
        NCP_PETSC_CHECK(
            PetscObjectReference(reinterpret_cast<PetscObject>(interpolation_[l])));
      } else {
        NCP_PETSC_CHECK(DMCoarsen(dms_[l], comm, &dms_[l - 1]));
        NCP_PETSC_CHECK(
            DMCreateInterpolation(dms_[l - 1], dms_[l], &interpolation_[l], nullptr));
      }
      NCP_PETSC_CHECK(MatCreateVecs(interpolation_[l], &decoupled_[l - 1], nullptr));
      NCP_PETSC_CHECK(
          PCMGSetInterpolation(pc, static_cast<PetscInt>(l), interpolation_[l]));
    }
    NCP_PETSC_CHECK(PCMGSetGalerkin(pc, PC_MG_GALERKIN_NONE));
    attached_ = true;
  }

  // The coarse operators for the reduced system S of this Newton step; eliminated: 1 - m
  // of the finest level (1 on the eliminated rows of S, 0 on the others).
  void Update(PC pc, Mat S, Vec eliminated) {
    Mat A = S;
    Vec decoupled = eliminated;
    for (size_t l = coarse_.size() - 1; l >= 1; --l) {
      NCP_PETSC_CHECK(VecScale(decoupled, -1.0));  // A_l,0 for the product ...
      NCP_PETSC_CHECK(MatDiagonalSet(A, decoupled, ADD_VALUES));
      NCP_PETSC_CHECK(MatPtAP(A, interpolation_[l],
                              coarse_[l - 1] ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX,
                              PETSC_DEFAULT, &coarse_[l - 1]));
      NCP_PETSC_CHECK(VecScale(decoupled, -1.0));  // ... and A_l again
      NCP_PETSC_CHECK(MatDiagonalSet(A, decoupled, ADD_VALUES));
      Mat coarse = coarse_[l - 1];
      Vec coarse_decoupled = decoupled_[l - 1];
      NCP_PETSC_CHECK(MatGetDiagonal(coarse, coarse_decoupled));
      PetscInt local = 0;
      NCP_PETSC_CHECK(VecGetLocalSize(coarse_decoupled, &local));
      {
        // A_{l-1} = P_r' A_l P_r with A_l positive definite on the kept rows: its
        // diagonal entry j is zero exactly when column j of P_r is.
        LocalWrite d(coarse_decoupled);
        for (PetscInt j = 0; j < local; ++j)
          d[j] = PetscRealPart(d[j]) == 0.0 ? 1.0 : 0.0;
      }
      NCP_PETSC_CHECK(MatDiagonalSet(coarse, coarse_decoupled, ADD_VALUES));
      KSP smoother = nullptr;
      NCP_PETSC_CHECK(PCMGGetSmoother(pc, static_cast<PetscInt>(l - 1), &smoother));
      NCP_PETSC_CHECK(KSPSetOperators(smoother, coarse, coarse));
      A = coarse;
      decoupled = coarse_decoupled;
    }
  }

 private:
  void Clear() {
    for (std::vector<Mat>* M : {&interpolation_, &coarse_})
      for (Mat& m : *M) DestroyMat(&m);
    for (Vec& v : decoupled_)
      if (v) VecDestroy(&v);
    for (DM& dm : dms_)
      if (dm) DMDestroy(&dm);
    dms_.clear();
    interpolation_.clear();
    coarse_.clear();
    decoupled_.clear();
    if (grid_) DMDestroy(&grid_);
    grid_ = nullptr;
    attached_ = false;
  }

  DM grid_ = nullptr;
  bool attached_ = false;
  std::vector<DM> dms_;             // level l = 0 (coarsest) ... finest
  std::vector<Mat> interpolation_;  // [l]: P_l from level l - 1 to l
  std::vector<Mat> coarse_;         // [l]: A_l of the coarse levels
  std::vector<Vec> decoupled_;      // [l]: 1 - m_l of the coarse levels
};

// The Krylov solve of a Newton system continued past the KSP's own test (rtol, atol)
// until its residual, in the units of Phi, passes the outer stopping test with the margin
// `fraction` (-<prefix>newton_residual_fraction, docs/petsc.md): every row
//
//   |w_r (b - A d)_r| <= fraction (tolerance + roundoff_ulps eps s_r),
//
// with w_r the factor from the KSP's row r to the row of J d + Phi (1, or in symmetric
// mode c_F,r on a kept row and c_I,r on an eliminated one) and s_r the round-off
// sensitivity of the stopping test at x. Where the Newton matrix does not change between
// x and x + d (the min function on a linear F with an unchanged active set) Phi(x + d) =
// J d + Phi exactly, so the step that lands on the final active set is also the last one;
// elsewhere Phi(x + d) differs by O(||d||^2) terms, for which 1 - fraction of the
// tolerance is left. The residual is formed (KSPBuildResidual: one product with A) only
// once the KSP's own test has passed. Margin of the Newton KSP's test against the outer
// stopping test (OuterResidualTest): half the tolerance for the linear residual, half for
// what the step changes beyond it. By default only for the min function, whose Phi(x + d)
// is J d + Phi on every row whose active side does not change; for FB and penalized FB
// the O(||d||^2) remainder decides, and continued solves only cost iterations
// (docs/petsc.md).
constexpr double kDefaultResidualFraction = 0.5;

class OuterResidualTest {
 public:
  ~OuterResidualTest() {
    if (default_context_) KSPConvergedDefaultDestroy(default_context_);
  }
  double fraction() const { return fraction_; }
  // Whether it applies to a Newton system of `function`: the min function by default,
  // every function when -<prefix>newton_residual_fraction was given.
  bool AppliesTo(NcpFunction function) const {
    return fraction_ > 0.0 && (explicit_ || function == NcpFunction::kMin);
  }
  long long continued() const { return continued_; }
  void ResetCount() { continued_ = 0; }

  // The test in place of ksp's (after KSPSetFromOptions); fraction 0 leaves ksp's own.
  void Install(KSP ksp, double fraction, bool given) {
    fraction_ = fraction;
    explicit_ = given;
    if (fraction_ == 0.0) return;
    NCP_PETSC_CHECK(KSPConvergedDefaultCreate(&default_context_));
    NCP_PETSC_CHECK(
        KSPSetConvergenceTest(ksp, &OuterResidualTest::Converged, this, nullptr));
  }

  // The rows' weights w and bounds for the next solve (Vecs laid out like its right-hand
  // side, kept by the caller until Disarm), and two work vectors of that layout.
  void Arm(Vec weight, Vec bound, Vec residual, Vec work) {
    weight_ = weight;
    bound_ = bound;
    residual_ = residual;
    work_ = work;
  }
  void Disarm() { weight_ = bound_ = residual_ = work_ = nullptr; }

 private:
  static PetscErrorCode Converged(KSP ksp, PetscInt it, PetscReal rnorm,
                                  KSPConvergedReason* reason, void* context) {
    auto* self = static_cast<OuterResidualTest*>(context);
    PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, self->default_context_));
    if (*reason <= 0 || !self->weight_) return 0;
    Vec r = nullptr;
    PetscCall(KSPBuildResidual(ksp, self->work_, self->residual_, &r));
    PetscCall(VecPointwiseMult(self->work_, r, self->weight_));
    PetscCall(VecAbs(self->work_));
    PetscCall(VecPointwiseDivide(self->work_, self->work_, self->bound_));
    PetscReal largest = 0.0;
    PetscCall(VecMax(self->work_, nullptr, &largest));
    if (largest > 1.0) {
      *reason = KSP_CONVERGED_ITERATING;
      ++self->continued_;
    }
    return 0;
  }

  double fraction_ = 0.0;
  bool explicit_ = false;  // given in the options database
  void* default_context_ = nullptr;
  Vec weight_ = nullptr, bound_ = nullptr, residual_ = nullptr, work_ = nullptr;
  long long continued_ = 0;  // iterations past the KSP's own test
};

}  // namespace

// ---------------------------------------------------------------------------------------
// The solver's state kept between solves: the KSP and the Newton matrix (so a direct
// solver's symbolic factorization is reused while F' keeps its pattern).

struct Solver::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  Options options;
  std::string prefix;
  KSP ksp = nullptr;
  bool ksp_configured = false;
  KspReport report;
  // The KSP's operator on the pattern of G (plus its diagonal; G = F' without slacks),
  // built for the user's matrix `source` in the nonzero state `source_state`: J of the
  // file comment, or with symmetric_newton the reduced symmetric system
  // (Iteration::Symmetrize: rows with c_F != 0 divided by c_F, the others eliminated;
  // KspReport::symmetric_newton). Products with J itself (gradient, backward error) are
  // formed from G and c_F, c_I (Iteration::MultNewton), so the symmetric mode keeps a
  // second matrix only for the LM direction (lm_jacobian).
  Mat newton = nullptr;
  Mat source = nullptr;
  PetscObjectState source_state = -1;
  bool same_pattern = true;    // the operator's pattern is F''s (no diagonal entry added)
  AbsoluteProduct abs_source;  // |G| v (round-off floor, backward error)
  bool symmetric_newton = false;
  // With two-sided bounds: G of the file comment for the layout `layout_rows`.
  SlackMatrix slack;
  std::vector<Row> layout_rows;
  // The Levenberg-Marquardt system J'J + mu I (Options::regularized_direction and the
  // hybrid's "+lm" strategies) and its own KSP, options prefix <prefix>lm_.
  // With symmetric_newton J is not `newton`: lm_jacobian holds it, built on demand.
  KSP lm_ksp = nullptr;
  Mat normal = nullptr, lm_jacobian = nullptr;
  // PCMG restricted to the inactive set (Solver::SetMultigridGrid), or no grid.
  InactiveSetMultigrid multigrid;
  // The Newton KSP's test tied to the outer stopping test (OuterResidualTest).
  OuterResidualTest outer_test;
  // MUMPS' ICNTL(14) after a factorization ran out of workspace (KspSolve), 0: default.
  int newton_workspace_percent = 0, lm_workspace_percent = 0;

  ~Impl() {
    DestroyMat(&newton);
    DestroyMat(&normal);
    DestroyMat(&lm_jacobian);
    if (ksp) KSPDestroy(&ksp);
    if (lm_ksp) KSPDestroy(&lm_ksp);
  }

  // N = J'J + mu I for the J of the current iterate (the matrix J), on lm_ksp; the
  // product's structure is kept while J's is.
  void PrepareNormalMatrix(Mat J, double mu) {
    NCP_PETSC_CHECK(MatTransposeMatMult(
        J, J, normal ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, PETSC_DEFAULT, &normal));
    NCP_PETSC_CHECK(MatShift(normal, mu));
    NCP_PETSC_CHECK(KSPSetOperators(lm_ksp, normal, normal));
  }

  // The matrix G of the file comment: F' itself without slacks.
  Mat SourceMatrix(Mat F) const { return slack.matrix() ? slack.matrix() : F; }

  // J's structure for the matrix F' and the layout (again when F' is another matrix or
  // changed pattern, or the bounds another layout). Returns true when J was (re)built.
  bool PrepareNewtonMatrix(Mat F, const MixedLayout& layout) {
    PetscObjectState state = 0;
    NCP_PETSC_CHECK(MatGetNonzeroState(F, &state));
    const bool same_layout = !AnyRank(comm, layout.rows != layout_rows);
    if (newton && source == F && state == source_state && same_layout) return false;
    DestroyMat(&newton);
    DestroyMat(&normal);
    DestroyMat(&lm_jacobian);
    layout_rows = layout.rows;
    if (layout.total_slacks > 0)
      slack.Build(comm, F, layout);
    else
      slack.Clear();
    NCP_PETSC_CHECK(MatDuplicate(SourceMatrix(F), MAT_COPY_VALUES, &newton));
    abs_source.Prepare(SourceMatrix(F));
    PetscBool missing = PETSC_FALSE;
    PetscInt row = 0;
    NCP_PETSC_CHECK(MatMissingDiagonal(newton, &missing, &row));
    same_pattern = !AnyRank(comm, missing == PETSC_TRUE);
    if (!same_pattern) {  // c_I needs every diagonal entry: add the missing ones as zeros
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
      Vec zero = nullptr;
      NCP_PETSC_CHECK(MatCreateVecs(newton, &zero, nullptr));
      NCP_PETSC_CHECK(VecSet(zero, 0.0));
      NCP_PETSC_CHECK(MatDiagonalSet(newton, zero, ADD_VALUES));
      VecDestroy(&zero);
    }
    source = F;
    source_state = state;
    if (symmetric_newton) {  // MatZeroRowsColumns keeps the pattern for the next MatCopy
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    }
    NCP_PETSC_CHECK(KSPSetOperators(ksp, newton, newton));
    return true;
  }

  // Once, at the first solve: the KSP from the options database, and whether the Newton
  // systems are symmetrized: -<prefix>symmetric_newton <bool>, by default on for the KSPs
  // and PCs that need a symmetric operator (CG family, MINRES, Cholesky, ICC).
  void Configure() {
    if (ksp_configured) return;
    NCP_PETSC_CHECK(KSPSetFromOptions(ksp));
    NCP_PETSC_CHECK(KSPSetFromOptions(lm_ksp));
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    PetscBool symmetric_ksp = PETSC_FALSE, symmetric_pc = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(
        reinterpret_cast<PetscObject>(ksp), &symmetric_ksp, KSPCG, KSPPIPECG, KSPGROPPCG,
        KSPCR, KSPPIPECR, KSPMINRES, KSPSYMMLQ, ""));
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc),
                                              &symmetric_pc, PCCHOLESKY, PCICC, ""));
    PetscBool flag = symmetric_ksp || symmetric_pc ? PETSC_TRUE : PETSC_FALSE,
              set = PETSC_FALSE;
    NCP_PETSC_CHECK(
        PetscOptionsGetBool(nullptr, prefix.c_str(), "-symmetric_newton", &flag, &set));
    symmetric_newton = flag == PETSC_TRUE;
    report.symmetric_newton = symmetric_newton;
    InstallOuterResidualTest();
    ksp_configured = true;
  }

  // -<prefix>newton_residual_fraction f in [0, 1] (default kDefaultResidualFraction for
  // the min function): the Newton KSP runs until its residual passes f times the outer
  // stopping test (OuterResidualTest); 0 keeps the KSP's own test alone.
  void InstallOuterResidualTest() {
    PetscReal fraction = kDefaultResidualFraction;
    PetscBool set = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscOptionsGetReal(nullptr, prefix.c_str(),
                                        "-newton_residual_fraction", &fraction, &set));
    if (!(fraction >= 0.0 && fraction <= 1.0))
      throw std::invalid_argument(
          "ncp::petsc::Solver: -" + prefix + "newton_residual_fraction = " +
          FormatNumber("%g", fraction) + ": accepted a number in [0, 1] (0: off)");
    outer_test.Install(ksp, fraction, set == PETSC_TRUE);
  }

  // KspReport's names of the KSP, PC and factorization package in use.
  void DescribeKsp() {
    KSPType ksp_type = nullptr;
    PCType pc_type = nullptr;
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetType(ksp, &ksp_type));
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    NCP_PETSC_CHECK(PCGetType(pc, &pc_type));
    report.ksp_type = ksp_type ? ksp_type : "";
    report.pc_type = pc_type ? pc_type : "";
    PetscBool factor = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factor,
                                              PCLU, PCCHOLESKY, PCILU, PCICC, ""));
    MatSolverType solver_type = nullptr;
    if (factor) NCP_PETSC_CHECK(PCFactorGetMatSolverType(pc, &solver_type));
    report.factor_solver_type = solver_type ? solver_type : "";
  }
};

// ---------------------------------------------------------------------------------------
// Misuse at the API boundary, checked collectively: the same exception on every rank.

namespace {

[[noreturn]] void Misuse(const std::string& what) {
  throw std::invalid_argument("ncp::petsc::Solver::Solve: " + what);
}

void CheckLayout(MPI_Comm comm, Vec x, Vec v, const char* name) {
  PetscInt n = 0, nl = 0, N = 0, NL = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(VecGetSize(v, &N));
  NCP_PETSC_CHECK(VecGetLocalSize(v, &NL));
  if (AnyRank(comm, N != n || NL != nl))
    Misuse(std::string(name) + " has global size " + std::to_string(N) +
           ", the start point " + std::to_string(n) +
           (N == n ? " (but the local sizes differ on some rank)" : "") +
           ": both must have the same layout");
}

void CheckMatrixLayout(MPI_Comm comm, Vec x, Mat J) {
  PetscInt n = 0, nl = 0, rows = 0, cols = 0, local_rows = 0, local_cols = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(MatGetSize(J, &rows, &cols));
  NCP_PETSC_CHECK(MatGetLocalSize(J, &local_rows, &local_cols));
  if (AnyRank(comm, rows != n || cols != n || local_rows != nl || local_cols != nl))
    Misuse("the Jacobian matrix is " + std::to_string(rows) + " x " +
           std::to_string(cols) + ", the start point has size " + std::to_string(n) +
           ": the matrix must be square with rows and columns laid out like x");
}

// The first (lowest global index) bad entry of the bounds or the start point, reported
// with its values on every rank (the owner contributes them to a sum, the others zeros).
void CheckBoundsAndStart(MPI_Comm comm, PetscInt first, const std::vector<double>& lower,
                         const std::vector<double>& upper, Vec x) {
  const auto n = static_cast<PetscInt>(lower.size());
  LocalRead xa(x);
  long long bad = LLONG_MAX;
  for (PetscInt i = 0; i < n && bad == LLONG_MAX; ++i) {
    const double l = lower[static_cast<size_t>(i)], u = upper[static_cast<size_t>(i)];
    const bool problem = std::isnan(l) || std::isnan(u) || l > u ||
                         l == std::numeric_limits<double>::infinity() ||
                         u == -std::numeric_limits<double>::infinity() ||
                         !std::isfinite(xa[i]);
    if (problem) bad = first + i;
  }
  const long long global_bad = MinRanks(comm, bad);
  if (global_bad == LLONG_MAX) return;
  double values[3] = {0.0, 0.0, 0.0};  // l, u, x0 at global_bad
  if (bad == global_bad) {
    const auto i = static_cast<size_t>(bad - first);
    values[0] = lower[i];
    values[1] = upper[i];
    values[2] = xa[static_cast<PetscInt>(i)];
  }
  double at_bad[3];
  MPI_Allreduce(values, at_bad, 3, MPI_DOUBLE, MPI_SUM, comm);
  const double l = at_bad[0], u = at_bad[1], x0 = at_bad[2];
  const std::string at = "[" + std::to_string(global_bad) + "]";
  if (std::isnan(l) || std::isnan(u)) Misuse("bound" + at + " is NaN");
  if (l > u)
    Misuse("lower" + at + " = " + FormatNumber("%.17g", l) + " > upper" + at + " = " +
           FormatNumber("%.17g", u));
  if (l == std::numeric_limits<double>::infinity() ||
      u == -std::numeric_limits<double>::infinity())
    Misuse("empty box at" + at + " (lower = +inf or upper = -inf)");
  Misuse("start point x" + at + " = " + FormatNumber("%g", x0) + " is not finite");
}

}  // namespace

// ---------------------------------------------------------------------------------------
// One solve, phase by phase; Run() has the layout of ncp::Solver::Iteration::Run
// (ncp/src/solver.cpp) and takes its decisions from globalization.hpp.

class Iteration {
 public:
  Iteration(Solver::Impl& impl, const BoxMcp& problem, Vec x, Summary& summary,
            const MixedLayout& layout)
      : impl_(impl),
        o_(impl.options),
        comm_(impl.comm),
        p_(problem),
        x_(x),
        s_(summary),
        layout_(layout),
        lower_(layout.lower),
        upper_(layout.upper),
        local_(layout.LocalRows()) {}

  enum class Direction { kNewton, kRegularized, kGradient };

  // The solve; x holds the x part of the last iterate afterwards.
  void Run() {
    RunIterations();
    if (layout_.total_slacks > 0) CopyXPart(y_, x_);
  }

 private:
  void RunIterations() {
    if (!Start()) return;
    for (int k = 0;;) {
      phi_inf_ = NormInf(phi_);
      psi_ = 0.5 * Dot(phi_, phi_);
      converged_ = phi_inf_ <= o_.tolerance;
      roundoff_limited_ = false;
      have_jacobian_ = !converged_ && k < o_.max_iterations;
      jacobian_ok_ = true;
      degenerate_count_ = 0;
      if (have_jacobian_ && !EvaluateJacobian(k)) return;
      if (have_jacobian_ && jacobian_ok_)
        converged_ = roundoff_limited_ = WithinRoundoffFloor();
      if (!Report(k)) return;
      if (TestStop(k)) {
        if (Restart(k) || SwitchStrategy(k, SwitchReason::kStuck)) continue;
        return;
      }
      if (LeaveStrategy(k)) continue;
      const Direction direction = ChooseDirection(k);
      if (finished_) {
        if (SwitchStrategy(k, SwitchReason::kStuck)) continue;
        return;
      }
      if (!LineSearch(k, direction)) {
        if (Restart(k) || SwitchStrategy(k, SwitchReason::kStuck)) continue;
        return;
      }
      Accept(direction);
      ++k;
    }
  }

  // ---- Start: work vectors, Phi(x^0)
  // -----------------------------------------------------
  bool Start() {
    start_ = Clock::now();
    InitializeSummary();
    for (OwnedVec* v : {&f_, &f_trial_, &x_part_}) v->DuplicateOf(x_);
    y_ = x_;
    if (layout_.total_slacks > 0) {
      y_owned_.Create(comm_, local_);
      y_ = y_owned_;
    }
    for (OwnedVec* v : {&phi_, &phi_trial_, &grad_, &d_, &x_trial_, &c_f_, &c_i_, &z_,
                        &f_z_, &work_, &work2_, &fixed_values_, &diag_g_, &sensitivity_})
      v->DuplicateOf(y_);
    NCP_PETSC_CHECK(VecSet(sensitivity_, 0.0));  // no round-off floor: stays 0
    impl_.Configure();
    if (impl_.outer_test.fraction() > 0.0)
      for (OwnedVec* v : {&ksp_row_weight_, &ksp_row_bound_, &ksp_residual_, &ksp_work_})
        v->DuplicateOf(y_);
    const bool new_matrix = impl_.PrepareNewtonMatrix(p_.jacobian_matrix, layout_);
    G_ = impl_.SourceMatrix(p_.jacobian_matrix);
    s_.symbolic_factorizations = new_matrix ? 1 : 0;
    impl_.DescribeKsp();
    function_ = o_.ncp_function;
    restarts_left_ = o_.merit_restarts;
    first_k_ = 0;
    regularized_ = o_.regularized_direction;
    strategy_start_ = 0;
    schedule_.Reset(o_);
    progress_.ResetRecord(o_, s_.num_variables);
    if (o_.hybrid) best_y_.DuplicateOf(y_);
    impl_.report.linear_iterations = 0;
    impl_.report.residual_test_iterations = 0;
    impl_.outer_test.ResetCount();
    if (layout_.total_slacks > 0) {
      CopyXPart(x_, y_);
      if (!SetSlacks(y_)) {
        NCP_PETSC_CHECK(VecSet(phi_, std::numeric_limits<double>::quiet_NaN()));
        Finish(TerminationType::kEvaluationFailure,
               "F cannot be evaluated (or is not finite) at the start point");
        return false;
      }
    }
    if (!Evaluate(y_, f_, phi_)) {
      NCP_PETSC_CHECK(VecSet(phi_, std::numeric_limits<double>::quiet_NaN()));
      Finish(TerminationType::kEvaluationFailure,
             "the problem cannot be evaluated at the start point");
      return false;
    }
    s_.initial_phi_inf = NormInf(phi_);
    if (!AllFinite(comm_, phi_)) {
      Finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
      return false;
    }
    stagnation_.Reset(o_.stagnation_window);
    armijo_reference_.Reset(o_.nonmonotone_memory);
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter",
                   "|Phi|_inf", "psi", "|grad|_inf", "step", "bt", "dir", "|gam|");
    return true;
  }

  void InitializeSummary() {
    s_ = Summary();
    s_.num_variables = static_cast<int>(SumRanks(comm_, local_));
    long long equations = 0;
    for (Row r : layout_.rows)
      equations += r == Row::kFree || r == Row::kFixed || r == Row::kSplit;
    s_.num_equations = static_cast<int>(SumRanks(comm_, equations));
    s_.num_pairs = s_.num_variables - s_.num_equations;
    s_.ncp_function = o_.ncp_function;
    s_.linear_solver_requested = s_.linear_solver_used = LinearSolverType::kAuto;
    s_.iterations = s_.jacobian_evaluations = s_.residual_evaluations = 0;
    s_.gradient_steps = s_.regularized_steps = s_.merit_restarts = 0;
    // Options::minimum_norm_step and scale_newton_system act on the serial LU only
    // (docs/petsc.md): a KSP that fails goes to the LM direction or -grad psi at once.
    s_.minimum_norm_steps = s_.equilibrated_factorizations = 0;
    s_.linear_solver_failures = s_.descent_test_failures = s_.backtracks = 0;
    s_.cholesky_fallbacks = s_.projected_start_components = 0;
    s_.evaluation_time_s = s_.linear_solver_time_s = 0.0;
    s_.predicted_factorization_flops =
        std::numeric_limits<double>::quiet_NaN();  // none predicted
  }

  // ---- Phi(x) row by row (file comment); false when F cannot be evaluated on some rank
  // ----
  bool Evaluate(Vec point, Vec f, Vec phi) {
    ++s_.residual_evaluations;
    const auto t0 = Clock::now();
    const PetscErrorCode code = p_.residual(XPart(point), f);
    s_.evaluation_time_s += Seconds(t0);
    if (AnyRank(comm_, code != 0)) return false;
    LocalRead ya(point), fa(f);
    LocalWrite out(phi);
    for (PetscInt r = 0; r < local_; ++r) {
      const auto rr = static_cast<size_t>(r);
      double a = 0.0, b = 0.0;
      if (PairValues(r, ya, fa, &a, &b)) {
        out[r] = internal::PhiValue(function_, o_.penalized_fb_lambda, a, b);
        continue;
      }
      const Row row = layout_.row(r);
      if (row == Row::kFree) out[r] = fa[r];
      if (row == Row::kFixed) out[r] = ya[r] - lower_[rr];
      if (row == Row::kSplit) {
        const PetscInt k = layout_.Link(r);
        out[r] = fa[r] - ya[layout_.WRow(k)] + ya[layout_.VRow(k)];
      }
    }
    return true;
  }

  // The x part of the unknowns y (y itself without slacks; else a copy in x_part_).
  Vec XPart(Vec y) {
    if (layout_.total_slacks == 0) return y;
    CopyXPart(y, x_part_);
    return x_part_;
  }
  // The local x entries from one layout to the other (y -> x or x -> y).
  void CopyXPart(Vec from, Vec to) {
    LocalRead a(from);
    LocalWrite b(to);
    for (PetscInt i = 0; i < layout_.components; ++i) b[i] = a[i];
  }

  // The slacks of y from F at its x part: w = max(F_i, 0), v = max(-F_i, 0)
  // (box_mcp.cpp's InitialSlacks, an evaluation not counted in the Summary); false when F
  // cannot be evaluated or is not finite there.
  bool SetSlacks(Vec y) {
    if (AnyRank(comm_, p_.residual(XPart(y), f_trial_) != 0) ||
        !AllFinite(comm_, f_trial_))
      return false;
    LocalRead fa(f_trial_);
    LocalWrite ya(y);
    for (PetscInt r = 0; r < layout_.components; ++r) {
      if (layout_.row(r) != Row::kSplit) continue;
      const PetscInt k = layout_.Link(r);
      ya[layout_.WRow(k)] = std::max(fa[r], 0.0);
      ya[layout_.VRow(k)] = std::max(-fa[r], 0.0);
    }
    return true;
  }

  // ---- J^k in the B-subdifferential and grad psi = J' Phi (eq. 24)
  // --------------------- false only when the solve has finished (non-finite Jacobian).
  bool EvaluateJacobian(int k) {
    ++s_.jacobian_evaluations;
    const auto t0 = Clock::now();
    jacobian_ok_ = !AnyRank(comm_, p_.jacobian(XPart(y_), p_.jacobian_matrix) != 0);
    s_.evaluation_time_s += Seconds(t0);
    if (!jacobian_ok_) return true;
    bool finite = true;
    ForEachLocalValue<false>(p_.jacobian_matrix, [&](const PetscScalar& v) {
      finite = finite && std::isfinite(PetscRealPart(v));
    });
    if (AnyRank(comm_, !finite)) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    if (layout_.total_slacks > 0) impl_.slack.Refresh(p_.jacobian_matrix, layout_);
    GDiagonalAtA();
    PhiPartials();
    if (!impl_.symmetric_newton) FillNewtonMatrix(impl_.newton);  // else by Symmetrize
    // grad psi = J' Phi = G' (c_F Phi) + c_I,r Phi_r added at y_AColumn(r)
    NCP_PETSC_CHECK(VecPointwiseMult(work_, c_f_, phi_));
    NCP_PETSC_CHECK(MatMultTranspose(G_, work_, grad_));
    {
      LocalRead c_i(c_i_), phi(phi_);
      LocalWrite grad(grad_);
      for (PetscInt r = 0; r < local_; ++r)
        grad[layout_.AColumn(r)] += c_i[r] * PetscRealPart(phi[r]);
    }
    return true;
  }

  // diag_g_ = G_{r, AColumn(r)}: the diagonal of G (of F') on the rows of x, 0 on the
  // slack rows (G's stored zeros at (w, i) and (v, i)).
  void GDiagonalAtA() {
    NCP_PETSC_CHECK(MatGetDiagonal(G_, diag_g_));
    LocalWrite diag(diag_g_);
    for (PetscInt r = layout_.components; r < local_; ++r) diag[r] = 0.0;
  }

  // c_F, c_I of every row (c_I: the coefficient of the A side, c_A of the file comment on
  // a slack row): the partials (da, db) of phi at (A_r, B_r) with the signs of A and B,
  // the z-vector rule on the degenerate set (z = 1 at the variable of every degenerate
  // pair, the row's own unknown; DFK 1996, eq. 27): za = A' z = +-z_AColumn(r),
  // zb = B' z = +-(G z)_r.
  void PhiPartials() {
    long long degenerate = 0;
    {
      LocalRead ya(y_), fa(f_);
      LocalWrite z(z_);
      for (PetscInt r = 0; r < local_; ++r) {
        z[r] = 0.0;
        double a = 0.0, b = 0.0;
        if (!PairValues(r, ya, fa, &a, &b)) continue;
        if (internal::InDegenerateSet(function_, o_.degenerate_tolerance, a, b)) {
          z[r] = 1.0;
          ++degenerate;
        }
      }
    }
    degenerate_count_ = static_cast<int>(SumRanks(comm_, degenerate));
    if (degenerate_count_ > 0) NCP_PETSC_CHECK(MatMult(G_, z_, f_z_));
    LocalRead ya(y_), fa(f_), z(z_);
    std::unique_ptr<LocalRead> fz(degenerate_count_ > 0 ? new LocalRead(f_z_) : nullptr);
    LocalWrite c_f(c_f_), c_i(c_i_);
    for (PetscInt r = 0; r < local_; ++r) {
      const Row row = layout_.row(r);
      double a = 0.0, b = 0.0;
      if (!PairValues(r, ya, fa, &a, &b)) {
        c_f[r] = row == Row::kFixed ? 0.0 : 1.0;
        c_i[r] = row == Row::kFixed ? 1.0 : 0.0;
        continue;
      }
      // A = +-(x_i - bound), B = +-F_i or the slack.
      const double sign_a = row == Row::kLower || row == Row::kLowerSlack ? 1.0 : -1.0;
      const double sign_b = row == Row::kUpper ? -1.0 : 1.0;
      const bool gamma = z[r] == 1.0;
      const internal::PhiPartials dp =
          internal::PhiDerivatives(function_, o_.penalized_fb_lambda, a, b, gamma,
                                   gamma ? sign_a * z[layout_.AColumn(r)] : 0.0,
                                   gamma ? sign_b * (*fz)[r] : 0.0, o_.min_tie_takes_b);
      c_i[r] = sign_a * dp.da;
      c_f[r] = sign_b * dp.db;
    }
  }

  // (A_r, B_r) of a pair row; false for an equation row.
  bool PairValues(PetscInt r, const LocalRead& ya, const LocalRead& fa, double* a,
                  double* b) const {
    const PetscInt i = layout_.AColumn(r);  // the component
    const auto ii = static_cast<size_t>(i);
    switch (layout_.row(r)) {
      case Row::kLower:
        *a = ya[i] - lower_[ii];
        *b = fa[i];
        return true;
      case Row::kUpper:
        *a = upper_[ii] - ya[i];
        *b = -fa[i];
        return true;
      case Row::kLowerSlack:
        *a = ya[i] - lower_[ii];
        *b = ya[r];
        return true;
      case Row::kUpperSlack:
        *a = upper_[ii] - ya[i];
        *b = ya[r];
        return true;
      default:
        return false;
    }
  }

  // out = J v: out_r = c_F,r (G v)_r + c_I,r v_a with a = AColumn(r) (r itself on the
  // rows of x; FillNewtonMatrix's J without forming it; v and out distinct).
  void MultNewton(Vec v, Vec out) {
    NCP_PETSC_CHECK(MatMult(G_, v, out));
    LocalRead vv(v), c_f(c_f_), c_i(c_i_);
    LocalWrite o(out);
    for (PetscInt r = 0; r < local_; ++r)
      o[r] =
          c_f[r] * PetscRealPart(o[r]) + c_i[r] * PetscRealPart(vv[layout_.AColumn(r)]);
  }

  // out = |J| |v|: row r of J is c_F,r G_r plus c_I,r at a = AColumn(r), so
  // out_r = |c_F,r| (|G||v|)_r + (|c_F,r G_ra + c_I,r| - |c_F,r G_ra|) |v_a| with
  // G_ra = diag_g_ (v and out distinct, neither work2_).
  void MultAbsNewton(Vec v, Vec out) {
    NCP_PETSC_CHECK(VecCopy(v, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    impl_.abs_source.Mult(G_, work2_, out);
    LocalRead abs_v(work2_), c_f(c_f_), c_i(c_i_), diag(diag_g_);
    LocalWrite o(out);
    for (PetscInt r = 0; r < local_; ++r) {
      const double cfd = c_f[r] * diag[r];
      o[r] = std::abs(c_f[r]) * PetscRealPart(o[r]) +
             (std::abs(cfd + c_i[r]) - std::abs(cfd)) * abs_v[layout_.AColumn(r)];
    }
  }

  // J = diag(c_F) G + diag(c_I) on the rows of x, c_I at (r, AColumn(r)) on slack rows,
  // into the matrix J (impl_.newton or impl_.lm_jacobian, both on newton's pattern).
  void FillNewtonMatrix(Mat J) {
    NCP_PETSC_CHECK(MatCopy(
        G_, J, impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    NCP_PETSC_CHECK(MatDiagonalScale(J, c_f_, nullptr));
    if (layout_.total_slacks == 0) {
      NCP_PETSC_CHECK(MatDiagonalSet(J, c_i_, ADD_VALUES));
      return;
    }
    PetscInt first = 0, last = 0;
    NCP_PETSC_CHECK(VecGetOwnershipRange(y_, &first, &last));
    NCP_PETSC_CHECK(VecCopy(c_i_, work_));
    {
      LocalRead c_i(c_i_);
      LocalWrite diagonal(work_);
      for (PetscInt r = layout_.components; r < local_; ++r) {
        diagonal[r] = 0.0;
        const PetscInt row = first + r, col = first + layout_.AColumn(r);
        const PetscScalar value = c_i[r];
        NCP_PETSC_CHECK(MatSetValues(J, 1, &row, 1, &col, &value, INSERT_VALUES));
      }
    }
    NCP_PETSC_CHECK(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    NCP_PETSC_CHECK(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    NCP_PETSC_CHECK(MatDiagonalSet(J, work_, ADD_VALUES));
  }

  // ---- the round-off floor of the test (Options::roundoff_ulps)
  // ------------------------- r_r = |c_F,r| (|G||y|)_r + |c_I,r| |y_AColumn(r)|, the
  // serial solver's |da| |J_A||x| + |db| |J_B||x| (and |J_E||x| for equations) for these
  // rows.
  bool WithinRoundoffFloor() {
    if (o_.roundoff_ulps == 0.0) return false;
    RoundoffSensitivity();
    bool within = true;
    {
      LocalRead phi(phi_), sensitivity(sensitivity_);
      for (PetscInt r = 0; r < local_ && within; ++r)
        within = internal::RowWithinRoundoffFloor(phi[r], o_.tolerance, o_.roundoff_ulps,
                                                  sensitivity[r]);
    }
    return !AnyRank(comm_, !within);
  }

  // sensitivity_ = the rows' r of the round-off floor at y (WithinRoundoffFloor).
  void RoundoffSensitivity() {
    NCP_PETSC_CHECK(VecCopy(y_, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    impl_.abs_source.Mult(G_, work2_, work_);  // |G||y|
    LocalRead abs_gy(work_), abs_y(work2_), c_f(c_f_), c_i(c_i_);
    LocalWrite sensitivity(sensitivity_);
    for (PetscInt r = 0; r < local_; ++r)
      sensitivity[r] =
          std::abs(c_f[r]) * abs_gy[r] + std::abs(c_i[r]) * abs_y[layout_.AColumn(r)];
  }

  // ---- trace, log, callback for iterate k; false when the callback stopped ------------
  bool Report(int k) {
    record_.iteration = k;
    record_.phi_inf = phi_inf_;
    record_.psi = psi_;
    record_.grad_psi_inf = have_jacobian_ && jacobian_ok_ ? NormInf(grad_) : 0.0;
    record_.degenerate_pairs = degenerate_count_;
    const bool reported = o_.keep_trace || o_.log_to_stderr || o_.callback;
    record_.time_s = reported ? Seconds(start_) : 0.0;
    if (o_.keep_trace) s_.trace.push_back(record_);
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n",
                   k, phi_inf_, psi_, record_.grad_psi_inf, record_.step_length,
                   record_.backtracks,
                   record_.gradient_step      ? "grad"
                   : record_.regularized_step ? "reg"
                                              : "newt",
                   degenerate_count_);
    if (o_.callback && AnyRank(comm_, !o_.callback(record_))) {
      Finish(
          TerminationType::kUserAbort,
          "the iteration callback stopped the solve at iteration " + std::to_string(k));
      return false;
    }
    return true;
  }

  // ---- step 1 and the safeguards; true when the solve ends here
  // ------------------------
  bool TestStop(int k) {
    if (converged_) {
      s_.roundoff_limited = roundoff_limited_;
      Finish(TerminationType::kConverged,
             internal::ConvergedMessage(o_, false, roundoff_limited_, phi_inf_, k));
      return true;
    }
    if (k >= o_.max_iterations) {
      Finish(TerminationType::kMaxIterations,
             internal::MaxIterationsMessage(o_, phi_inf_));
      return true;
    }
    if (OutOfTime("at iteration ", k)) return true;
    if (!jacobian_ok_) {
      Finish(TerminationType::kEvaluationFailure,
             "the Jacobian callback failed at iteration " + std::to_string(k));
      return true;
    }
    grad_inf_ = NormInf(grad_);
    if (stagnation_.Stagnated(static_cast<size_t>(k - first_k_), psi_, o_)) {
      Finish(TerminationType::kStationaryPoint,
             internal::StagnationMessage(o_, phi_inf_, grad_inf_));
      return true;
    }
    if (grad_inf_ == 0.0) {
      Finish(TerminationType::kStationaryPoint, internal::ZeroGradientMessage(phi_inf_));
      return true;
    }
    return false;
  }

  // Options::max_seconds passed on any rank? (collective only under a finite limit)
  bool OutOfTime(const char* where, int k) {
    if (!std::isfinite(o_.max_seconds)) return false;
    if (!AnyRank(comm_, Seconds(start_) > o_.max_seconds)) return false;
    Finish(TerminationType::kTimeLimit,
           internal::TimeLimitMessage(o_, where, k, phi_inf_));
    return true;
  }

  // ---- step 2: the direction d and slope_ = grad psi' d; true for d = -grad psi
  // --------
  // Newton J d = -Phi (eq. 21) kept if it passes the descent test (eq. 22); else, with
  // Options::regularized_direction, the Levenberg-Marquardt direction; else -grad psi.
  Direction ChooseDirection(int k) {
    const bool newton_solved = NewtonDirection();
    if (newton_solved && PassesDescentTest()) return Direction::kNewton;
    if (newton_solved)
      ++s_.descent_test_failures;
    else
      ++s_.linear_solver_failures;
    if (!o_.gradient_fallback) {
      if (!newton_solved)
        Finish(TerminationType::kLinearSolverFailure,
               "the Newton system is singular or the KSP solve (" +
                   impl_.report.ksp_type + " + " + impl_.report.pc_type +
                   ") failed at iteration " + std::to_string(k) +
                   " and gradient_fallback is off");
      return Direction::kNewton;  // Algorithm 1 without step 2's fallback
    }
    if (regularized_ && RegularizedDirection() && PassesDescentTest()) {
      ++s_.regularized_steps;
      return Direction::kRegularized;
    }
    NCP_PETSC_CHECK(VecCopy(grad_, d_));
    NCP_PETSC_CHECK(VecScale(d_, -1.0));
    slope_ = -Dot(grad_, grad_);
    ++s_.gradient_steps;
    return Direction::kGradient;
  }

  // grad psi' d <= -rho ||d||^p (eq. 22); sets the slope.
  bool PassesDescentTest() {
    slope_ = Dot(grad_, d_);
    PetscReal norm = 0.0;
    NCP_PETSC_CHECK(VecNorm(d_, NORM_2, &norm));
    return internal::PassesDescentTest(slope_, norm, o_);
  }

  // Levenberg-Marquardt direction (J'J + mu I) d = -J' Phi with mu = ||Phi||_2 (Fan and
  // Yuan 2005), the serial solver's, by the KSP lm_ksp (default MUMPS LU); false when the
  // KSP failed or d is not finite.
  bool RegularizedDirection() {
    const auto t0 = Clock::now();
    impl_.PrepareNormalMatrix(ExplicitJacobian(), std::sqrt(2.0 * psi_));
    NCP_PETSC_CHECK(VecCopy(grad_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    const bool solved =
        KspSolve(impl_.lm_ksp, impl_.normal, &impl_.lm_workspace_percent, work_, d_);
    s_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // J as a matrix: impl_.newton, or with symmetric_newton (where newton holds the
  // symmetrized system) impl_.lm_jacobian, created on first use and filled here.
  Mat ExplicitJacobian() {
    if (!impl_.symmetric_newton) return impl_.newton;
    if (!impl_.lm_jacobian)
      NCP_PETSC_CHECK(
          MatDuplicate(impl_.newton, MAT_DO_NOT_COPY_VALUES, &impl_.lm_jacobian));
    FillNewtonMatrix(impl_.lm_jacobian);
    return impl_.lm_jacobian;
  }

  // out = op^-1 rhs by ksp; false (on every rank) when the KSP failed or out is not
  // finite. A failed factorization is set up afresh (ResetFactorization): MUMPS skips
  // every numeric factorization after a failed one (its INFOG(1) stays < 0), while the
  // serial backends factorize each Newton matrix anew. When MUMPS ran out of its
  // estimated workspace (pivots delayed by the zero entries of slack rows, for one) the
  // same system is factorized again with ICNTL(14) doubled, kept in *workspace_percent
  // for the later factorizations of this KSP.
  bool KspSolve(KSP ksp, Mat op, int* workspace_percent, Vec rhs, Vec out) {
    constexpr int kWorkspaceRetries = 4;  // up to 2^4 times the first estimate's margin
    for (int attempt = 0;; ++attempt) {
      const PetscErrorCode code = KSPSolve(ksp, rhs, out);
      KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
      if (code == 0) {
        PetscInt its = 0;
        NCP_PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
        NCP_PETSC_CHECK(KSPGetIterationNumber(ksp, &its));
        impl_.report.linear_iterations += static_cast<int>(its);
        impl_.report.residual_test_iterations =
            static_cast<int>(impl_.outer_test.continued());
      }
      if (!AnyRank(comm_, code != 0 || reason == KSP_DIVERGED_PC_FAILED))
        return !AnyRank(comm_, reason <= 0) && AllFinite(comm_, out);
      const int more = MumpsWorkspaceToRetry(ksp);
      if (more > 0) *workspace_percent = more;
      ResetFactorization(ksp, op, *workspace_percent);
      if (more == 0 || attempt == kWorkspaceRetries) return false;
    }
  }

  // ICNTL(14) to factorize again with when ksp's PC is a MUMPS factorization that failed
  // for want of workspace (INFOG(1) = -8, -9, -11, -12, -14, -15, -17: MUMPS' "increase
  // ICNTL(14)" errors), else 0. The same answer on every rank.
  int MumpsWorkspaceToRetry(KSP ksp) {
    Mat F = MumpsFactor(ksp);
    PetscInt info = 0, percent = 0;
    if (F) {
      NCP_PETSC_CHECK(MatMumpsGetInfog(F, 1, &info));
      NCP_PETSC_CHECK(MatMumpsGetIcntl(F, 14, &percent));
    }
    const bool short_of_workspace = info == -8 || info == -9 || info == -11 ||
                                    info == -12 || info == -14 || info == -15 ||
                                    info == -17;
    if (!AnyRank(comm_, short_of_workspace)) return 0;
    return static_cast<int>(
        std::max<long long>(50, 2 * -MinRanks(comm_, -static_cast<long long>(percent))));
  }

  // The factorization of ksp's PC from scratch at the next solve, with MUMPS' ICNTL(14)
  // = workspace_percent when that is > 0.
  void ResetFactorization(KSP ksp, Mat op, int workspace_percent) {
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    NCP_PETSC_CHECK(PCReset(pc));
    NCP_PETSC_CHECK(KSPSetOperators(ksp, op, op));
    if (workspace_percent <= 0 || !UsesMumps(pc)) return;
    NCP_PETSC_CHECK(PCFactorSetUpMatSolverType(pc));
    Mat F = nullptr;
    NCP_PETSC_CHECK(PCFactorGetMatrix(pc, &F));
    NCP_PETSC_CHECK(MatMumpsSetIcntl(F, 14, workspace_percent));
  }

  static bool UsesMumps(PC pc) {
    PetscBool factor = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factor,
                                              PCLU, PCCHOLESKY, ""));
    MatSolverType type = nullptr;
    if (factor) NCP_PETSC_CHECK(PCFactorGetMatSolverType(pc, &type));
    return type && std::string(type) == MATSOLVERMUMPS;
  }
  // MUMPS' factor matrix of ksp's PC (after a solve), or nullptr for another PC.
  static Mat MumpsFactor(KSP ksp) {
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    if (!UsesMumps(pc)) return nullptr;
    Mat F = nullptr;
    NCP_PETSC_CHECK(PCFactorGetMatrix(pc, &F));
    return F;
  }

  // J d = -Phi (eq. 21) by the KSP; false when the KSP diverged, d is not finite or fails
  // the backward-error guard of globalization.hpp.
  bool NewtonDirection() {
    const auto t0 = Clock::now();
    NCP_PETSC_CHECK(VecCopy(phi_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    if (impl_.symmetric_newton && !Symmetrize(work_)) {
      s_.linear_solver_time_s += Seconds(t0);
      return false;
    }
    if (impl_.outer_test.AppliesTo(function_)) ArmOuterResidualTest();
    bool solved =
        KspSolve(impl_.ksp, impl_.newton, &impl_.newton_workspace_percent, work_, d_);
    impl_.outer_test.Disarm();
    if (solved) {
      MultNewton(d_, work_);  // J d + Phi
      NCP_PETSC_CHECK(VecAXPY(work_, 1.0, phi_));
      const double residual_inf = NormInf(work_);
      MultAbsNewton(d_, work_);  // |J||d|
      solved = internal::NewtonSolutionAccurate(residual_inf, phi_inf_, NormInf(work_));
    }
    s_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // The rows' weights and bounds of OuterResidualTest for this Newton system: the KSP's
  // row r is row r of J (weight 1), or in symmetric mode row r of J divided by c_F,r (a
  // kept row) or by c_I,r (an eliminated one); the bound is the fraction of the stopping
  // test's bound on |Phi_r| at this iterate (tolerance and round-off floor; sensitivity_
  // is this iterate's: WithinRoundoffFloor ran before the direction, or 0 without floor).
  void ArmOuterResidualTest() {
    {
      LocalRead c_f(c_f_), c_i(c_i_), sensitivity(sensitivity_);
      LocalWrite weight(ksp_row_weight_), bound(ksp_row_bound_);
      const double fraction = impl_.outer_test.fraction();
      for (PetscInt r = 0; r < local_; ++r) {
        weight[r] = !impl_.symmetric_newton ? 1.0 : c_f[r] != 0.0 ? c_f[r] : c_i[r];
        bound[r] = fraction * internal::RoundoffFloorBound(o_.tolerance, o_.roundoff_ulps,
                                                           sensitivity[r]);
      }
    }
    impl_.outer_test.Arm(ksp_row_weight_, ksp_row_bound_, ksp_residual_, ksp_work_);
  }

  // The same system J d = rhs made symmetric (the serial kCholmod backend's
  // transformation, types.hpp): a row with c_F != 0 is divided by c_F, giving diag(c_I /
  // c_F) + F'_i with c_I / c_F >= 0 for FB, min and penalized FB (both partials are <=
  // 0); a row with c_F = 0 fixes d_i = rhs_i / c_I and is eliminated from the others
  // (MatZeroRowsColumns). For a symmetric positive (semi)definite F' (obstacle problems)
  // the result is symmetric positive definite: CG and AMG apply. rhs is replaced by the
  // symmetric system's right-hand side; false when a row is zero (c_F = c_I = 0) on some
  // rank.
  bool Symmetrize(Vec rhs) {
    Mat S = impl_.newton;
    NCP_PETSC_CHECK(MatCopy(
        G_, S, impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    PetscInt first = 0, last = 0;
    NCP_PETSC_CHECK(VecGetOwnershipRange(y_, &first, &last));
    std::vector<PetscInt> fixed_rows;
    bool zero_row = false;
    {
      LocalRead c_f(c_f_), c_i(c_i_);
      LocalWrite b(rhs), ratio(work2_), known(fixed_values_);
      for (PetscInt i = 0; i < local_; ++i) {
        ratio[i] = 0.0;
        known[i] = 0.0;
        if (c_f[i] != 0.0) {
          ratio[i] = c_i[i] / c_f[i];
          b[i] = PetscRealPart(b[i]) / c_f[i];
        } else if (c_i[i] != 0.0) {
          known[i] = PetscRealPart(b[i]) / c_i[i];
          fixed_rows.push_back(first + i);
        } else {
          zero_row = true;
        }
      }
    }
    if (AnyRank(comm_, zero_row)) return false;
    NCP_PETSC_CHECK(MatDiagonalSet(S, work2_, ADD_VALUES));
    NCP_PETSC_CHECK(MatZeroRowsColumns(S, static_cast<PetscInt>(fixed_rows.size()),
                                       fixed_rows.data(), 1.0, fixed_values_, rhs));
    if (impl_.multigrid.grid()) {  // 1 on the eliminated rows of S, 0 on the others
      NCP_PETSC_CHECK(VecSet(work2_, 0.0));
      {
        LocalWrite eliminated(work2_);
        for (PetscInt row : fixed_rows) eliminated[row - first] = 1.0;
      }
      PC pc = nullptr;
      NCP_PETSC_CHECK(KSPGetPC(impl_.ksp, &pc));
      impl_.multigrid.Update(pc, S, work2_);
    }
    return true;
  }

  // ---- step 3: Armijo line search (internal::ArmijoLineSearch)
  // ----------------------------
  bool LineSearch(int k, Direction direction) {
    const double reference =
        armijo_reference_.Update(static_cast<size_t>(k - first_k_), psi_);
    using Trial = internal::LineSearchTrial;
    const internal::LineSearchResult r = internal::ArmijoLineSearch(
        o_, reference, slope_,
        [&] { return OutOfTime("in the line search of iteration ", k); },
        [&](double t) {
          NCP_PETSC_CHECK(VecWAXPY(x_trial_, t, d_, y_));
          PetscBool unchanged = PETSC_FALSE;
          NCP_PETSC_CHECK(VecEqual(x_trial_, y_, &unchanged));
          if (unchanged) return Trial{Trial::kUnchanged, 0.0};
          if (!Evaluate(x_trial_, f_trial_, phi_trial_))
            return Trial{Trial::kNotEvaluable, 0.0};
          if (!AllFinite(comm_, phi_trial_)) return Trial{Trial::kNonFinite, 0.0};
          return Trial{Trial::kEvaluated, 0.5 * Dot(phi_trial_, phi_trial_)};
        });
    if (r.out_of_time) {
      s_.backtracks += r.backtracks;
      return false;
    }
    s_.backtracks += std::min(r.backtracks, o_.max_backtracks);
    step_ = r.step;
    backtracks_ = r.backtracks;
    if (!r.accepted) {
      const internal::Ending ending = internal::LineSearchFailure(
          o_, r,
          direction == Direction::kGradient      ? "gradient"
          : direction == Direction::kRegularized ? "regularized"
                                                 : "Newton",
          k, phi_inf_, grad_inf_);
      Finish(ending.termination, ending.message);
    }
    return r.accepted;
  }

  // The point a restart or a new strategy continues from (box_mcp.cpp's RestartPoint): x
  // projected onto [l, u], the slacks recomputed from F there; false when F cannot be
  // evaluated there.
  bool RestartPoint(Vec y) {
    ProjectOntoBox(lower_, upper_, y);
    return layout_.total_slacks == 0 || SetSlacks(y);
  }

  // ---- the hybrid default (Options::hybrid, strategy.hpp) -----------------------------
  // Records iterate k; true when the strategy was left for slow progress or its budget
  // and the next one continues from its best point.
  bool LeaveStrategy(int k) {
    if (!o_.hybrid) return false;
    const auto kk = static_cast<size_t>(k - first_k_);
    Observe(kk, k);
    SwitchReason reason = SwitchReason::kStuck;
    return progress_.ShouldLeave(kk, k - strategy_start_, o_, &reason) &&
           SwitchStrategy(k, reason);
  }

  // psi(x^k) to the progress record, x^k kept when it is the strategy's best point.
  void Observe(size_t kk, int k) {
    if (progress_.Record(kk, psi_, k)) NCP_PETSC_CHECK(VecCopy(y_, best_y_));
  }

  // The next strategy of the schedule continues from the smallest-psi point of this one
  // (its RestartPoint), at iterate k (ncp::Solver's SwitchStrategy, step by step); false
  // (nothing changed) when no strategy is left or the point cannot be evaluated. kStuck
  // applies to a solve that ended at a non-solution stationary point, in a failed line
  // search or a failed Newton solve.
  bool SwitchStrategy(int k, SwitchReason reason) {
    if (!o_.hybrid) return false;
    const bool stuck = s_.termination == TerminationType::kStationaryPoint ||
                       s_.termination == TerminationType::kLineSearchFailure ||
                       s_.termination == TerminationType::kLinearSolverFailure;
    if (reason == SwitchReason::kStuck && !(finished_ && stuck)) return false;
    const Strategy from{function_, regularized_};
    if (!schedule_.Advance(from)) return false;
    const Strategy& to = schedule_.current();
    Observe(static_cast<size_t>(k - first_k_), k);  // (TestStop may have come first)
    NCP_PETSC_CHECK(VecCopy(best_y_, x_trial_));
    function_ = to.ncp_function;  // Evaluate() uses function_
    if (!RestartPoint(x_trial_) || !Evaluate(x_trial_, f_trial_, phi_trial_) ||
        !AllFinite(comm_, phi_trial_)) {
      function_ = from.ncp_function;
      return false;
    }
    s_.strategy_switches.push_back(progress_.SwitchRecord(k, from, to, reason));
    NCP_PETSC_CHECK(VecCopy(x_trial_, y_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    regularized_ = to.regularized_direction;
    if (o_.keep_trace && !s_.trace.empty()) s_.trace.pop_back();  // iterate k anew
    finished_ = false;
    s_.termination = TerminationType::kNotSolved;
    first_k_ = strategy_start_ = k;
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR,
                   "strategy %s -> %s at iteration %d (%s), from iteration %d\n",
                   internal::StrategyName(from).c_str(),
                   internal::StrategyName(to).c_str(), k, ToString(reason),
                   progress_.best_iteration());
    return true;
  }

  // ---- restart strategy (Options::merit_restarts): continue from mid(l, u, x^k), the
  // slacks recomputed (box_mcp.cpp's RestartPoint)
  bool Restart(int k) {
    if (!internal::MeritRestartApplies(s_.termination, restarts_left_, function_))
      return false;
    const NcpFunction stuck_function = function_;
    function_ = internal::OtherMeritFunction(function_);
    NCP_PETSC_CHECK(VecCopy(y_, x_trial_));
    if (!RestartPoint(x_trial_) || !Evaluate(x_trial_, f_trial_, phi_trial_) ||
        !AllFinite(comm_, phi_trial_)) {
      function_ = stuck_function;
      return false;
    }
    NCP_PETSC_CHECK(VecCopy(x_trial_, y_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    --restarts_left_;
    ++s_.merit_restarts;
    if (o_.keep_trace && !s_.trace.empty())
      s_.trace.pop_back();  // iterate k is reported anew
    finished_ = false;
    s_.termination = TerminationType::kNotSolved;
    first_k_ = k;
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "restart %d at iteration %d with %s\n",
                   s_.merit_restarts, k, ToString(function_));
    return true;
  }

  // ---- step 4: x^{k+1} = x^k + t d
  // -------------------------------------------------------
  void Accept(Direction direction) {
    NCP_PETSC_CHECK(VecCopy(x_trial_, y_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    ++s_.iterations;
    PetscReal norm = 0.0;
    NCP_PETSC_CHECK(VecNorm(d_, NORM_2, &norm));
    record_.step_length = step_;
    record_.direction_norm = norm;
    record_.backtracks = backtracks_;
    record_.gradient_step = direction == Direction::kGradient;
    record_.regularized_step = direction == Direction::kRegularized;
  }

  void Finish(TerminationType type, const std::string& message) {
    finished_ = true;
    s_.termination = type;
    s_.message = message;
    if (s_.merit_restarts > 0) s_.message += internal::RestartSuffix(s_.merit_restarts);
    s_.message += internal::StrategySwitchSuffix(s_.strategy_switches);
    s_.final_phi_inf = NormInf(phi_);
    s_.final_psi = 0.5 * Dot(phi_, phi_);
    s_.total_time_s = Seconds(start_);
  }

  Solver::Impl& impl_;
  const Options& o_;
  MPI_Comm comm_;
  const BoxMcp& p_;
  Vec x_;  // the caller's x (layout of F)
  Summary& s_;
  const MixedLayout& layout_;
  const std::vector<double>& lower_;  // of the rank's components, normalized
  const std::vector<double>& upper_;  // (+-inf = no bound)
  const PetscInt local_;              // rows of y on this rank
  Vec y_ = nullptr;                   // the unknowns: x_ itself, or y_owned_ with slacks
  OwnedVec y_owned_, x_part_;         // x_part_: the x part of a y (XPart)
  Mat G_ = nullptr;                   // G of the file comment
  // f_, f_trial_ laid out like x; x_trial_ (the trial y) and the others like y.
  OwnedVec f_, f_trial_, phi_, phi_trial_, grad_, d_, x_trial_, c_f_, c_i_, z_, f_z_,
      work_, work2_;
  OwnedVec fixed_values_;  // d_i of the rows the symmetrized system eliminates
  OwnedVec diag_g_;        // G_{r, AColumn(r)} (GDiagonalAtA)
  OwnedVec sensitivity_;   // r of the round-off floor at y (RoundoffSensitivity)
  // OuterResidualTest's rows: weights, bounds, and its work vectors.
  OwnedVec ksp_row_weight_, ksp_row_bound_, ksp_residual_, ksp_work_;
  Clock::time_point start_;
  NcpFunction function_ = NcpFunction::kFischerBurmeister;
  int restarts_left_ = 0, first_k_ = 0;  // first_k_: iterate of the last (re)start
  bool regularized_ = false;             // the current strategy tries the LM direction
  int strategy_start_ = 0;  // iterate the current strategy of the hybrid began at
  internal::StrategySchedule schedule_;
  internal::StrategyProgress progress_;
  OwnedVec best_y_;  // the current strategy's smallest-psi point (Options::hybrid)
  internal::StagnationTest stagnation_;
  internal::NonmonotoneReference armijo_reference_;
  IterationRecord record_;
  double phi_inf_ = 0.0, psi_ = 0.0, grad_inf_ = 0.0, slope_ = 0.0, step_ = 0.0;
  int backtracks_ = 0, degenerate_count_ = 0;
  bool converged_ = false, have_jacobian_ = false, jacobian_ok_ = true;
  bool roundoff_limited_ = false, finished_ = false;
};

// ---------------------------------------------------------------------------------------
// The public API.

BoxMcp BoxMcp::FromFunctionPointers(ResidualFunctionPointer residual,
                                    JacobianFunctionPointer jacobian, void* context,
                                    Mat jacobian_matrix, Vec lower, Vec upper) {
  BoxMcp p;
  if (residual)
    p.residual = [residual, context](Vec x, Vec f) { return residual(x, f, context); };
  if (jacobian)
    p.jacobian = [jacobian, context](Vec x, Mat J) { return jacobian(x, J, context); };
  p.jacobian_matrix = jacobian_matrix;
  p.lower = lower;
  p.upper = upper;
  return p;
}

namespace {

// A KSP with the options prefix `prefix` and the default of both linear systems: one
// direct solve by MUMPS' LU (Amestoy et al. 2001), exact up to round-off like the serial
// backends, so that the iterates are the serial solver's.
KSP DirectKsp(MPI_Comm comm, const std::string& prefix) {
  KSP ksp = nullptr;
  NCP_PETSC_CHECK(KSPCreate(comm, &ksp));
  NCP_PETSC_CHECK(KSPSetOptionsPrefix(ksp, prefix.c_str()));
  NCP_PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  NCP_PETSC_CHECK(PCSetType(pc, PCLU));
  NCP_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  return ksp;
}

}  // namespace

Solver::Solver(MPI_Comm comm, const Options& options, const std::string& options_prefix)
    : impl_(new Impl) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    throw std::invalid_argument(
        "ncp::petsc::Solver: PETSc is not initialized; call PetscInitialize "
        "before constructing the solver (and PetscFinalize after destroying it)");
  std::string error;
  if (!options.IsValid(&error))
    throw std::invalid_argument("ncp::petsc::Solver: " + error);
  if (options.linear_solver != LinearSolverType::kAuto)
    throw std::invalid_argument(
        std::string("ncp::petsc::Solver: Options::linear_solver = ") +
        ToString(options.linear_solver) +
        " names a serial backend; over PETSc the Newton systems are solved by "
        "the KSP (leave kAuto, choose with -" +
        options_prefix + "ksp_type / -" + options_prefix + "pc_type)");
  impl_->comm = comm;
  impl_->options = options;
  impl_->prefix = options_prefix;
  impl_->ksp = DirectKsp(comm, options_prefix);
  impl_->lm_ksp = DirectKsp(comm, options_prefix + "lm_");
  int size = 0;
  MPI_Comm_size(comm, &size);
  impl_->report.ranks = size;
}

Solver::~Solver() = default;

void Solver::SetMultigridGrid(DM grid) { impl_->multigrid.SetGrid(grid); }

namespace {

// Solver::SetMultigridGrid's preconditions, checked collectively at the solve; the
// hierarchy is built here at the first solve on the grid.
void CheckMultigridGrid(MPI_Comm comm, KSP ksp, const std::string& prefix,
                        bool symmetric_newton, InactiveSetMultigrid& multigrid, Vec x) {
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  PetscBool mg = PETSC_FALSE;
  NCP_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCMG, &mg));
  if (!mg || !symmetric_newton)
    Misuse(
        "SetMultigridGrid restricts PCMG to the inactive set of the symmetrized "
        "Newton system: it needs -" +
        prefix + "pc_type mg and the symmetric mode (a CG-like KSP or -" + prefix +
        "symmetric_newton true); the PC is " +
        (mg ? std::string("mg") : std::string("not mg")) + ", symmetric mode " +
        (symmetric_newton ? "on" : "off"));
  Vec layout = nullptr;
  NCP_PETSC_CHECK(DMCreateGlobalVector(multigrid.grid(), &layout));
  PetscInt grid_local = 0, x_local = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(layout, &grid_local));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &x_local));
  VecDestroy(&layout);
  if (AnyRank(comm, grid_local != x_local))
    Misuse("the multigrid grid's global vectors have " + std::to_string(grid_local) +
           " local entries, the start point " + std::to_string(x_local) +
           " (on some rank): the grid must be the one x lives on");
  if (!multigrid.attached()) multigrid.Attach(pc);
}

}  // namespace
const Options& Solver::options() const { return impl_->options; }
KSP Solver::ksp() const { return impl_->ksp; }
const KspReport& Solver::ksp_report() const { return impl_->report; }

void Solver::Solve(const BoxMcp& problem, Vec x, Summary* summary) {
  Impl& impl = *impl_;
  const Options& o = impl.options;
  if (x == nullptr || summary == nullptr) Misuse("x and summary must not be null");
  if (!problem.residual || !problem.jacobian)
    Misuse("BoxMcp::residual and BoxMcp::jacobian must be set");
  if (problem.jacobian_matrix == nullptr) Misuse("BoxMcp::jacobian_matrix must be set");
  int compare = MPI_UNEQUAL;
  MPI_Comm_compare(PetscObjectComm(reinterpret_cast<PetscObject>(x)), impl.comm,
                   &compare);
  if (compare != MPI_IDENT && compare != MPI_CONGRUENT)
    Misuse("the start point lives on another communicator than the solver");
  if (problem.lower) CheckLayout(impl.comm, x, problem.lower, "lower");
  if (problem.upper) CheckLayout(impl.comm, x, problem.upper, "upper");
  CheckMatrixLayout(impl.comm, x, problem.jacobian_matrix);
  bool parallel = false;
  if (AnyRank(impl.comm, !IsAij(problem.jacobian_matrix, &parallel)))
    Misuse("the Jacobian matrix must be of type AIJ (MATSEQAIJ or MATMPIAIJ)");

  // Local bounds, normalized (|b| >= infinite_bound is no bound), and the rows.
  PetscInt local = 0, first = 0, last = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(x, &local));
  NCP_PETSC_CHECK(VecGetOwnershipRange(x, &first, &last));
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> lower(static_cast<size_t>(local), -kInf),
      upper(static_cast<size_t>(local), kInf);
  for (auto [bound, out] :
       {std::pair<Vec, std::vector<double>*>{problem.lower, &lower},
        std::pair<Vec, std::vector<double>*>{problem.upper, &upper}}) {
    if (!bound) continue;
    LocalRead a(bound);
    for (PetscInt i = 0; i < local; ++i)
      (*out)[static_cast<size_t>(i)] = NormalizeBound(a[i], o.infinite_bound);
  }
  CheckBoundsAndStart(impl.comm, first, lower, upper, x);
  const MixedLayout layout(impl.comm, std::move(lower), std::move(upper));
  impl.Configure();
  if (impl.multigrid.grid())
    CheckMultigridGrid(impl.comm, impl.ksp, impl.prefix, impl.symmetric_newton,
                       impl.multigrid, x);
  if (impl.symmetric_newton && layout.total_slacks > 0)
    Misuse(
        "two-sided bounds (l < u, both finite) at " +
        std::to_string(layout.total_slacks) +
        " components make the Newton matrix of the slack form unsymmetric, and the "
        "KSP asks for the symmetrized Newton system (a CG-like KSP, Cholesky/ICC or -" +
        impl.prefix +
        "symmetric_newton true): use a KSP for unsymmetric systems (the default LU, "
        "GMRES) and -" +
        impl.prefix + "symmetric_newton false");

  // Options::project_start_point: x0 <- mid(l, u, x0).
  const long long moved =
      o.project_start_point
          ? SumRanks(impl.comm, ProjectOntoBox(layout.lower, layout.upper, x))
          : 0;

  Iteration(impl, problem, x, *summary, layout).Run();

  summary->projected_start_components = static_cast<int>(moved);
  if (moved > 0)
    summary->message +=
        " (" + std::to_string(moved) +
        " components of the start point were outside [l, u] and were projected onto it)";
  // The returned x lies in [l, u] whatever the status (FB iterates may leave the box),
  // as ncp::Solver's.
  double largest = 0.0;
  const long long outside =
      SumRanks(impl.comm, ProjectOntoBox(layout.lower, layout.upper, x, &largest));
  double largest_all = 0.0;
  MPI_Allreduce(&largest, &largest_all, 1, MPI_DOUBLE, MPI_MAX, impl.comm);
  summary->projected_final_components = static_cast<int>(outside);
  if (outside > 0)
    summary->message += " (" + std::to_string(outside) +
                        " components of the last iterate were outside [l, u], by up to " +
                        FormatNumber("%.3e", largest_all) +
                        ", and were projected onto it)";
}

}  // namespace ncp::petsc
