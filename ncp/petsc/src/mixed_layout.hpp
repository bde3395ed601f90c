// The rows of the box MCP written as the serial solver's mixed form, rank by rank, and
// the matrix G of two-sided bounds.
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
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "huge_page_memory.hpp"
#include "petsc_support.hpp"

namespace ncp::petsc {

// The kind of row r of the mixed form (the comment above): kSplit is the equation F_i - w
// + v of a two-sided component, kLowerSlack / kUpperSlack its pairs (x_i - l_i, w) and
// (u_i - x_i, v).
enum class Row : char { kFree, kFixed, kLower, kUpper, kSplit, kLowerSlack, kUpperSlack };

inline bool IsSlackRow(Row row) {
  return row == Row::kLowerSlack || row == Row::kUpperSlack;
}

inline double NormalizeBound(double bound, double infinite_bound) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  return bound >= infinite_bound ? kInf : bound <= -infinite_bound ? -kInf : bound;
}

// The first lower.size() local entries x of v <- mid(l, u, x), the projection onto the
// box; returns how many moved on this rank and (in *largest) by how much at most.
inline long long ProjectOntoBox(const LocalArray<double>& lower,
                                const LocalArray<double>& upper, Vec v,
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
  LocalArray<Row> rows;  // kind of row r of y and of Phi
  // kSplit: its slack k; kLowerSlack, kUpperSlack: its component i; otherwise r itself.
  LocalArray<PetscInt> link;
  LocalArray<double> lower, upper;  // bounds of the rank's components, normalized
  PetscInt components = 0, slacks = 0;
  PetscInt total_slacks = 0;  // over all ranks

  // The rows of components with the (normalized) bounds lower, upper.
  MixedLayout(MPI_Comm comm, LocalArray<double> lower_bounds,
              LocalArray<double> upper_bounds)
      : lower(std::move(lower_bounds)), upper(std::move(upper_bounds)) {
    components = static_cast<PetscInt>(lower.size());
    rows.reserve(lower.size());
    link.reserve(lower.size());
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

  // (A_r, B_r) of a pair row at the local entries y of the unknowns and f of F(x); false
  // for an equation row.
  bool PairValues(PetscInt r, const LocalRead& y, const LocalRead& f, double* a,
                  double* b) const {
    const PetscInt i = AColumn(r);  // the component
    const auto ii = static_cast<size_t>(i);
    switch (row(r)) {
      case Row::kLower:
        *a = y[i] - lower[ii];
        *b = f[i];
        return true;
      case Row::kUpper:
        *a = upper[ii] - y[i];
        *b = -f[i];
        return true;
      case Row::kLowerSlack:
        *a = y[i] - lower[ii];
        *b = y[r];
        return true;
      case Row::kUpperSlack:
        *a = upper[ii] - y[i];
        *b = y[r];
        return true;
      default:
        return false;
    }
  }
};

// G of the comment above for a layout with slacks: F' with its columns renumbered from x
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

}  // namespace ncp::petsc
