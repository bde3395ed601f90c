// The box MCP  l <= x <= u  perp  F(x)  written in the mixed form of the thesis (eq. 12):
//
//   free      (l = -inf, u = +inf):  equation  F_i(x) = 0
//   fixed     (l = u):               equation  x_i - l_i = 0
//   lower     (l finite, u = +inf):  pair      (x_i - l_i,  F_i(x))
//   upper     (l = -inf, u finite):  pair      (u_i - x_i, -F_i(x))
//   two-sided (l < u both finite):   F_i(x) = w_k - v_k with two slack unknowns w_k, v_k
//                                    and pairs (x_i - l_i, w_k), (u_i - x_i, v_k).
//
// The slacks are the positive and negative parts of F_i: at a solution w_k = max(F_i, 0),
// v_k = max(-F_i, 0); they also start there. Unknowns are ordered [x; w; v] and each pair
// is associated (for the z-vector rule) with x_i, or with its slack for two-sided bounds.

#include "box_mcp.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "ncp_function_internal.hpp"
#include "sparse_pattern.hpp"

namespace ncp::internal {
namespace {

using Triplet = Eigen::Triplet<double, int>;

/// x <- mid(l, u, x), the Euclidean projection onto the box; returns how many
/// components moved.
int ProjectOntoBox(const Vector& lower, const Vector& upper, Vector* x) {
  int moved = 0;
  for (Eigen::Index i = 0; i < x->size(); ++i) {
    const double projected = std::max(lower(i), std::min(upper(i), (*x)(i)));
    if (projected != (*x)(i)) ++moved;
    (*x)(i) = projected;
  }
  return moved;
}

/// Like ProjectOntoBox; *largest = the largest distance a component moved.
int ProjectOntoBox(const Vector& lower, const Vector& upper, Vector* x, double* largest) {
  *largest = 0.0;
  for (Eigen::Index i = 0; i < x->size(); ++i)
    *largest = std::max(
        *largest, std::abs(std::max(lower(i), std::min(upper(i), (*x)(i))) - (*x)(i)));
  return ProjectOntoBox(lower, upper, x);
}

/// Bounds with |b| >= infinite_bound are infinite (GAMS and PATH write "no bound" as
/// +-1e20); a lower bound >= infinite_bound becomes +inf (an empty box, rejected later).
double NormalizeBound(double bound, double infinite_bound) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  return bound >= infinite_bound ? kInf : bound <= -infinite_bound ? -kInf : bound;
}

}  // namespace

/// The box MCP as a mixed problem; the Solver keeps it between solves (Matches: same size
/// and bounds; F is bound anew by Rebind) so that a problem solved again reuses its
/// Jacobian structure (checked against F's pattern at every Jacobian) and allocates
/// nothing.
class BoxMcpAsMixed final : public MixedProblem, public DenseMixedJacobian {
 public:
  /// lower and upper as given (sizes checked by the caller); bounds with |b| >=
  /// infinite_bound are stored as infinite.
  BoxMcpAsMixed(SquareFunction& F, const Vector& lower_given, const Vector& upper_given,
                double infinite_bound)
      : F_(&F),
        n_(F.NumVariables()),
        lower_(n_),
        upper_(n_),
        infinite_bound_(infinite_bound) {
    for (int i = 0; i < n_; ++i) {
      lower_(i) = NormalizeBound(lower_given(i), infinite_bound);
      upper_(i) = NormalizeBound(upper_given(i), infinite_bound);
    }
    const Vector& lower = lower_;
    const Vector& upper = upper_;
    // Equations first: free, fixed, two-sided; then pairs.
    std::vector<int> two_sided;
    for (int i = 0; i < n_; ++i) {
      const bool lo = std::isfinite(lower(i)), up = std::isfinite(upper(i));
      if (!lo && !up)
        equations_.push_back({Kind::kFree, i, -1});
      else if (lo && up && lower(i) == upper(i))
        equations_.push_back({Kind::kFixed, i, -1});
      else if (lo && up)
        two_sided.push_back(i);
    }
    num_slacks_ = static_cast<int>(two_sided.size());
    for (int k = 0; k < num_slacks_; ++k)
      equations_.push_back({Kind::kSlackSplit, two_sided[static_cast<size_t>(k)], k});
    for (int i = 0; i < n_; ++i) {
      const bool lo = std::isfinite(lower(i)), up = std::isfinite(upper(i));
      if (lo && !up) pairs_.push_back({Kind::kLower, i, -1});
      if (!lo && up) pairs_.push_back({Kind::kUpper, i, -1});
    }
    for (int k = 0; k < num_slacks_; ++k) {
      pairs_.push_back({Kind::kLowerSlack, two_sided[static_cast<size_t>(k)], k});
      pairs_.push_back({Kind::kUpperSlack, two_sided[static_cast<size_t>(k)], k});
    }
    Fx_.resize(n_);
    x_.resize(n_);
    BuildDenseLayout();
  }

  /// Same number of variables and the same bounds (after NormalizeBound) as this one was
  /// built for: the mixed form's rows depend on nothing else.
  bool Matches(const SquareFunction& F, const Vector& lower, const Vector& upper,
               double infinite_bound) const {
    if (F.NumVariables() != n_ || infinite_bound != infinite_bound_) return false;
    for (int i = 0; i < n_; ++i)
      if (!SameBound(NormalizeBound(lower(i), infinite_bound), lower_(i)) ||
          !SameBound(NormalizeBound(upper(i), infinite_bound), upper_(i)))
        return false;
    return true;
  }
  void Rebind(SquareFunction& F) { F_ = &F; }
  const Vector& lower() const { return lower_; }
  const Vector& upper() const { return upper_; }
  /// The unknowns [x; slacks] of the mixed form, kept for the next solve.
  Vector& unknowns() { return y_; }

  int NumVariables() const override { return n_ + 2 * num_slacks_; }
  int NumEquations() const override { return static_cast<int>(equations_.size()); }
  int PairVariable(int j) const override {
    const Row& r = pairs_[static_cast<size_t>(j)];
    if (r.kind == Kind::kLowerSlack) return n_ + r.slack;
    if (r.kind == Kind::kUpperSlack) return n_ + num_slacks_ + r.slack;
    return r.index;
  }
  int num_slacks() const { return num_slacks_; }

  bool Evaluate(const Vector& y, Vector* E, Vector* A, Vector* B) override {
    if (!F_->Evaluate(XPart(y), &Fx_)) return false;
    if (Fx_.size() != n_)
      throw std::invalid_argument("ncp: SquareFunction::Evaluate returned size " +
                                  std::to_string(Fx_.size()) + ", expected " +
                                  std::to_string(n_));
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const auto row = static_cast<Eigen::Index>(e);
      if (r.kind == Kind::kFree)
        (*E)(row) = Fx_(r.index);
      else if (r.kind == Kind::kFixed)
        (*E)(row) = y(r.index) - lower_(r.index);
      else
        (*E)(row) = Fx_(r.index) - y(n_ + r.slack) + y(n_ + num_slacks_ + r.slack);
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const auto row = static_cast<Eigen::Index>(j);
      switch (r.kind) {
        case Kind::kLower:
          (*A)(row) = y(r.index) - lower_(r.index);
          (*B)(row) = Fx_(r.index);
          break;
        case Kind::kUpper:
          (*A)(row) = upper_(r.index) - y(r.index);
          (*B)(row) = -Fx_(r.index);
          break;
        case Kind::kLowerSlack:
          (*A)(row) = y(r.index) - lower_(r.index);
          (*B)(row) = y(n_ + r.slack);
          break;
        default:
          (*A)(row) = upper_(r.index) - y(r.index);
          (*B)(row) = y(n_ + num_slacks_ + r.slack);
          break;
      }
    }
    return true;
  }

  /// [JE; JA; JB] of the mixed form. The pattern follows F's: while F' keeps its pattern
  /// and the solver hands back the matrices it got last time, only the values are written
  /// (no allocation); otherwise the structure is built again (BuildStructure).
  bool Jacobian(const Vector& y, SparseMatrix* JE, SparseMatrix* JA,
                SparseMatrix* JB) override {
    if (!EvaluateF(y)) return false;
    SparseMatrix* out[3] = {JE, JA, JB};
    if (!StructureMatches(out)) BuildStructure(out);
    FillValues(out);
    return true;
  }

  /// The point a restart continues from (Options::merit_restarts): x projected onto
  /// [l, u], slacks recomputed. The FB iterates may leave the box; a point where the
  /// merit function is stuck outside it is generally not stationary once projected.
  bool RestartPoint(Vector* y) override {
    x_ = y->head(n_);
    ProjectOntoBox(lower_, upper_, &x_);
    return InitialSlacks(x_, y);
  }

  // ---- DenseMixedJacobian: the rows of Phi written dense straight from F' ----------

  bool EvaluateDerivative(const Vector& y) override { return EvaluateF(y); }

  /// za = JA z: the one constant of each A row; zb = JB z: a row of F' (times its sign)
  /// or a slack's constant. Sums in the order of JA * z and JB * z (column by column).
  void MultiplyPairJacobians(const Vector& z, Vector* za, Vector* zb) const override {
    za->setZero();
    zb->setZero();
    for (const DenseConstant& c : a_constants_) (*za)(c.pair) += c.value * z(c.column);
    for (int col = 0; col < n_; ++col)
      for (int k = JF_.outerIndexPtr()[col]; k < JF_.outerIndexPtr()[col + 1]; ++k) {
        const int r = JF_.innerIndexPtr()[k];
        const int j = f_row_pair_[static_cast<size_t>(r)];
        if (j >= 0)
          (*zb)(j) += f_row_sign_[static_cast<size_t>(r)] * JF_.valuePtr()[k] * z(col);
      }
    for (const DenseConstant& c : other_constants_)
      if (c.pair >= 0) (*zb)(c.pair) += c.value * z(c.column);
  }

  /// Jd row by row as FillValues and the solver's FillDenseJacobian would make it: per
  /// row of Phi first A's constant (times da), then the row of F' in column order (times
  /// the row's sign, and db for a pair), then the constants of slacks and fixed
  /// variables.
  bool Fill(const Vector& da, const Vector& db, const Vector& y, DenseMatrix* Jd,
            Vector* sensitivity) const override {
    const Eigen::Index size = NumVariables();
    Jd->setZero(size, size);
    sensitivity->setZero(size);
    double* const J = Jd->data();  // column-major, leading dimension size
    double* const r_sum = sensitivity->data();
    auto add = [&](int row, int col, double value) {
      J[row + col * size] += value;
      r_sum[row] += std::abs(value) * std::abs(y(col));
    };
    for (const DenseConstant& c : a_constants_)
      add(c.row, c.column, da(c.pair) * c.value);
    for (int r = 0; r < n_; ++r) {
      const int j = f_row_pair_[static_cast<size_t>(r)];
      row_factor_(r) = f_row_sign_[static_cast<size_t>(r)] * (j >= 0 ? db(j) : 1.0);
    }
    bool finite = true;
    const int* const outer = JF_.outerIndexPtr();
    const int* const inner = JF_.innerIndexPtr();
    const double* const values = JF_.valuePtr();
    for (int col = 0; col < n_; ++col) {
      double* const J_col = J + col * size;
      const double y_col = std::abs(y(col));
      for (int k = outer[col]; k < outer[col + 1]; ++k) {
        const int row = f_row_target_[static_cast<size_t>(inner[k])];
        if (row < 0) continue;  // a fixed variable's row of F
        finite &= std::isfinite(values[k]);
        const double value = row_factor_(inner[k]) * values[k];
        J_col[row] += value;
        r_sum[row] += std::abs(value) * y_col;
      }
    }
    for (const DenseConstant& c : other_constants_)
      add(c.row, c.column, c.pair >= 0 ? db(c.pair) * c.value : c.value);
    return finite;
  }

  /// True when JF_ has the pattern the structure was built for and each output still has
  /// the pattern it was given (the solver scales values in place, never the pattern).
  bool StructureMatches(SparseMatrix* const out[3]) const {
    if (!structure_built_ || !jf_pattern_.Matches(JF_)) return false;
    for (int s = 0; s < 3; ++s)
      if (!out_pattern_[s].Matches(*out[s])) return false;
    return true;
  }

  /// The rows of the mixed form (file comment) as triplets, then a map from each stored
  /// entry of F' to the entry of JE or JB it becomes (with the sign of the row), and the
  /// constant entries (+-1 of bounds and slacks) kept apart. The triplet values encode
  /// the source: k + 1 for entry k of F', -(c + 1) for constant c. No two sources share
  /// an entry (F' rows fill columns < n, slacks columns >= n, bound rows hold no F' row).
  void BuildStructure(SparseMatrix* const out[3]) {
    // Entries of F' grouped by row, with their columns.
    const auto nnz = static_cast<size_t>(JF_.nonZeros());
    std::vector<std::vector<std::pair<int, int>>> row_entries(
        static_cast<size_t>(n_));  // (k, col)
    for (int c = 0; c < n_; ++c)
      for (int k = JF_.outerIndexPtr()[c]; k < JF_.outerIndexPtr()[c + 1]; ++k)
        row_entries[static_cast<size_t>(JF_.innerIndexPtr()[k])].emplace_back(k, c);
    std::vector<Triplet> t[3];
    entry_sign_.assign(nnz, 0.0);
    constants_.clear();
    auto add_row = [&](int s, int out_row, int f_row, double sign) {
      for (const auto& [k, col] : row_entries[static_cast<size_t>(f_row)]) {
        t[s].emplace_back(out_row, col, static_cast<double>(k + 1));
        entry_sign_[static_cast<size_t>(k)] = sign;
      }
    };
    auto add_constant = [&](int s, int out_row, int col, double value) {
      constants_.push_back(value);
      t[s].emplace_back(out_row, col, -static_cast<double>(constants_.size()));
    };
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const int row = static_cast<int>(e);
      if (r.kind == Kind::kFree)
        add_row(0, row, r.index, 1.0);
      else if (r.kind == Kind::kFixed)
        add_constant(0, row, r.index, 1.0);
      else {
        add_row(0, row, r.index, 1.0);
        add_constant(0, row, n_ + r.slack, -1.0);
        add_constant(0, row, n_ + num_slacks_ + r.slack, 1.0);
      }
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const int row = static_cast<int>(j);
      switch (r.kind) {
        case Kind::kLower:
          add_constant(1, row, r.index, 1.0);
          add_row(2, row, r.index, 1.0);
          break;
        case Kind::kUpper:
          add_constant(1, row, r.index, -1.0);
          add_row(2, row, r.index, -1.0);
          break;
        case Kind::kLowerSlack:
          add_constant(1, row, r.index, 1.0);
          add_constant(2, row, n_ + r.slack, 1.0);
          break;
        default:
          add_constant(1, row, r.index, -1.0);
          add_constant(2, row, n_ + num_slacks_ + r.slack, 1.0);
          break;
      }
    }
    entry_target_.assign(nnz, {-1, -1});
    for (int s = 0; s < 3; ++s) {
      SparseMatrix& S = *out[s];
      S.setFromTriplets(t[s].begin(), t[s].end());
      S.makeCompressed();
      constant_slots_[s].clear();
      for (int q = 0; q < static_cast<int>(S.nonZeros()); ++q) {
        const double code = S.valuePtr()[q];
        if (code >= 1.0)
          entry_target_[static_cast<size_t>(code) - 1] = {s, q};
        else
          constant_slots_[s].push_back({q, constants_[static_cast<size_t>(-code) - 1]});
      }
      out_pattern_[s].Store(S);
    }
    jf_pattern_.Store(JF_);
    structure_built_ = true;
  }

  /// Values of JE, JA, JB from F' through the map of BuildStructure.
  void FillValues(SparseMatrix* const out[3]) const {
    for (int s = 0; s < 3; ++s)
      for (const ConstantSlot& slot : constant_slots_[s])
        out[s]->valuePtr()[slot.position] = slot.value;
    const double* values = JF_.valuePtr();
    for (size_t k = 0; k < entry_target_.size(); ++k) {
      const Target& target = entry_target_[k];
      if (target.matrix >= 0)
        out[target.matrix]->valuePtr()[target.position] = entry_sign_[k] * values[k];
    }
  }

  /// The layout of the dense Jacobian (DenseMixedJacobian) from the rows of the mixed
  /// form: where each row of F' goes, with which sign, and the constant entries.
  void BuildDenseLayout() {
    f_row_target_.assign(static_cast<size_t>(n_), -1);
    f_row_pair_.assign(static_cast<size_t>(n_), -1);
    f_row_sign_.assign(static_cast<size_t>(n_), 1.0);
    row_factor_.resize(n_);
    auto f_row = [&](int f_row, int phi_row, int pair, double sign) {
      f_row_target_[static_cast<size_t>(f_row)] = phi_row;
      f_row_pair_[static_cast<size_t>(f_row)] = pair;
      f_row_sign_[static_cast<size_t>(f_row)] = sign;
    };
    const int m = NumEquations();
    for (int e = 0; e < m; ++e) {
      const Row& r = equations_[static_cast<size_t>(e)];
      if (r.kind == Kind::kFixed) {
        other_constants_.push_back({e, r.index, 1.0, -1});
        continue;
      }
      f_row(r.index, e, -1, 1.0);
      if (r.kind == Kind::kSlackSplit) {
        other_constants_.push_back({e, n_ + r.slack, -1.0, -1});
        other_constants_.push_back({e, n_ + num_slacks_ + r.slack, 1.0, -1});
      }
    }
    for (int j = 0; j < static_cast<int>(pairs_.size()); ++j) {
      const Row& r = pairs_[static_cast<size_t>(j)];
      const bool lower_side = r.kind == Kind::kLower || r.kind == Kind::kLowerSlack;
      a_constants_.push_back({m + j, r.index, lower_side ? 1.0 : -1.0, j});
      if (r.kind == Kind::kLower || r.kind == Kind::kUpper)
        f_row(r.index, m + j, j, lower_side ? 1.0 : -1.0);
      else
        other_constants_.push_back(
            {m + j,
             r.kind == Kind::kLowerSlack ? n_ + r.slack : n_ + num_slacks_ + r.slack, 1.0,
             j});
    }
  }

  /// Start point of the slacks: the positive and negative parts of F at x0.
  bool InitialSlacks(const Vector& x0, Vector* y) {
    y->setZero(NumVariables());
    y->head(n_) = x0;
    if (num_slacks_ == 0) return true;
    if (!F_->Evaluate(x0, &Fx_) || !Fx_.allFinite()) return false;
    for (const Row& r : equations_) {
      if (r.kind != Kind::kSlackSplit) continue;
      (*y)(n_ + r.slack) = std::max(Fx_(r.index), 0.0);
      (*y)(n_ + num_slacks_ + r.slack) = std::max(-Fx_(r.index), 0.0);
    }
    return true;
  }

 private:
  enum class Kind {
    kFree,
    kFixed,
    kSlackSplit,
    kLower,
    kUpper,
    kLowerSlack,
    kUpperSlack
  };
  struct Row {
    Kind kind;
    int index;  // variable i of the box MCP
    int slack;  // k for two-sided variables, else -1
  };
  /// F' at the x of y into JF_ (compressed); false when F cannot give it.
  bool EvaluateF(const Vector& y) {
    if (!F_->Jacobian(XPart(y), &JF_)) return false;
    if (JF_.rows() != n_ || JF_.cols() != n_)
      throw std::invalid_argument("ncp: SquareFunction::Jacobian returned " +
                                  std::to_string(JF_.rows()) + " x " +
                                  std::to_string(JF_.cols()) + ", expected " +
                                  std::to_string(n_) + " x " + std::to_string(n_));
    JF_.makeCompressed();
    return true;
  }

  /// x of the unknowns y = [x; slacks], without a temporary.
  const Vector& XPart(const Vector& y) {
    if (num_slacks_ == 0) return y;
    x_ = y.head(n_);
    return x_;
  }

  static bool SameBound(double a, double b) {
    return a == b || (std::isnan(a) && std::isnan(b));
  }

  SquareFunction* F_;
  int n_;
  Vector lower_, upper_, Fx_, x_, y_;
  double infinite_bound_;
  SparseMatrix JF_;
  std::vector<Row> equations_, pairs_;
  int num_slacks_ = 0;
  // The Jacobian structure (BuildStructure): patterns it was built for, where each entry
  // of F' goes (matrix 0/1/2 = JE/JA/JB, value position; -1: nowhere, a fixed variable's
  // row) with its sign, and the constant entries.
  struct Target {
    int matrix, position;
  };
  struct ConstantSlot {
    int position;
    double value;
  };
  bool structure_built_ = false;
  SparsePattern jf_pattern_, out_pattern_[3];
  std::vector<Target> entry_target_;
  std::vector<double> entry_sign_, constants_;
  std::vector<ConstantSlot> constant_slots_[3];
  // The dense layout (BuildDenseLayout): row i of F' is row f_row_target_[i] of Phi (-1:
  // none, a fixed variable) times f_row_sign_[i], and times db of pair f_row_pair_[i]
  // (-1: an equation); the constant entries of A rows (times da), and the others (of
  // equations, or of B rows times db: `pair` >= 0). row_factor_: the factor of each row
  // of F' in one Fill.
  struct DenseConstant {
    int row, column;
    double value;
    int pair;
  };
  std::vector<int> f_row_target_, f_row_pair_;
  std::vector<double> f_row_sign_;
  std::vector<DenseConstant> a_constants_, other_constants_;
  mutable Vector row_factor_;
};

namespace {

void CheckSizes(int n, const Vector& lower, const Vector& upper, const Vector& x) {
  auto size_error = [&](const char* what, Eigen::Index got) {
    throw std::invalid_argument(std::string("ncp::Solver::Solve (box MCP): ") + what +
                                " has size " + std::to_string(got) +
                                ", expected NumVariables() = " + std::to_string(n));
  };
  if (lower.size() != n) size_error("lower", lower.size());
  if (upper.size() != n) size_error("upper", upper.size());
  if (x.size() != n) size_error("the start point", x.size());
}

/// Bounds (normalized) and start point; the message is built only for the first bad
/// entry.
void CheckBounds(const Vector& lower, const Vector& upper, const Vector& x) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const bool nan = std::isnan(lower(i)) || std::isnan(upper(i));
    const bool crossed = lower(i) > upper(i);
    const bool empty = lower(i) == std::numeric_limits<double>::infinity() ||
                       upper(i) == -std::numeric_limits<double>::infinity();
    const bool bad_start = !std::isfinite(x(i));
    if (!(nan || crossed || empty || bad_start)) continue;
    const std::string at = "[" + std::to_string(i) + "]";
    if (nan)
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): bound" + at + " is NaN");
    if (crossed)
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): lower" + at + " = " +
                                  std::to_string(lower(i)) + " > upper" + at + " = " +
                                  std::to_string(upper(i)));
    if (empty)
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): empty box at" + at +
                                  " (lower = +inf or upper = -inf)");
    throw std::invalid_argument("ncp::Solver::Solve: start point x" + at + " = " +
                                std::to_string(x(i)) + " is not finite");
  }
}

// ---------------------------------------------------------------------------------------
// Infeasibility of a box LCP (TerminationType::kInfeasible). A solution x of
// l <= x <= u perp F(x) = M x + q has F(x) in the cone K of the bounds: F_i >= 0 where
// only l_i is finite, F_i <= 0 where only u_i is, F_i = 0 where neither is (no condition
// on two-sided or fixed rows). Farkas: if some y in the dual cone K* (y_i >= 0, <= 0,
// free, 0 on those rows) has
//     sup_{x in [l, u]} y'(M x + q) = q'y + sum_i sup_{x_i in [l_i, u_i]} g_i x_i < 0,
// g = M'y, then y'F(x) < 0 on the whole box while y'F(x) >= 0 at any x with F(x) in K: no
// solution exists. (The sup is finite only if g_i <= 0 where u_i = +inf and g_i >= 0
// where l_i = -inf.) Candidates come from where the solve got stuck: at a stationary
// point of psi = 1/2 ||Phi||^2, grad psi = 0 pairs the rows of F with the weights db_j
// phi_j, the multipliers of the pairs (x_i - l_i, F_i) (Facchinei and Pang 2003,
// sec. 9.1); and the violations of F(x) in K at x projected onto the box. Each is checked
// exactly as above, with round-off allowance n * 8 eps relative to the terms summed
// (Higham 2002, sec. 3.1).

enum class RowCone { kNonNegative, kNonPositive, kZero, kAny };

RowCone ConeOfRow(double lower, double upper) {
  const bool lo = std::isfinite(lower), up = std::isfinite(upper);
  if (lo && !up) return RowCone::kNonNegative;
  if (!lo && up) return RowCone::kNonPositive;
  if (!lo && !up) return RowCone::kZero;
  return RowCone::kAny;
}

/// y projected onto K*: y_i >= 0 on K_i = [0, inf), <= 0 on (-inf, 0], free on {0}, 0 on
/// R.
void ProjectOntoDualCone(const Vector& lower, const Vector& upper, Vector* y) {
  for (Eigen::Index i = 0; i < y->size(); ++i) {
    switch (ConeOfRow(lower(i), upper(i))) {
      case RowCone::kNonNegative:
        (*y)(i) = std::max((*y)(i), 0.0);
        break;
      case RowCone::kNonPositive:
        (*y)(i) = std::min((*y)(i), 0.0);
        break;
      case RowCone::kZero:
        break;
      case RowCone::kAny:
        (*y)(i) = 0.0;
        break;
    }
  }
}

/// sup over the box of y'(M x + q) (y in K*), or +inf when it is unbounded or not
/// negative beyond round-off; the certificate holds when the result is < 0.
double CertificateValue(const SparseMatrix& M, const Vector& q, const Vector& lower,
                        const Vector& upper, const Vector& y) {
  const Eigen::Index n = y.size();
  if (y.lpNorm<Eigen::Infinity>() == 0.0) return std::numeric_limits<double>::infinity();
  const Vector g = M.transpose() * y;
  const Vector g_terms = SparseMatrix(M.cwiseAbs()).transpose() * y.cwiseAbs();
  const double roundoff =
      8.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon();
  double value = q.dot(y), magnitude = q.cwiseAbs().dot(y.cwiseAbs());
  for (Eigen::Index i = 0; i < n; ++i) {
    const double gi = std::abs(g(i)) <= roundoff * g_terms(i) ? 0.0 : g(i);
    if (gi == 0.0) continue;
    const double bound = gi > 0.0 ? upper(i) : lower(i);
    if (!std::isfinite(bound)) return std::numeric_limits<double>::infinity();
    value += gi * bound;
    magnitude += std::abs(gi * bound);
  }
  return value < -roundoff * magnitude ? value : std::numeric_limits<double>::infinity();
}

/// The candidate of grad psi = 0 at the (unprojected) iterate x with F(x) = Fx: the
/// weight of grad F_i in grad psi is db phi for a lower pair (x_i - l_i, F_i), -db phi
/// for an upper pair (u_i - x_i, -F_i), F_i for an equation; y = -(that weight).
Vector StationaryCandidate(const Options& options, const Vector& lower,
                           const Vector& upper, const Vector& x, const Vector& Fx) {
  Vector y = Vector::Zero(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const RowCone cone = ConeOfRow(lower(i), upper(i));
    if (cone == RowCone::kZero) y(i) = -Fx(i);
    if (cone != RowCone::kNonNegative && cone != RowCone::kNonPositive) continue;
    const double sign = cone == RowCone::kNonNegative ? 1.0 : -1.0;
    const double a = cone == RowCone::kNonNegative ? x(i) - lower(i) : upper(i) - x(i);
    const double b = sign * Fx(i);
    const double phi = PhiValue(options.ncp_function, options.penalized_fb_lambda, a, b);
    const PhiPartials dp =
        PhiDerivatives(options.ncp_function, options.penalized_fb_lambda, a, b,
                       a == 0.0 && b == 0.0, 0.0, 0.0, options.min_tie_takes_b);
    y(i) = -sign * dp.db * phi;
  }
  ProjectOntoDualCone(lower, upper, &y);
  return y;
}

/// A checked certificate in summary->infeasibility_certificate (and kInfeasible), when F
/// is affine and the solve got stuck; x is the last iterate, before its projection.
void CheckInfeasibility(const Options& options, SquareFunction& F, const Vector& lower,
                        const Vector& upper, const Vector& x, Summary* summary) {
  const TerminationType t = summary->termination;
  const bool stuck = t == TerminationType::kStationaryPoint ||
                     t == TerminationType::kLineSearchFailure ||
                     t == TerminationType::kMaxIterations ||
                     t == TerminationType::kLinearSolverFailure;
  if (!stuck || !F.IsAffine()) return;
  const Eigen::Index n = x.size();
  Vector Fx(n), x_box = x, F_box(n);
  SparseMatrix M;
  ProjectOntoBox(lower, upper, &x_box);
  if (!F.Evaluate(x, &Fx) || !F.Jacobian(x, &M) || !F.Evaluate(x_box, &F_box) ||
      Fx.size() != n || M.rows() != n || M.cols() != n || !Fx.allFinite() ||
      !F_box.allFinite())
    return;
  const Vector q = Fx - M * x;  // F(x) = M x + q
  Vector violation = -F_box;    // the violation of F(x_box) in K, as an element of K*
  ProjectOntoDualCone(lower, upper, &violation);
  for (const Vector& y : {StationaryCandidate(options, lower, upper, x, Fx), violation}) {
    const double value = CertificateValue(M, q, lower, upper, y);
    if (!std::isfinite(value)) continue;
    char text[200];
    std::snprintf(
        text, sizeof text,
        "no solution exists: F is affine and y = Summary::infeasibility_certificate "
        "(||y||_inf = %.3e) gives sup over [l, u] of y'F(x) = %.3e < 0 (Farkas)",
        y.lpNorm<Eigen::Infinity>(), value);
    summary->message = std::string(text) + "; the solver had stopped with " +
                       ToString(t) + ": " + summary->message;
    summary->termination = TerminationType::kInfeasible;
    summary->infeasibility_certificate = y;
    return;
  }
}

/// *cache if it was built for the same F and bounds, else a new mixed form in *cache.
BoxMcpAsMixed& MixedForm(const Options& options, BoxMcpCache* cache, SquareFunction& F,
                         const Vector& lower, const Vector& upper, const Vector& x) {
  CheckSizes(F.NumVariables(), lower, upper, x);
  if (!*cache || !(*cache)->Matches(F, lower, upper, options.infinite_bound))
    cache->reset(new BoxMcpAsMixed(F, lower, upper, options.infinite_bound));
  (*cache)->Rebind(F);
  return **cache;
}

}  // namespace

void BoxMcpDeleter::operator()(BoxMcpAsMixed* p) const { delete p; }

BoxMcpSolve::BoxMcpSolve(const Options& options, BoxMcpCache* cache, SquareFunction& F,
                         const Vector& lower, const Vector& upper, Vector* x)
    : options_(options),
      F_(F),
      mixed_(MixedForm(options, cache, F, lower, upper, *x)),
      x_(*x) {
  CheckBounds(mixed_.lower(), mixed_.upper(), x_);
  projected_start_ = options.project_start_point
                         ? ProjectOntoBox(mixed_.lower(), mixed_.upper(), &x_)
                         : 0;
  ready_ = mixed_.InitialSlacks(x_, &mixed_.unknowns());
}

MixedProblem& BoxMcpSolve::problem() { return mixed_; }
DenseMixedJacobian& BoxMcpSolve::dense_jacobian() { return mixed_; }
Vector& BoxMcpSolve::unknowns() { return mixed_.unknowns(); }

void BoxMcpSolve::Finish(Summary* summary) {
  if (!ready_) {
    *summary = Summary();
    summary->termination = TerminationType::kEvaluationFailure;
    summary->message = "F cannot be evaluated (or is not finite) at the start point";
  } else {
    x_ = mixed_.unknowns().head(F_.NumVariables());
    CheckInfeasibility(options_, F_, mixed_.lower(), mixed_.upper(), x_, summary);
  }
  summary->projected_start_components = projected_start_;
  if (projected_start_ > 0)
    summary->message += " (" + std::to_string(projected_start_) +
                        " components of the start point were outside [l, u] and were "
                        "projected onto it)";
  // The returned x lies in [l, u] whatever the status (FB iterates may leave the box).
  double moved_by = 0.0;
  summary->projected_final_components =
      ProjectOntoBox(mixed_.lower(), mixed_.upper(), &x_, &moved_by);
  if (summary->projected_final_components > 0) {
    char text[160];
    std::snprintf(
        text, sizeof text,
        " (%d components of the last iterate were outside [l, u], by up to %.3e, "
        "and were projected onto it)",
        summary->projected_final_components, moved_by);
    summary->message += text;
  }
}

}  // namespace ncp::internal
