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
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

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

class BoxMcpAsMixed final : public MixedProblem {
 public:
  BoxMcpAsMixed(SquareFunction& F, const Vector& lower, const Vector& upper)
      : F_(F), n_(F.NumVariables()), lower_(lower), upper_(upper) {
    // Equations first: free, fixed, two-sided; then pairs.
    std::vector<int> two_sided;
    for (int i = 0; i < n_; ++i) {
      const bool lo = std::isfinite(lower(i)), up = std::isfinite(upper(i));
      if (!lo && !up) equations_.push_back({Kind::kFree, i, -1});
      else if (lo && up && lower(i) == upper(i)) equations_.push_back({Kind::kFixed, i, -1});
      else if (lo && up) two_sided.push_back(i);
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
  }

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
    if (!F_.Evaluate(y.head(n_), &Fx_)) return false;
    if (Fx_.size() != n_)
      throw std::invalid_argument("ncp: SquareFunction::Evaluate returned size " +
                                  std::to_string(Fx_.size()) + ", expected " + std::to_string(n_));
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const auto row = static_cast<Eigen::Index>(e);
      if (r.kind == Kind::kFree) (*E)(row) = Fx_(r.index);
      else if (r.kind == Kind::kFixed) (*E)(row) = y(r.index) - lower_(r.index);
      else (*E)(row) = Fx_(r.index) - y(n_ + r.slack) + y(n_ + num_slacks_ + r.slack);
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const auto row = static_cast<Eigen::Index>(j);
      switch (r.kind) {
        case Kind::kLower: (*A)(row) = y(r.index) - lower_(r.index); (*B)(row) = Fx_(r.index); break;
        case Kind::kUpper: (*A)(row) = upper_(r.index) - y(r.index); (*B)(row) = -Fx_(r.index); break;
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

  bool Jacobian(const Vector& y, SparseMatrix* JE, SparseMatrix* JA, SparseMatrix* JB) override {
    if (!F_.Jacobian(y.head(n_), &JF_)) return false;
    if (JF_.rows() != n_ || JF_.cols() != n_)
      throw std::invalid_argument("ncp: SquareFunction::Jacobian returned " +
                                  std::to_string(JF_.rows()) + " x " + std::to_string(JF_.cols()) +
                                  ", expected " + std::to_string(n_) + " x " + std::to_string(n_));
    // Rows of F' are needed; a row-major copy gives them in O(nnz).
    Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows(JF_);
    auto add_row = [&](std::vector<Triplet>& t, int out_row, int f_row, double sign) {
      for (decltype(rows)::InnerIterator it(rows, f_row); it; ++it)
        t.emplace_back(out_row, static_cast<int>(it.col()), sign * it.value());
    };
    te_.clear();
    ta_.clear();
    tb_.clear();
    for (size_t e = 0; e < equations_.size(); ++e) {
      const Row& r = equations_[e];
      const int row = static_cast<int>(e);
      if (r.kind == Kind::kFree) add_row(te_, row, r.index, 1.0);
      else if (r.kind == Kind::kFixed) te_.emplace_back(row, r.index, 1.0);
      else {
        add_row(te_, row, r.index, 1.0);
        te_.emplace_back(row, n_ + r.slack, -1.0);
        te_.emplace_back(row, n_ + num_slacks_ + r.slack, 1.0);
      }
    }
    for (size_t j = 0; j < pairs_.size(); ++j) {
      const Row& r = pairs_[j];
      const int row = static_cast<int>(j);
      switch (r.kind) {
        case Kind::kLower: ta_.emplace_back(row, r.index, 1.0); add_row(tb_, row, r.index, 1.0); break;
        case Kind::kUpper: ta_.emplace_back(row, r.index, -1.0); add_row(tb_, row, r.index, -1.0); break;
        case Kind::kLowerSlack:
          ta_.emplace_back(row, r.index, 1.0);
          tb_.emplace_back(row, n_ + r.slack, 1.0);
          break;
        default:
          ta_.emplace_back(row, r.index, -1.0);
          tb_.emplace_back(row, n_ + num_slacks_ + r.slack, 1.0);
          break;
      }
    }
    JE->setFromTriplets(te_.begin(), te_.end());
    JA->setFromTriplets(ta_.begin(), ta_.end());
    JB->setFromTriplets(tb_.begin(), tb_.end());
    return true;
  }

  /// The point a restart continues from (Options::merit_restarts): x projected onto
  /// [l, u], slacks recomputed. The FB iterates may leave the box; a point where the merit
  /// function is stuck outside it is generally not stationary once projected.
  bool RestartPoint(Vector* y) override {
    Vector x = y->head(n_);
    ProjectOntoBox(lower_, upper_, &x);
    return InitialSlacks(x, y);
  }

  /// Start point of the slacks: the positive and negative parts of F at x0.
  bool InitialSlacks(const Vector& x0, Vector* y) {
    y->setZero(NumVariables());
    y->head(n_) = x0;
    if (num_slacks_ == 0) return true;
    if (!F_.Evaluate(x0, &Fx_) || !Fx_.allFinite()) return false;
    for (const Row& r : equations_) {
      if (r.kind != Kind::kSlackSplit) continue;
      (*y)(n_ + r.slack) = std::max(Fx_(r.index), 0.0);
      (*y)(n_ + num_slacks_ + r.slack) = std::max(-Fx_(r.index), 0.0);
    }
    return true;
  }

 private:
  enum class Kind { kFree, kFixed, kSlackSplit, kLower, kUpper, kLowerSlack, kUpperSlack };
  struct Row {
    Kind kind;
    int index;  // variable i of the box MCP
    int slack;  // k for two-sided variables, else -1
  };
  SquareFunction& F_;
  int n_;
  Vector lower_, upper_, Fx_;
  SparseMatrix JF_;
  std::vector<Row> equations_, pairs_;
  std::vector<Triplet> te_, ta_, tb_;
  int num_slacks_ = 0;
};

void CheckBounds(int n, const Vector& lower, const Vector& upper, const Vector& x) {
  auto size_error = [&](const char* what, Eigen::Index got) {
    throw std::invalid_argument(std::string("ncp::Solver::Solve (box MCP): ") + what +
                                " has size " + std::to_string(got) +
                                ", expected NumVariables() = " + std::to_string(n));
  };
  if (lower.size() != n) size_error("lower", lower.size());
  if (upper.size() != n) size_error("upper", upper.size());
  if (x.size() != n) size_error("the start point", x.size());
  for (int i = 0; i < n; ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    if (std::isnan(lower(i)) || std::isnan(upper(i)))
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): bound" + at + " is NaN");
    if (lower(i) > upper(i))
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): lower" + at + " = " +
                                  std::to_string(lower(i)) + " > upper" + at + " = " +
                                  std::to_string(upper(i)));
    if (lower(i) == std::numeric_limits<double>::infinity() ||
        upper(i) == -std::numeric_limits<double>::infinity())
      throw std::invalid_argument("ncp::Solver::Solve (box MCP): empty box at" + at +
                                  " (lower = +inf or upper = -inf)");
    if (!std::isfinite(x(i)))
      throw std::invalid_argument("ncp::Solver::Solve: start point x" + at + " = " +
                                  std::to_string(x(i)) + " is not finite");
  }
}

/// Bounds with |b| >= infinite_bound become +-inf (GAMS/PATH write "no bound" as
/// +-1e20); a lower bound >= infinite_bound becomes +inf (an empty box, rejected later).
Vector NormalizeBound(const Vector& bound, double infinite_bound) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Vector normalized = bound;
  for (Eigen::Index i = 0; i < bound.size(); ++i) {
    if (bound(i) >= infinite_bound) normalized(i) = kInf;
    else if (bound(i) <= -infinite_bound) normalized(i) = -kInf;
  }
  return normalized;
}

}  // namespace

void SolveBoxMcp(Solver& solver, SquareFunction& F, const Vector& lower_in,
                 const Vector& upper_in, Vector* x, Summary* summary) {
  if (x == nullptr || summary == nullptr)
    throw std::invalid_argument("ncp::Solver::Solve: x and summary must not be null");
  const Options& options = solver.options();
  const double infinite_bound = options.infinite_bound;
  const Vector lower = NormalizeBound(lower_in, infinite_bound);
  const Vector upper = NormalizeBound(upper_in, infinite_bound);
  CheckBounds(F.NumVariables(), lower, upper, *x);
  const int projected = options.project_start_point ? ProjectOntoBox(lower, upper, x) : 0;
  BoxMcpAsMixed mixed(F, lower, upper);
  Vector y;
  if (!mixed.InitialSlacks(*x, &y)) {
    *summary = Summary();
    summary->termination = TerminationType::kEvaluationFailure;
    summary->message = "F cannot be evaluated (or is not finite) at the start point";
  } else {
    solver.Solve(mixed, &y, summary);
    *x = y.head(F.NumVariables());
  }
  summary->projected_start_components = projected;
  if (projected > 0)
    summary->message += " (" + std::to_string(projected) +
                        " components of the start point were outside [l, u] and were "
                        "projected onto it)";
}

}  // namespace ncp::internal
