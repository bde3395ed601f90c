// Algorithm 1 of the thesis (section 3.1): the globalized semismooth Newton method of
// De Luca, Facchinei and Kanzow (1996) applied to Phi(x) = [E(x); phi(A(x), B(x))].

#include "ncp/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "linear_solver.hpp"
#include "sparse_pattern.hpp"
#include "box_mcp.hpp"
#include "globalization.hpp"
#include "ncp_function_internal.hpp"
#include "strategy.hpp"

namespace ncp {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

bool AllFinite(const Vector& v) { return v.allFinite(); }

bool AllFinite(const SparseMatrix& S) {
  const double* values = S.valuePtr();
  for (Eigen::Index k = 0; k < S.nonZeros(); ++k) {
    if (!std::isfinite(values[k])) return false;
  }
  return true;
}

std::string Fmt(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

void CheckJacobianShape(const SparseMatrix& S, Eigen::Index rows, Eigen::Index cols,
                        const char* name) {
  if (S.rows() != rows || S.cols() != cols) {
    std::ostringstream msg;
    msg << "ncp::Solver: MixedProblem::Jacobian returned " << name << " of size " << S.rows()
        << " x " << S.cols() << ", expected " << rows << " x " << cols;
    throw std::invalid_argument(msg.str());
  }
}

// row_i *= weight_i for every stored entry of a compressed column-major matrix.
void ScaleRows(const Vector& weight, SparseMatrix* J) {
  double* values = J->valuePtr();
  const int* rows = J->innerIndexPtr();
  for (Eigen::Index k = 0; k < J->nonZeros(); ++k) values[k] *= weight(rows[k]);
}

// weight = 1 / (scale + floor / tolerance), checked; `what` names the vector in errors.
// (|row| weight <= tolerance  <=>  |row| <= floor + tolerance * scale; the weighted rows are
// relative residuals of order 1 at a typical point, which keeps the penalized FB function,
// not positively homogeneous, on data of order 1.)
void Weights(const Vector& scale, const Vector& floor, Eigen::Index size, double tolerance,
             const char* what, Vector* weight) {
  if (scale.size() != size || (floor.size() != 0 && floor.size() != size))
    throw std::invalid_argument(std::string("ncp::Solver: MixedProblem::Scales gave ") + what +
                                " of size " + std::to_string(scale.size()) + " (floor " +
                                std::to_string(floor.size()) + "), expected " + std::to_string(size));
  weight->resize(size);
  for (Eigen::Index i = 0; i < size; ++i) {
    const double f = floor.size() ? floor(i) : 0.0;
    const double accuracy = tolerance > 0.0 ? scale(i) + f / tolerance : scale(i);
    if (!(scale(i) > 0.0) || !(f >= 0.0) || !std::isfinite(accuracy))
      throw std::invalid_argument(std::string("ncp::Solver: MixedProblem::Scales gave ") + what +
                                  "[" + std::to_string(i) + "] = " + Fmt("%.3e", scale(i)) +
                                  " with floor " + Fmt("%.3e", f) +
                                  ": scales must be finite and > 0, floors finite and >= 0");
    (*weight)(i) = 1.0 / accuracy;
  }
}

// The problem's scales as row weights; false (weights untouched) if it gives none.
// (`scales` is the caller's, kept between solves so that no vector is allocated again.)
bool SetWeights(MixedProblem& problem, const Vector& x0, int m, int p, double tolerance,
                ResidualScales* scales_ptr, Vector* we, Vector* wa, Vector* wb) {
  ResidualScales& scales = *scales_ptr;
  if (!problem.Scales(x0, &scales)) return false;
  Weights(scales.equation, scales.equation_floor, m, tolerance, "equation", we);
  Weights(scales.a, scales.a_floor, p, tolerance, "a", wa);
  Weights(scales.b, scales.b_floor, p, tolerance, "b", wb);
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Options and Summary.

Options Options::Algorithm1() {
  Options options;
  options.descent_rho = 1e-8;
  options.descent_p = 2.1;
  options.armijo_beta = 1e-4;
  options.nonmonotone_memory = 1;
  options.regularized_direction = false;
  options.gradient_fallback = true;
  options.merit_restarts = 0;
  options.hybrid = false;
  return options;
}

bool Options::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    return fail("Options::tolerance must be finite and >= 0, got " + Fmt("%g", tolerance));
  if (!(roundoff_ulps >= 0.0) || !std::isfinite(roundoff_ulps))
    return fail("Options::roundoff_ulps must be finite and >= 0, got " + Fmt("%g", roundoff_ulps));
  if (max_iterations < 0)
    return fail("Options::max_iterations must be >= 0, got " + std::to_string(max_iterations));
  if (!(descent_rho > 0.0))
    return fail("Options::descent_rho must be > 0 (eq. 22), got " + Fmt("%g", descent_rho));
  if (!(descent_p > 2.0))
    return fail("Options::descent_p must be > 2 (eq. 22), got " + Fmt("%g", descent_p));
  if (!(armijo_beta > 0.0 && armijo_beta < 0.5))
    return fail("Options::armijo_beta must lie in (0, 1/2) (eq. 23), got " +
                Fmt("%g", armijo_beta));
  if (nonmonotone_memory < 1 || nonmonotone_memory > 1000)
    return fail("Options::nonmonotone_memory must lie in [1, 1000], got " +
                std::to_string(nonmonotone_memory));
  if (merit_restarts < 0 || merit_restarts > 1000)
    return fail("Options::merit_restarts must lie in [0, 1000], got " + std::to_string(merit_restarts));
  if (max_backtracks < 0 || max_backtracks > 1000)
    return fail("Options::max_backtracks must lie in [0, 1000], got " +
                std::to_string(max_backtracks));
  if (!(degenerate_tolerance >= 0.0))
    return fail("Options::degenerate_tolerance must be >= 0, got " +
                Fmt("%g", degenerate_tolerance));
  if (!(stationarity_tolerance >= 0.0))
    return fail("Options::stationarity_tolerance must be >= 0, got " +
                Fmt("%g", stationarity_tolerance));
  if (!(penalized_fb_lambda > 0.0 && penalized_fb_lambda <= 1.0))
    return fail("Options::penalized_fb_lambda must lie in (0, 1], got " +
                Fmt("%g", penalized_fb_lambda));
  if (stagnation_window < 0 || stagnation_window > kMaxStagnationWindow)
    return fail("Options::stagnation_window must lie in [0, " + std::to_string(kMaxStagnationWindow) +
                "] iterations, got " + std::to_string(stagnation_window));
  if (!(stagnation_tolerance >= 0.0 && stagnation_tolerance < 1.0))
    return fail("Options::stagnation_tolerance must lie in [0, 1), got " +
                Fmt("%g", stagnation_tolerance));
  if (hybrid_window < 0 || hybrid_window > kMaxStagnationWindow)
    return fail("Options::hybrid_window must lie in [0, " + std::to_string(kMaxStagnationWindow) +
                "] iterations, got " + std::to_string(hybrid_window));
  if (!(hybrid_decrease > 0.0 && hybrid_decrease < 1.0))
    return fail("Options::hybrid_decrease must lie in (0, 1), got " + Fmt("%g", hybrid_decrease));
  if (!(hybrid_budget_per_unknown > 0.0))
    return fail("Options::hybrid_budget_per_unknown must be > 0 (or +inf) iterations, got " +
                Fmt("%g", hybrid_budget_per_unknown));
  if (!(max_seconds > 0.0))
    return fail("Options::max_seconds must be > 0 (or +inf), got " + Fmt("%g", max_seconds));
  if (!(factorization_flop_rate >= 0.0) || !std::isfinite(factorization_flop_rate))
    return fail("Options::factorization_flop_rate must be finite and >= 0, got " +
                Fmt("%g", factorization_flop_rate));
  if (dense_threshold < 0)
    return fail("Options::dense_threshold must be >= 0, got " + std::to_string(dense_threshold));
  if (!(infinite_bound > 0.0))
    return fail("Options::infinite_bound must be > 0 (or +inf), got " + Fmt("%g", infinite_bound));
  // Enums set from integers (a cast, a file) may hold any value: checked before a switch.
  const int function = static_cast<int>(ncp_function);
  if (function < 0 || function > static_cast<int>(kLastNcpFunction))
    return fail("Options::ncp_function must be an NcpFunction (0.." +
                std::to_string(static_cast<int>(kLastNcpFunction)) + "), got " +
                std::to_string(function));
  const int solver = static_cast<int>(linear_solver);
  if (solver < 0 || solver > static_cast<int>(kLastLinearSolverType))
    return fail("Options::linear_solver must be a LinearSolverType (0.." +
                std::to_string(static_cast<int>(kLastLinearSolverType)) + "), got " + std::to_string(solver));
  return true;
}

std::string Summary::BriefReport() const {
  std::ostringstream out;
  out << ToString(termination) << ": " << iterations << " iterations, " << jacobian_evaluations
      << " Jacobian / " << residual_evaluations << " residual evaluations, ||Phi||_inf = "
      << Fmt("%.3e", final_phi_inf) << ", " << Fmt("%.3g", total_time_s) << " s";
  if (merit_restarts > 0) out << ", " << merit_restarts << " merit restarts";
  if (!strategy_switches.empty()) out << ", " << strategy_switches.size() << " strategy switches";
  return out.str();
}

std::string Summary::FullReport() const {
  std::ostringstream out;
  out << "ncp solver summary\n"
      << "  termination              " << ToString(termination) << "\n"
      << "  message                  " << message << "\n"
      << "  unknowns / eqs / pairs   " << num_variables << " / " << num_equations << " / "
      << num_pairs << "\n"
      << "  NCP function             " << ToString(ncp_function) << "\n"
      << "  linear solver            " << ToString(linear_solver_requested) << " -> "
      << ToString(linear_solver_used) << "\n"
      << "  iterations               " << iterations << "\n"
      << "  Jacobian evaluations     " << jacobian_evaluations << "\n"
      << "  residual evaluations     " << residual_evaluations << "\n"
      << "  gradient steps           " << gradient_steps << "\n"
      << "  regularized (LM) steps   " << regularized_steps << "\n"
      << "  merit restarts           " << merit_restarts << "\n"
      << "  strategy switches        " << strategy_switches.size()
      << internal::StrategySwitchSuffix(strategy_switches) << "\n"
      << "  linear solver failures   " << linear_solver_failures << "\n"
      << "  descent test failures    " << descent_test_failures << "\n"
      << "  backtracks               " << backtracks << "\n"
      << "  symbolic factorizations  " << symbolic_factorizations << "\n"
      << "  Cholesky -> LU fallbacks " << cholesky_fallbacks << "\n"
      << "  start components moved   " << projected_start_components << "\n"
      << "  final components moved   " << projected_final_components << "\n"
      << "  ||Phi||_inf initial      " << Fmt("%.6e", initial_phi_inf) << "\n"
      << "  ||Phi||_inf final        " << Fmt("%.6e", final_phi_inf)
      << (roundoff_limited ? " (at the round-off floor)" : "") << "\n"
      << "  psi final                " << Fmt("%.6e", final_psi) << "\n"
      << "  time total / eval / lin  " << Fmt("%.6f", total_time_s) << " / "
      << Fmt("%.6f", evaluation_time_s) << " / " << Fmt("%.6f", linear_solver_time_s) << " s\n";
  return out.str();
}

// ---------------------------------------------------------------------------------------
// Workspace: the Jacobian of Phi with a cached pattern, the linear solver, and every
// vector of the iteration, sized by Solve() before the first iteration (reallocated only
// when n, m or the Jacobian pattern change). The iterations then allocate only inside the
// numeric factorization of a sparse backend (SuiteSparse for UMFPACK and KLU, and
// Eigen::SparseLU) and for Summary::trace with keep_trace; the Summary's message is built
// when the solve ends (tests/contact/test_no_allocation.cpp).

struct Solver::Workspace {
  std::unique_ptr<internal::LinearSolver> linear_solver;
  // The last box MCP in mixed form, reused when the same F and bounds come again.
  internal::BoxMcpCache box_mcp;
  // The backend of the last solve; dense: J is the dense Jd and dense_lu factorizes it (the
  // light path of small problems: no pattern bookkeeping, no sparse matrix, no allocation).
  LinearSolverType backend = LinearSolverType::kAuto;
  bool dense = false;
  DenseMatrix Jd;
  internal::DenseLU dense_lu;

  // Cached patterns of the user's JE, JA, JB; a change triggers a new symbolic analysis.
  internal::SparsePattern pattern[3];
  bool have_pattern = false;

  // J = [JE; diag(da) JA + diag(db) JB], pattern = union; map[s][k] is where the k-th
  // stored entry of source s lands in J's value array.
  SparseMatrix J;
  std::vector<int> map[3];

  SparseMatrix JE, JA, JB;
  // Row weights 1 / (scale + floor / tolerance) of MixedProblem::Scales (when `weighted`).
  bool weighted = false;
  ResidualScales scales;
  Vector we, wa, wb;
  Vector E, A, B, Et, At, Bt;  // current point and trial point
  Vector phi, phi_trial, grad, d, x_trial, da, db, z, za, zb, newton_rhs, newton_residual,
      newton_terms;
  // Round-off floor (Options::roundoff_ulps): row i of |J||x| summed entry by entry, i.e.
  // |J_E||x| for an equation and |da| |J_A||x| + |db| |J_B||x| for a pair.
  Vector sensitivity;
  // flop/s of the last timed numeric factorization (0: none timed yet).
  double measured_flop_rate = 0.0;
  // Levenberg-Marquardt system J'J + mu I, its own solver and pattern bookkeeping.
  std::unique_ptr<internal::LinearSolver> regularized_solver;
  SparseMatrix normal_matrix, identity;
  bool regularized_analyzed = false;
  Eigen::Index regularized_nonzeros = -1;
  // The nonmonotone Armijo reference and the stagnation test (globalization.hpp).
  internal::NonmonotoneReference armijo_reference;
  internal::StagnationTest stagnation;
  // The hybrid default (Options::hybrid, strategy.hpp).
  internal::StrategySchedule schedule;
  internal::StrategyProgress progress;

  /// Sizes every vector of the iteration for n unknowns and m equations (zeros).
  void Resize(int n, int m) {
    const int p = n - m;
    for (Vector* v : {&E, &Et}) v->setZero(m);
    for (Vector* v : {&A, &B, &At, &Bt, &da, &db, &za, &zb}) v->setZero(p);
    for (Vector* v : {&phi, &phi_trial, &grad, &d, &x_trial, &z, &newton_rhs, &newton_residual,
                      &newton_terms, &sensitivity})
      v->setZero(n);
    if (JE.rows() != m || JE.cols() != n) JE.resize(m, n);
    if (JA.rows() != p || JA.cols() != n) JA.resize(p, n);
    if (JB.rows() != p || JB.cols() != n) JB.resize(p, n);
  }

  /// Returns true when the pattern differs from the cached one (and rebuilds J's pattern).
  bool UpdatePattern(int m) {
    const SparseMatrix* sources[3] = {&JE, &JA, &JB};
    bool same = have_pattern;
    for (int s = 0; s < 3 && same; ++s)
      same = pattern[s].Matches(*sources[s]);
    if (same) return false;

    const Eigen::Index n = JE.cols();
    std::vector<Eigen::Triplet<double, int>> triplets;
    triplets.reserve(static_cast<size_t>(JE.nonZeros() + JA.nonZeros() + JB.nonZeros()));
    for (int s = 0; s < 3; ++s) {
      const SparseMatrix& S = *sources[s];
      const int row_offset = s == 0 ? 0 : m;
      for (int c = 0; c < S.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(S, c); it; ++it)
          triplets.emplace_back(static_cast<int>(it.row()) + row_offset, c, 0.0);
      pattern[s].Store(S);
    }
    J.resize(n, n);
    J.setFromTriplets(triplets.begin(), triplets.end());
    J.makeCompressed();
    for (int s = 0; s < 3; ++s) {
      const SparseMatrix& S = *sources[s];
      const int row_offset = s == 0 ? 0 : m;
      map[s].resize(static_cast<size_t>(S.nonZeros()));
      size_t k = 0;
      for (int c = 0; c < S.outerSize(); ++c) {
        const int* begin = J.innerIndexPtr() + J.outerIndexPtr()[c];
        const int* end = J.innerIndexPtr() + J.outerIndexPtr()[c + 1];
        for (SparseMatrix::InnerIterator it(S, c); it; ++it, ++k) {
          const int* pos = std::lower_bound(begin, end, static_cast<int>(it.row()) + row_offset);
          map[s][k] = static_cast<int>(pos - J.innerIndexPtr());
        }
      }
    }
    have_pattern = true;
    return true;
  }

  /// Calls add(s, k, row, col, value) for the k-th stored entry of source s (JE, JA, JB) as
  /// an entry of J = [JE; diag(da) JA + diag(db) JB]: row of J, value scaled by da or db.
  template <class Add>
  void ForEachJacobianEntry(int m, Add&& add) const {
    const SparseMatrix* sources[3] = {&JE, &JA, &JB};
    const Vector* scale[3] = {nullptr, &da, &db};
    for (int s = 0; s < 3; ++s) {
      const SparseMatrix& S = *sources[s];
      const int row_offset = s == 0 ? 0 : m;
      int k = 0;
      for (int c = 0; c < S.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(S, c); it; ++it, ++k)
          add(s, k, static_cast<int>(it.row()) + row_offset, c,
              scale[s] ? (*scale[s])(it.row()) * it.value() : it.value());
    }
  }

  /// Jd = J, dense (the light path); sensitivity = |J||x| row by row (with the partials
  /// da, db inside, the round-off floor's r; see WithinRoundoffFloor).
  void FillDenseJacobian(int m, const Vector& x) {
    const Eigen::Index n = JE.cols();
    Jd.resize(n, n);
    Jd.setZero();
    sensitivity.setZero();
    ForEachJacobianEntry(m, [&](int, int, int row, int col, double value) {
      Jd(row, col) += value;
      sensitivity(row) += std::abs(value) * std::abs(x(col));
    });
  }

  /// out = J' v.
  void MultiplyJacobianTransposed(const Vector& v, Vector* out) const {
    if (dense) out->noalias() = Jd.transpose() * v;
    else out->noalias() = J.transpose() * v;
  }
  /// *residual = J v + b and returns max_i (|J||v|)_i, the size of the terms summed in J v
  /// (its round-off is relative to that, not to |J v|); one pass over J.
  double ResidualAndTerms(const Vector& v, const Vector& b, Vector* residual, Vector* terms) const {
    *residual = b;
    terms->setZero();
    auto add = [&](Eigen::Index row, Eigen::Index col, double value) {
      (*residual)(row) += value * v(col);
      (*terms)(row) += std::abs(value * v(col));
    };
    if (dense) {
      for (Eigen::Index c = 0; c < Jd.cols(); ++c)
        for (Eigen::Index r = 0; r < Jd.rows(); ++r) add(r, c, Jd(r, c));
    } else {
      for (int c = 0; c < J.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(J, c); it; ++it) add(it.row(), c, it.value());
    }
    return terms->lpNorm<Eigen::Infinity>();
  }

  /// J values = [JE; diag(da) JA + diag(db) JB] on the cached pattern; sensitivity as above.
  void FillJacobian(int m, const Vector& x) {
    double* values = J.valuePtr();
    std::fill(values, values + J.nonZeros(), 0.0);
    sensitivity.setZero();
    ForEachJacobianEntry(m, [&](int s, int k, int row, int col, double value) {
      values[map[s][k]] += value;
      sensitivity(row) += std::abs(value) * std::abs(x(col));
    });
  }
};

Solver::Solver(const Options& options) : options_(options), workspace_(new Workspace) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("ncp::Solver: " + error);
}
Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

// ---------------------------------------------------------------------------------------
// Misuse at the API boundary: sizes, a non-finite start point, pair variables.

namespace {

void CheckProblem(const MixedProblem& problem, const Vector& x) {
  const int n = problem.NumVariables();
  const int m = problem.NumEquations();
  if (n < 0 || m < 0 || m > n) {
    throw std::invalid_argument("ncp::Solver::Solve: need 0 <= NumEquations() <= NumVariables(), got " +
                                std::to_string(m) + " equations and " + std::to_string(n) +
                                " variables");
  }
  if (x.size() != n) {
    throw std::invalid_argument("ncp::Solver::Solve: start point has size " +
                                std::to_string(x.size()) + ", expected NumVariables() = " +
                                std::to_string(n));
  }
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(x(i))) {
      throw std::invalid_argument("ncp::Solver::Solve: start point x[" + std::to_string(i) +
                                  "] = " + std::to_string(x(i)) + " is not finite");
    }
  }
  for (int j = 0; j < n - m; ++j) {
    const int v = problem.PairVariable(j);
    if (v < 0 || v >= n)
      throw std::invalid_argument("ncp::Solver::Solve: PairVariable(" + std::to_string(j) +
                                  ") = " + std::to_string(v) + " is outside [0, n)");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Algorithm 1, one named phase per step. Solver::Iteration holds the state of one solve:
// Run() reads like the algorithm,
//
//   Start                      Phi(x^0), sizes, backend, row weights
//   loop k = 0, 1, ...
//     EvaluateJacobian         J^k in the B-subdifferential, grad psi = J' Phi   (eq. 24)
//     Report                   trace, log, callback
//     TestStop                 step 1: ||Phi||_inf <= tolerance; safeguards
//     ChooseDirection          step 2: Newton (eq. 21, 22), regularized, -grad psi
//     LineSearch               step 3: Armijo, monotone (eq. 23) or nonmonotone
//     Accept                   step 4
//
// (the layout follows Ceres' LineSearchMinimizer::Minimize).

class Solver::Iteration {
 public:
  Iteration(const Options& options, Workspace& workspace, MixedProblem& problem, Vector& x,
            Summary& summary)
      : o_(options), w_(workspace), problem_(problem), x_(x), s_(summary),
        n_(problem.NumVariables()), m_(problem.NumEquations()), p_(n_ - m_) {}

  void Run() {
    if (!Start()) return;
    for (int k = 0;;) {
      phi_inf_ = w_.phi.lpNorm<Eigen::Infinity>();
      psi_ = 0.5 * w_.phi.squaredNorm();
      converged_ = phi_inf_ <= threshold_;
      roundoff_limited_ = false;
      have_jacobian_ = !converged_ && k < o_.max_iterations;
      jacobian_ok_ = true;
      degenerate_count_ = 0;
      pattern_changed_ = false;
      if (have_jacobian_ && !EvaluateJacobian(k)) return;
      if (have_jacobian_ && jacobian_ok_) converged_ = roundoff_limited_ = WithinRoundoffFloor();
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

 private:
  enum class Direction { kNewton, kRegularized, kGradient };

  // ---- Start: sizes, backend, weights, Phi(x^0) ------------------------------------
  bool Start() {
    start_ = Clock::now();
    InitializeSummary();
    resolved_ = o_.linear_solver;
    if (resolved_ == LinearSolverType::kAuto)
      resolved_ = n_ <= o_.dense_threshold ? LinearSolverType::kDenseLU : LinearSolverType::kUmfpack;
    if (w_.backend != resolved_) {
      w_.backend = resolved_;
      w_.dense = resolved_ == LinearSolverType::kDenseLU;
      w_.linear_solver = w_.dense ? nullptr : internal::MakeLinearSolver(resolved_);
      w_.regularized_solver.reset();  // made on first use (Options::regularized_direction)
      w_.have_pattern = false;
      w_.measured_flop_rate = 0.0;
    }
    symbolic_before_ = SymbolicFactorizations();
    fallbacks_before_ = Fallbacks();
    s_.linear_solver_used = resolved_;
    w_.Resize(n_, m_);

    // Row weights from the problem's own scales (MixedProblem::Scales), once per solve.
    w_.weighted = SetWeights(problem_, x_, m_, p_, o_.tolerance, &w_.scales, &w_.we, &w_.wa, &w_.wb);
    s_.weighted_residual = w_.weighted;
    threshold_ = o_.tolerance;  // on ||Phi||_inf, weighted (relative) or not
    function_ = o_.ncp_function;
    restarts_left_ = o_.merit_restarts;
    first_k_ = 0;
    regularized_ = o_.regularized_direction;
    strategy_start_ = 0;
    w_.schedule.Reset(o_);
    w_.progress.Reset(o_, n_);

    if (!Evaluate(x_, &w_.E, &w_.A, &w_.B, &w_.phi)) {
      w_.phi.setConstant(std::numeric_limits<double>::quiet_NaN());
      Finish(TerminationType::kEvaluationFailure, "the problem cannot be evaluated at the start point");
      return false;
    }
    s_.initial_phi_inf = w_.phi.lpNorm<Eigen::Infinity>();
    if (!AllFinite(w_.phi)) {
      Finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
      return false;
    }
    w_.stagnation.Reset(o_.stagnation_window);
    w_.armijo_reference.Reset(o_.nonmonotone_memory);
    if (o_.log_to_stderr)
      std::fprintf(stderr, "%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter", "|Phi|_inf", "psi",
                   "|grad|_inf", "step", "bt", "dir", "|gam|");
    return true;
  }

  void InitializeSummary() {
    s_ = Summary();
    s_.num_variables = n_;
    s_.num_equations = m_;
    s_.num_pairs = p_;
    s_.ncp_function = o_.ncp_function;
    s_.linear_solver_requested = o_.linear_solver;
    s_.iterations = s_.jacobian_evaluations = s_.residual_evaluations = 0;
    s_.gradient_steps = s_.regularized_steps = s_.merit_restarts = 0;
    s_.linear_solver_failures = s_.descent_test_failures = s_.backtracks = 0;
    s_.projected_start_components = s_.projected_final_components = 0;
    s_.evaluation_time_s = s_.linear_solver_time_s = 0.0;
  }

  // ---- Phi(x) = [E; phi(A_j, B_j)] (thesis eq. 15), rows weighted by the scales ----
  bool Evaluate(const Vector& point, Vector* E, Vector* A, Vector* B, Vector* phi) {
    ++s_.residual_evaluations;
    const auto t0 = Clock::now();
    const bool ok = problem_.Evaluate(point, E, A, B);
    s_.evaluation_time_s += Seconds(t0);
    if (!ok) return false;
    if (E->size() != m_ || A->size() != p_ || B->size() != p_)
      throw std::invalid_argument("ncp::Solver: MixedProblem::Evaluate resized its outputs");
    if (w_.weighted) {
      E->array() *= w_.we.array();
      A->array() *= w_.wa.array();
      B->array() *= w_.wb.array();
    }
    phi->head(m_) = *E;
    for (int j = 0; j < p_; ++j)
      (*phi)(m_ + j) = internal::PhiValue(function_, o_.penalized_fb_lambda, (*A)(j), (*B)(j));
    return true;
  }

  // ---- J^k in the B-subdifferential (step 2) and grad psi = J' Phi (eq. 24) ---------
  // Returns false only when the solve has finished (non-finite Jacobian); a Jacobian()
  // that returned false is reported by TestStop after the callback has seen iterate k.
  bool EvaluateJacobian(int k) {
    ++s_.jacobian_evaluations;
    const auto t0 = Clock::now();
    jacobian_ok_ = problem_.Jacobian(x_, &w_.JE, &w_.JA, &w_.JB);
    s_.evaluation_time_s += Seconds(t0);
    if (!jacobian_ok_) return true;
    CheckJacobianShape(w_.JE, m_, n_, "JE");
    CheckJacobianShape(w_.JA, p_, n_, "JA");
    CheckJacobianShape(w_.JB, p_, n_, "JB");
    for (SparseMatrix* S : {&w_.JE, &w_.JA, &w_.JB}) S->makeCompressed();
    if (w_.weighted) {
      ScaleRows(w_.we, &w_.JE);
      ScaleRows(w_.wa, &w_.JA);
      ScaleRows(w_.wb, &w_.JB);
    }
    if (!AllFinite(w_.JE) || !AllFinite(w_.JA) || !AllFinite(w_.JB)) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    PhiPartials();
    if (w_.dense) {
      w_.FillDenseJacobian(m_, x_);
    } else {
      pattern_changed_ = w_.UpdatePattern(m_);
      w_.FillJacobian(m_, x_);
    }
    w_.MultiplyJacobianTransposed(w_.phi, &w_.grad);  // grad psi = J' Phi (eq. 24)
    return true;
  }

  // da_j, db_j: the partials of phi at (A_j, B_j). Degenerate set gamma = {j : A_j = B_j
  // = 0} (eq. 13) and the z-vector rule: z_v = 1 at the variable of every degenerate pair
  // (DFK 1996, eq. 27; thesis 3.1).
  void PhiPartials() {
    degenerate_count_ = 0;
    const bool fb_family = function_ != NcpFunction::kMin;
    auto degenerate = [&](int j) {
      return internal::InDegenerateSet(function_, o_.degenerate_tolerance, w_.A(j), w_.B(j));
    };
    if (fb_family) {
      w_.z.setZero();
      for (int j = 0; j < p_; ++j) {
        if (!degenerate(j)) continue;
        w_.z(problem_.PairVariable(j)) = 1.0;
        ++degenerate_count_;
      }
      if (degenerate_count_ > 0) {
        w_.za.noalias() = w_.JA * w_.z;
        w_.zb.noalias() = w_.JB * w_.z;
      }
    }
    for (int j = 0; j < p_; ++j) {
      const bool gamma = degenerate(j);
      const internal::PhiPartials dp = internal::PhiDerivatives(
          function_, o_.penalized_fb_lambda, w_.A(j), w_.B(j), gamma,
          gamma ? w_.za(j) : 0.0, gamma ? w_.zb(j) : 0.0, o_.min_tie_takes_b);
      w_.da(j) = dp.da;
      w_.db(j) = dp.db;
    }
  }

  // ---- the round-off floor of the test (Options::roundoff_ulps) ----------------------
  // Moving x to a neighbouring double (x_j (1 + delta_j), |delta_j| <= eps) changes row i of
  // Phi by up to eps r_i with r = |J_E||x| for equations and |da| |J_A||x| + |db| |J_B||x|
  // for pairs (to first order; J_E, J_A, J_B weighted like the rows). No x closer to the
  // solution is representable below that, so a row within tolerance + roundoff_ulps eps r_i
  // is as converged as double precision allows. Needs J at x^k (EvaluateJacobian).
  // (r = Workspace::sensitivity, summed while J was filled: no extra pass over J.)
  bool WithinRoundoffFloor() {
    if (o_.roundoff_ulps == 0.0) return false;
    for (int i = 0; i < n_; ++i)
      if (!internal::RowWithinRoundoffFloor(w_.phi(i), threshold_, o_.roundoff_ulps, w_.sensitivity(i)))
        return false;
    return true;
  }

  // ---- trace, log, callback for iterate k; false when the callback stopped ----------
  bool Report(int k) {
    record_.iteration = k;
    record_.phi_inf = phi_inf_;
    record_.psi = psi_;
    record_.grad_psi_inf =
        have_jacobian_ && jacobian_ok_ ? w_.grad.lpNorm<Eigen::Infinity>() : 0.0;
    record_.degenerate_pairs = degenerate_count_;
    const bool reported = o_.keep_trace || o_.log_to_stderr || o_.callback;
    record_.time_s = reported ? Seconds(start_) : 0.0;  // (a clock read costs ~1% of a small iteration)
    if (o_.keep_trace) s_.trace.push_back(record_);
    if (o_.log_to_stderr)
      std::fprintf(stderr, "%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n", k, phi_inf_, psi_,
                   record_.grad_psi_inf, record_.step_length, record_.backtracks,
                   record_.gradient_step ? "grad" : record_.regularized_step ? "reg" : "newt",
                   degenerate_count_);
    if (o_.callback && !o_.callback(record_)) {
      Finish(TerminationType::kUserAbort,
             "the iteration callback stopped the solve at iteration " + std::to_string(k));
      return false;
    }
    return true;
  }

  // ---- step 1 and the safeguards; true when the solve ends here ----------------------
  bool TestStop(int k) {
    if (converged_) {
      s_.roundoff_limited = roundoff_limited_;
      Finish(TerminationType::kConverged,
             internal::ConvergedMessage(o_, w_.weighted, roundoff_limited_, phi_inf_, k));
      return true;
    }
    if (k >= o_.max_iterations) {
      Finish(TerminationType::kMaxIterations, internal::MaxIterationsMessage(o_, phi_inf_));
      return true;
    }
    if (OutOfTime("at iteration ", k)) return true;
    if (!jacobian_ok_) {
      Finish(TerminationType::kEvaluationFailure,
             "MixedProblem::Jacobian returned false at iteration " + std::to_string(k));
      return true;
    }
    grad_inf_ = w_.grad.lpNorm<Eigen::Infinity>();
    return Stagnated(k) || StationaryPoint();
  }

  // Options::max_seconds passed? (no allocation unless it did: checked every trial)
  bool OutOfTime(const char* where, int k) {
    if (!std::isfinite(o_.max_seconds) || !(Seconds(start_) > o_.max_seconds)) return false;
    Finish(TerminationType::kTimeLimit, internal::TimeLimitMessage(o_, where, k, phi_inf_));
    return true;
  }

  // The stagnation test of globalization.hpp (Options::stagnation_window).
  bool Stagnated(int k) {
    if (!w_.stagnation.Stagnated(static_cast<size_t>(k - first_k_), psi_, o_)) return false;
    Finish(TerminationType::kStationaryPoint, internal::StagnationMessage(o_, phi_inf_, grad_inf_));
    return true;
  }

  bool StationaryPoint() {
    if (grad_inf_ != 0.0) return false;
    Finish(TerminationType::kStationaryPoint, internal::ZeroGradientMessage(phi_inf_));
    return true;
  }

  // ---- step 2: the direction d and slope_ = grad psi' d ------------------------------
  // Newton J d = -Phi (eq. 21) kept if it passes the descent test (eq. 22); else, with
  // Options::regularized_direction, the Levenberg-Marquardt direction; else -grad psi.
  Direction ChooseDirection(int k) {
    const bool newton_solved = NewtonDirection(k);
    if (finished_) return Direction::kNewton;
    if (newton_solved && PassesDescentTest()) return Direction::kNewton;
    if (newton_solved) ++s_.descent_test_failures;
    else ++s_.linear_solver_failures;
    if (!o_.gradient_fallback) {
      if (!newton_solved)
        Finish(TerminationType::kLinearSolverFailure,
               std::string("the Newton system is singular or the ") + ToString(resolved_) +
                   " solve failed at iteration " + std::to_string(k) +
                   " and gradient_fallback is off");
      return Direction::kNewton;  // Algorithm 1 without step 2's fallback
    }
    if (regularized_ && RegularizedDirection() && PassesDescentTest()) {
      ++s_.regularized_steps;
      return Direction::kRegularized;
    }
    w_.d = -w_.grad;
    slope_ = -w_.grad.squaredNorm();
    ++s_.gradient_steps;
    return Direction::kGradient;
  }

  // grad psi' d <= -rho ||d||^p (eq. 22); sets slope_.
  bool PassesDescentTest() {
    slope_ = w_.grad.dot(w_.d);
    return internal::PassesDescentTest(slope_, w_.d.norm(), o_);
  }

  // J d = -Phi (eq. 21). A factorization predicted to take longer than the time left is
  // not started (the solve ends with kTimeLimit). false when singular or failed.
  bool NewtonDirection(int k) {
    const auto t0 = Clock::now();
    w_.newton_rhs = -w_.phi;
    bool solved = FactorizeJacobian(k) && SolveFactorized(w_.newton_rhs, &w_.d) && AllFinite(w_.d);
    if (solved) {  // the backward-error guard of globalization.hpp
      const double terms_inf = w_.ResidualAndTerms(w_.d, w_.phi, &w_.newton_residual, &w_.newton_terms);
      solved = internal::NewtonSolutionAccurate(w_.newton_residual.lpNorm<Eigen::Infinity>(), phi_inf_,
                                                terms_inf);
    }
    s_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // Symbolic analysis (sparse backends), the time check, the numeric factorization of J.
  bool FactorizeJacobian(int k) {
    if (w_.dense) {
      const double flops = internal::DenseLU::PredictedFlops(n_);
      return FactorizationFits(flops, internal::DenseLU::kTypicalFlopRate, k) &&
             TimedFactorize(flops, [&] { return w_.dense_lu.Factorize(w_.Jd); });
    }
    internal::LinearSolver& solver = *w_.linear_solver;
    if (!solver.Analyze(w_.J, pattern_changed_)) return false;
    const double flops = solver.PredictedFactorizationFlops();
    return FactorizationFits(flops, solver.TypicalFlopRate(), k) &&
           TimedFactorize(flops, [&] { return solver.Factorize(w_.J); });
  }

  // x = J^-1 rhs with the factorization of FactorizeJacobian.
  bool SolveFactorized(const Vector& rhs, Vector* x) {
    if (!w_.dense) return w_.linear_solver->Solve(rhs, x);
    w_.dense_lu.Solve(rhs, x);
    return true;
  }

  int SymbolicFactorizations() const { return w_.dense ? 0 : w_.linear_solver->symbolic_factorizations(); }
  // Cholesky fallbacks of the Newton and the regularized (J'J + mu I) solver.
  int Fallbacks() const {
    if (w_.dense) return 0;
    return w_.linear_solver->fallbacks() + (w_.regularized_solver ? w_.regularized_solver->fallbacks() : 0);
  }

  // Predicted time of the numeric factorization = flops / rate (Options::max_seconds,
  // factorization_flop_rate; typical_rate: the backend's before one was timed); false (and
  // the solve finished) when it exceeds the time left.
  bool FactorizationFits(double flops, double typical_rate, int k) {
    s_.predicted_factorization_flops = flops;
    const double rate = w_.measured_flop_rate > 0.0      ? w_.measured_flop_rate
                        : o_.factorization_flop_rate > 0.0 ? o_.factorization_flop_rate
                                                           : typical_rate;
    const double left = o_.max_seconds - Seconds(start_);
    if (!std::isfinite(o_.max_seconds) || !(flops / rate > left)) return true;
    Finish(TerminationType::kTimeLimit,
           "the factorization at iteration " + std::to_string(k) + " was not started: " +
               Fmt("%.3g", flops) + " flops at " + Fmt("%.3g", rate) + " flop/s predict " +
               Fmt("%.3g", flops / rate) + " s, more than the " + Fmt("%.3g", left) +
               " s left of max_seconds = " + Fmt("%.3g", o_.max_seconds) +
               " s (||Phi||_inf = " + Fmt("%.3e", phi_inf_) + ")");
    return false;
  }

  // factorize() returns false when singular. The measured rate (flops / seconds) only
  // serves FactorizationFits: timed under a finite max_seconds.
  template <class Factorize>
  bool TimedFactorize(double flops, Factorize&& factorize) {
    if (!std::isfinite(o_.max_seconds)) return factorize();
    const auto t0 = Clock::now();
    const bool ok = factorize();
    const double seconds = Seconds(t0);
    if (std::isfinite(flops) && flops > 0.0 && seconds > 0.0) w_.measured_flop_rate = flops / seconds;
    return ok;
  }

  // Levenberg-Marquardt direction (J'J + mu I) d = -J' Phi with mu = ||Phi||_2 (Fan and
  // Yuan 2005; the proximal perturbation of Munson et al. 2001, sec. 3): a descent
  // direction of psi whenever grad psi != 0, between Newton (mu -> 0) and -grad psi / mu.
  bool RegularizedDirection() {
    const auto t0 = Clock::now();
    const double mu = std::sqrt(2.0 * psi_);
    if (!w_.regularized_solver) w_.regularized_solver = internal::MakeLinearSolver(resolved_);
    if (w_.identity.rows() != n_) {
      w_.identity.resize(n_, n_);
      w_.identity.setIdentity();
    }
    if (w_.dense) w_.J = w_.Jd.sparseView();  // (the option's sparse form; off by default)
    w_.normal_matrix = SparseMatrix(w_.J.transpose()) * w_.J;
    w_.normal_matrix += mu * w_.identity;
    w_.normal_matrix.makeCompressed();
    // The pattern of J'J + mu I follows J's; analysed again whenever J's changed.
    const bool changed = pattern_changed_ || !w_.regularized_analyzed ||
                         w_.normal_matrix.nonZeros() != w_.regularized_nonzeros;
    w_.regularized_nonzeros = w_.normal_matrix.nonZeros();
    w_.newton_rhs = -w_.grad;
    bool solved = w_.regularized_solver->Analyze(w_.normal_matrix, changed);
    w_.regularized_analyzed = solved;
    internal::LinearSolver& solver = *w_.regularized_solver;
    solved = solved &&
             TimedFactorize(solver.PredictedFactorizationFlops(), [&] { return solver.Factorize(w_.normal_matrix); }) &&
             w_.regularized_solver->Solve(w_.newton_rhs, &w_.d) && AllFinite(w_.d);
    s_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // ---- step 3: Armijo line search on psi with steps 2^-i -------------------------------
  // Monotone (nonmonotone_memory = 1, eq. 23) or nonmonotone; the rules are
  // internal::ArmijoLineSearch's (globalization.hpp), this supplies the trial points.
  bool LineSearch(int k, Direction direction) {
    const double reference = w_.armijo_reference.Update(static_cast<size_t>(k - first_k_), psi_);
    const internal::LineSearchResult r = internal::ArmijoLineSearch(
        o_, reference, slope_, [&] { return OutOfTime("in the line search of iteration ", k); },
        [&](double t) {
          w_.x_trial = x_ + t * w_.d;
          // (Component by component: a test t ||d||_inf <= eps ||x||_inf stopped the 2D
          // obstacle at 10^6 unknowns, whose last corrections, ~1e-15 on gaps of 5e-7, are
          // far below eps max|w| ~ 8e-16 x 3.5.)
          if (w_.x_trial == x_) return internal::LineSearchTrial{internal::LineSearchTrial::kUnchanged, 0.0};
          if (!Evaluate(w_.x_trial, &w_.Et, &w_.At, &w_.Bt, &w_.phi_trial))
            return internal::LineSearchTrial{internal::LineSearchTrial::kNotEvaluable, 0.0};
          if (!AllFinite(w_.phi_trial))
            return internal::LineSearchTrial{internal::LineSearchTrial::kNonFinite, 0.0};
          return internal::LineSearchTrial{internal::LineSearchTrial::kEvaluated,
                                           0.5 * w_.phi_trial.squaredNorm()};
        });
    if (r.out_of_time) {
      s_.backtracks += r.backtracks;
      return false;
    }
    s_.backtracks += std::min(r.backtracks, o_.max_backtracks);
    step_ = r.step;
    backtracks_ = r.backtracks;
    if (!r.accepted) {
      const char* name = direction == Direction::kGradient      ? "gradient"
                         : direction == Direction::kRegularized ? "regularized"
                                                                : "Newton";
      const internal::Ending ending = internal::LineSearchFailure(o_, r, name, k, phi_inf_, grad_inf_);
      Finish(ending.termination, ending.message);
    }
    return r.accepted;
  }

  // ---- restart strategy (Options::merit_restarts) -----------------------------------
  // An FB-family solve that ended at a non-solution stationary point of psi or in a failed
  // line search continues with the other member of the family from the problem's restart
  // point (MixedProblem::RestartPoint: x^k itself, or for a box MCP x^k projected onto the
  // box): Phi, psi, the nonmonotone memory and the stagnation window start afresh.
  bool Restart(int k) {
    if (!internal::MeritRestartApplies(s_.termination, restarts_left_, function_)) return false;
    // The restart point and its Phi go to the trial buffers, so that a failed restart
    // leaves x^k, Phi(x^k) and the merit function of the finished solve untouched.
    const NcpFunction stuck_function = function_;
    function_ = internal::OtherMeritFunction(function_);
    w_.x_trial = x_;
    if (!problem_.RestartPoint(&w_.x_trial) || w_.x_trial.size() != n_ ||
        !Evaluate(w_.x_trial, &w_.Et, &w_.At, &w_.Bt, &w_.phi_trial) || !AllFinite(w_.phi_trial)) {
      function_ = stuck_function;
      return false;
    }
    x_.swap(w_.x_trial);
    w_.E.swap(w_.Et);
    w_.A.swap(w_.At);
    w_.B.swap(w_.Bt);
    w_.phi.swap(w_.phi_trial);
    --restarts_left_;
    ++s_.merit_restarts;
    if (o_.keep_trace && !s_.trace.empty()) s_.trace.pop_back();  // iterate k is reported anew
    finished_ = false;
    s_.termination = TerminationType::kNotSolved;
    first_k_ = k;
    if (o_.log_to_stderr)
      std::fprintf(stderr, "restart %d at iteration %d with %s\n", s_.merit_restarts, k, ToString(function_));
    return true;
  }

  // ---- the hybrid default (Options::hybrid, strategy.hpp) ---------------------------
  // Records iterate k; true when the strategy was left for slow progress or its budget and
  // the next one continues from its best point.
  bool LeaveStrategy(int k) {
    if (!o_.hybrid) return false;
    const size_t kk = static_cast<size_t>(k - first_k_);
    w_.progress.Observe(kk, psi_, x_, k);
    SwitchReason reason = SwitchReason::kStuck;
    return w_.progress.ShouldLeave(kk, k - strategy_start_, o_, &reason) && SwitchStrategy(k, reason);
  }

  // The next strategy of the schedule continues from the smallest-psi point of this one
  // (its MixedProblem::RestartPoint), at iterate k; Phi, psi, the nonmonotone memory, the
  // stagnation window and the progress test start afresh. kStuck applies to a solve that
  // ended at a non-solution stationary point, in a failed line search or a failed Newton
  // solve; false (nothing changed) when no strategy is left or the point cannot be evaluated.
  bool SwitchStrategy(int k, SwitchReason reason) {
    if (!o_.hybrid) return false;
    const bool stuck = s_.termination == TerminationType::kStationaryPoint ||
                       s_.termination == TerminationType::kLineSearchFailure ||
                       s_.termination == TerminationType::kLinearSolverFailure;
    if (reason == SwitchReason::kStuck && !(finished_ && stuck)) return false;
    const Strategy from{function_, regularized_};
    if (!w_.schedule.Advance(from)) return false;
    const Strategy& to = w_.schedule.current();
    // A stuck strategy may not have recorded iterate k (TestStop came first).
    w_.progress.Observe(static_cast<size_t>(k - first_k_), psi_, x_, k);
    w_.x_trial = w_.progress.best_x();
    function_ = to.ncp_function;  // Evaluate() uses function_
    if (!problem_.RestartPoint(&w_.x_trial) || w_.x_trial.size() != n_ ||
        !Evaluate(w_.x_trial, &w_.Et, &w_.At, &w_.Bt, &w_.phi_trial) || !AllFinite(w_.phi_trial)) {
      function_ = from.ncp_function;
      return false;
    }
    StrategySwitch record;
    record.iteration = k;
    record.from_strategy = from;
    record.to_strategy = to;
    record.reason = reason;
    record.best_iteration = w_.progress.best_iteration();
    record.best_psi = w_.progress.best_psi();
    s_.strategy_switches.push_back(record);
    x_.swap(w_.x_trial);
    w_.E.swap(w_.Et);
    w_.A.swap(w_.At);
    w_.B.swap(w_.Bt);
    w_.phi.swap(w_.phi_trial);
    regularized_ = to.regularized_direction;
    if (o_.keep_trace && !s_.trace.empty()) s_.trace.pop_back();  // iterate k is reported anew
    finished_ = false;
    s_.termination = TerminationType::kNotSolved;
    first_k_ = strategy_start_ = k;
    if (o_.log_to_stderr)
      std::fprintf(stderr, "strategy %s -> %s at iteration %d (%s), from iteration %d\n",
                   internal::StrategyName(from).c_str(), internal::StrategyName(to).c_str(), k,
                   ToString(reason), record.best_iteration);
    return true;
  }

  // ---- step 4: x^{k+1} = x^k + t d ---------------------------------------------------
  void Accept(Direction direction) {
    x_.swap(w_.x_trial);
    w_.E.swap(w_.Et);
    w_.A.swap(w_.At);
    w_.B.swap(w_.Bt);
    w_.phi.swap(w_.phi_trial);
    ++s_.iterations;
    record_.step_length = step_;
    record_.direction_norm = w_.d.norm();
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
    s_.final_phi_inf = w_.phi.lpNorm<Eigen::Infinity>();
    s_.final_psi = 0.5 * w_.phi.squaredNorm();
    s_.symbolic_factorizations = SymbolicFactorizations() - symbolic_before_;
    s_.cholesky_fallbacks = Fallbacks() - fallbacks_before_;
    s_.total_time_s = Seconds(start_);
  }

  const Options& o_;
  Workspace& w_;
  MixedProblem& problem_;
  Vector& x_;
  Summary& s_;
  const int n_, m_, p_;
  Clock::time_point start_;
  LinearSolverType resolved_ = LinearSolverType::kAuto;
  int symbolic_before_ = 0;
  int fallbacks_before_ = 0;
  double threshold_ = 0.0;
  NcpFunction function_ = NcpFunction::kFischerBurmeister;  // the current merit (restarts switch it)
  int restarts_left_ = 0, first_k_ = 0;                      // first_k_: iterate of the last (re)start
  bool regularized_ = false;   // the current strategy tries the LM direction (hybrid switches it)
  int strategy_start_ = 0;     // iterate the current strategy of the hybrid began at
  IterationRecord record_;
  // Iterate k.
  double phi_inf_ = 0.0, psi_ = 0.0, grad_inf_ = 0.0, slope_ = 0.0, step_ = 0.0;
  int backtracks_ = 0, degenerate_count_ = 0;
  bool converged_ = false, have_jacobian_ = false, jacobian_ok_ = true;
  bool roundoff_limited_ = false;  // converged_ by the round-off floor, not by the tolerance
  bool pattern_changed_ = false, finished_ = false;
};

void Solver::Solve(MixedProblem& problem, Vector* x_ptr, Summary* summary_ptr) {
  if (x_ptr == nullptr || summary_ptr == nullptr)
    throw std::invalid_argument("ncp::Solver::Solve: x and summary must not be null");
  CheckProblem(problem, *x_ptr);
  Iteration(options_, *workspace_, problem, *x_ptr, *summary_ptr).Run();
}

void Solver::Solve(SquareFunction& F, const Vector& lower, const Vector& upper, Vector* x,
                   Summary* summary) {
  internal::SolveBoxMcp(*this, &workspace_->box_mcp, F, lower, upper, x, summary);
}

void Solver::SolveNcp(SquareFunction& F, Vector* x, Summary* summary) {
  const int n = F.NumVariables();
  Solve(F, Vector::Zero(n), Vector::Constant(n, std::numeric_limits<double>::infinity()), x,
        summary);
}

void Solver::set_options(const Options& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("ncp::Solver: " + error);
  options_ = options;
}

namespace {

// The one-shot calls of small problems (n <= kPooledMaxVariables) borrow a Solver kept per
// thread, so that only the first call builds the workspace (~110 allocations, a few us: half
// the time of a small solve); everything a solve depends on is re-derived in Start() or
// checked (backend, box-MCP bounds, Jacobian pattern), so a borrowed workspace gives the
// same iterates as a fresh one. A call made while the thread's Solver is busy (from inside F)
// or for a larger problem, whose workspace should not outlive the call, gets a fresh Solver.
constexpr int kPooledMaxVariables = 100;

struct PooledSolver {
  std::unique_ptr<Solver> solver;
  bool busy = false;
};

template <typename SolveCall>
void SolveOnce(const Options& options, int n, SolveCall&& call) {
  thread_local PooledSolver pool;
  if (pool.busy || n > kPooledMaxVariables) {
    Solver solver(options);
    call(solver);
    return;
  }
  if (pool.solver) pool.solver->set_options(options);
  else pool.solver = std::make_unique<Solver>(options);
  struct Borrow {  // released on return and on an exception
    bool& busy;
    explicit Borrow(bool& b) : busy(b) { busy = true; }
    ~Borrow() { busy = false; }
  } borrow(pool.busy);
  call(*pool.solver);
}

}  // namespace

void Solve(const Options& options, MixedProblem& problem, Vector* x, Summary* summary) {
  SolveOnce(options, problem.NumVariables(), [&](Solver& s) { s.Solve(problem, x, summary); });
}

void Solve(const Options& options, SquareFunction& F, const Vector& lower, const Vector& upper,
           Vector* x, Summary* summary) {
  SolveOnce(options, F.NumVariables(), [&](Solver& s) { s.Solve(F, lower, upper, x, summary); });
}

void SolveNcp(const Options& options, SquareFunction& F, Vector* x, Summary* summary) {
  SolveOnce(options, F.NumVariables(), [&](Solver& s) { s.SolveNcp(F, x, summary); });
}

}  // namespace ncp
