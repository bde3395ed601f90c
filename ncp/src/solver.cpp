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
#include "box_mcp.hpp"
#include "ncp_function_internal.hpp"

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

}  // namespace

// ---------------------------------------------------------------------------------------
// Options and Summary.

bool Options::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    return fail("Options::tolerance must be finite and >= 0, got " + Fmt("%g", tolerance));
  if (max_iterations < 0)
    return fail("Options::max_iterations must be >= 0, got " + std::to_string(max_iterations));
  if (!(descent_rho > 0.0))
    return fail("Options::descent_rho must be > 0 (eq. 22), got " + Fmt("%g", descent_rho));
  if (!(descent_p > 2.0))
    return fail("Options::descent_p must be > 2 (eq. 22), got " + Fmt("%g", descent_p));
  if (!(armijo_beta > 0.0 && armijo_beta < 0.5))
    return fail("Options::armijo_beta must lie in (0, 1/2) (eq. 23), got " +
                Fmt("%g", armijo_beta));
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
  if (dense_threshold < 0)
    return fail("Options::dense_threshold must be >= 0, got " + std::to_string(dense_threshold));
  // Enums set from integers (a cast, a file) may hold any value: checked before a switch.
  const int function = static_cast<int>(ncp_function);
  if (function < 0 || function > static_cast<int>(NcpFunction::kPenalizedFischerBurmeister))
    return fail("Options::ncp_function must be an NcpFunction (0.." +
                std::to_string(static_cast<int>(NcpFunction::kPenalizedFischerBurmeister)) + "), got " +
                std::to_string(function));
  const int solver = static_cast<int>(linear_solver);
  if (solver < 0 || solver > static_cast<int>(LinearSolverType::kKlu))
    return fail("Options::linear_solver must be a LinearSolverType (0.." +
                std::to_string(static_cast<int>(LinearSolverType::kKlu)) + "), got " + std::to_string(solver));
  return true;
}

std::string Summary::BriefReport() const {
  std::ostringstream out;
  out << ToString(termination) << ": " << iterations << " iterations, " << jacobian_evaluations
      << " Jacobian / " << residual_evaluations << " residual evaluations, ||Phi||_inf = "
      << Fmt("%.3e", final_phi_inf) << ", " << Fmt("%.3g", total_time_s) << " s";
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
      << "  linear solver failures   " << linear_solver_failures << "\n"
      << "  descent test failures    " << descent_test_failures << "\n"
      << "  backtracks               " << backtracks << "\n"
      << "  symbolic factorizations  " << symbolic_factorizations << "\n"
      << "  ||Phi||_inf initial      " << Fmt("%.6e", initial_phi_inf) << "\n"
      << "  ||Phi||_inf final        " << Fmt("%.6e", final_phi_inf) << "\n"
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

  // Cached patterns of the user's JE, JA, JB; a change triggers a new symbolic analysis.
  std::vector<int> pattern[3][2];
  bool have_pattern = false;

  // J = [JE; diag(da) JA + diag(db) JB], pattern = union; map[s][k] is where the k-th
  // stored entry of source s lands in J's value array.
  SparseMatrix J;
  std::vector<int> map[3];

  SparseMatrix JE, JA, JB;
  Vector E, A, B, Et, At, Bt;  // current point and trial point
  Vector phi, phi_trial, grad, d, x_trial, da, db, z, za, zb, newton_rhs, newton_residual;
  // psi of the last stagnation_window + 1 iterates (ring buffer): the stagnation test.
  std::vector<double> psi_ring;

  static bool SamePattern(const SparseMatrix& S, const std::vector<int>& outer,
                          const std::vector<int>& inner) {
    const auto cols = static_cast<size_t>(S.cols());
    const auto nnz = static_cast<size_t>(S.nonZeros());
    return outer.size() == cols + 1 && inner.size() == nnz &&
           std::equal(S.outerIndexPtr(), S.outerIndexPtr() + cols + 1, outer.begin()) &&
           std::equal(S.innerIndexPtr(), S.innerIndexPtr() + nnz, inner.begin());
  }

  /// Returns true when the pattern differs from the cached one (and rebuilds J's pattern).
  bool UpdatePattern(int m) {
    const SparseMatrix* sources[3] = {&JE, &JA, &JB};
    bool same = have_pattern;
    for (int s = 0; s < 3 && same; ++s)
      same = SamePattern(*sources[s], pattern[s][0], pattern[s][1]);
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
      pattern[s][0].assign(S.outerIndexPtr(), S.outerIndexPtr() + S.cols() + 1);
      pattern[s][1].assign(S.innerIndexPtr(), S.innerIndexPtr() + S.nonZeros());
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

  /// J values = [JE; diag(da) JA + diag(db) JB] on the cached pattern.
  void FillJacobian() {
    double* values = J.valuePtr();
    std::fill(values, values + J.nonZeros(), 0.0);
    const SparseMatrix* sources[3] = {&JE, &JA, &JB};
    const Vector* scale[3] = {nullptr, &da, &db};
    for (int s = 0; s < 3; ++s) {
      const SparseMatrix& S = *sources[s];
      size_t k = 0;
      for (int c = 0; c < S.outerSize(); ++c)
        for (SparseMatrix::InnerIterator it(S, c); it; ++it, ++k)
          values[map[s][k]] += scale[s] ? (*scale[s])(it.row()) * it.value() : it.value();
    }
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
// Algorithm 1.

void Solver::Solve(MixedProblem& problem, Vector* x_ptr, Summary* summary_ptr) {
  if (x_ptr == nullptr || summary_ptr == nullptr)
    throw std::invalid_argument("ncp::Solver::Solve: x and summary must not be null");
  Vector& x = *x_ptr;
  Summary& s = *summary_ptr;
  Workspace& w = *workspace_;
  const Options& o = options_;

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
  const int p = n - m;
  for (int j = 0; j < p; ++j) {
    const int v = problem.PairVariable(j);
    if (v < 0 || v >= n)
      throw std::invalid_argument("ncp::Solver::Solve: PairVariable(" + std::to_string(j) +
                                  ") = " + std::to_string(v) + " is outside [0, n)");
  }

  const auto start = Clock::now();
  s = Summary();
  s.num_variables = n;
  s.num_equations = m;
  s.num_pairs = p;
  s.ncp_function = o.ncp_function;
  s.linear_solver_requested = o.linear_solver;
  s.iterations = 0;
  s.jacobian_evaluations = 0;
  s.residual_evaluations = 0;
  s.gradient_steps = 0;
  s.linear_solver_failures = 0;
  s.descent_test_failures = 0;
  s.backtracks = 0;
  s.evaluation_time_s = 0.0;
  s.linear_solver_time_s = 0.0;

  LinearSolverType resolved = o.linear_solver;
  if (resolved == LinearSolverType::kAuto)
    resolved = n <= o.dense_threshold ? LinearSolverType::kDenseLU : LinearSolverType::kUmfpack;
  if (!w.linear_solver || w.linear_solver->type() != resolved) {
    w.linear_solver = internal::MakeLinearSolver(resolved);
    w.have_pattern = false;
  }
  const int symbolic_before = w.linear_solver->symbolic_factorizations();
  s.linear_solver_used = resolved;

  for (Vector* v : {&w.E, &w.Et}) v->setZero(m);
  for (Vector* v : {&w.A, &w.B, &w.At, &w.Bt, &w.da, &w.db, &w.za, &w.zb}) v->setZero(p);
  for (Vector* v : {&w.phi, &w.phi_trial, &w.grad, &w.d, &w.x_trial, &w.z, &w.newton_rhs,
                    &w.newton_residual})
    v->setZero(n);
  if (w.JE.rows() != m || w.JE.cols() != n) w.JE.resize(m, n);
  if (w.JA.rows() != p || w.JA.cols() != n) w.JA.resize(p, n);
  if (w.JB.rows() != p || w.JB.cols() != n) w.JB.resize(p, n);

  // Phi(x) from E, A, B: equations first, then phi(A_j, B_j).
  auto evaluate = [&](const Vector& point, Vector* E, Vector* A, Vector* B, Vector* phi) {
    ++s.residual_evaluations;
    const auto t0 = Clock::now();
    const bool ok = problem.Evaluate(point, E, A, B);
    s.evaluation_time_s += Seconds(t0);
    if (!ok) return false;
    if (E->size() != m || A->size() != p || B->size() != p)
      throw std::invalid_argument("ncp::Solver: MixedProblem::Evaluate resized its outputs");
    phi->head(m) = *E;
    for (int j = 0; j < p; ++j)
      (*phi)(m + j) = internal::PhiValue(o.ncp_function, o.penalized_fb_lambda, (*A)(j), (*B)(j));
    return true;
  };

  auto finish = [&](TerminationType type, const std::string& message) {
    s.termination = type;
    s.message = message;
    s.final_phi_inf = w.phi.lpNorm<Eigen::Infinity>();
    s.final_psi = 0.5 * w.phi.squaredNorm();
    s.symbolic_factorizations = w.linear_solver->symbolic_factorizations() - symbolic_before;
    s.total_time_s = Seconds(start);
  };

  if (!evaluate(x, &w.E, &w.A, &w.B, &w.phi)) {
    w.phi.setConstant(std::numeric_limits<double>::quiet_NaN());
    finish(TerminationType::kEvaluationFailure, "the problem cannot be evaluated at the start point");
    return;
  }
  s.initial_phi_inf = w.phi.lpNorm<Eigen::Infinity>();
  if (!AllFinite(w.phi)) {
    finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
    return;
  }

  IterationRecord record;
  const size_t window = static_cast<size_t>(o.stagnation_window);
  std::vector<double>& psi_ring = w.psi_ring;
  psi_ring.assign(window + 1, 0.0);
  if (o.log_to_stderr)
    std::fprintf(stderr, "%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter", "|Phi|_inf", "psi",
                 "|grad|_inf", "step", "bt", "grad", "|gam|");

  for (int k = 0;; ++k) {
    const double phi_inf = w.phi.lpNorm<Eigen::Infinity>();
    const double psi = 0.5 * w.phi.squaredNorm();

    // Converged? (step 1; the infinity norm as in thesis section 6.4)
    const bool converged = phi_inf <= o.tolerance;

    // Jacobian element J^k in the B-subdifferential (step 2), unless we stop here.
    bool jacobian_ok = true;
    bool pattern_changed = false;
    int degenerate_count = 0;
    if (!converged && k < o.max_iterations) {
      ++s.jacobian_evaluations;
      const auto t0 = Clock::now();
      jacobian_ok = problem.Jacobian(x, &w.JE, &w.JA, &w.JB);
      s.evaluation_time_s += Seconds(t0);
      if (jacobian_ok) {
        CheckJacobianShape(w.JE, m, n, "JE");
        CheckJacobianShape(w.JA, p, n, "JA");
        CheckJacobianShape(w.JB, p, n, "JB");
        w.JE.makeCompressed();
        w.JA.makeCompressed();
        w.JB.makeCompressed();
      }
    }
    if (jacobian_ok && !converged && k < o.max_iterations) {
      if (!AllFinite(w.JE) || !AllFinite(w.JA) || !AllFinite(w.JB)) {
        finish(TerminationType::kNonFiniteValues,
               "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
        return;
      }
      // Degenerate set gamma = {j : A_j = B_j = 0} (eq. 13) and the z-vector rule:
      // z_v = 1 at the variable of every degenerate pair, 0 elsewhere (DFK; thesis 3.1).
      const bool fb_family = o.ncp_function != NcpFunction::kMin;
      if (fb_family) {
        w.z.setZero();
        for (int j = 0; j < p; ++j) {
          if (std::hypot(w.A(j), w.B(j)) <= o.degenerate_tolerance) {
            w.z(problem.PairVariable(j)) = 1.0;
            ++degenerate_count;
          }
        }
        if (degenerate_count > 0) {
          w.za.noalias() = w.JA * w.z;
          w.zb.noalias() = w.JB * w.z;
        }
      }
      for (int j = 0; j < p; ++j) {
        const bool degenerate =
            fb_family && std::hypot(w.A(j), w.B(j)) <= o.degenerate_tolerance;
        const internal::PhiPartials dp = internal::PhiDerivatives(
            o.ncp_function, o.penalized_fb_lambda, w.A(j), w.B(j), degenerate,
            degenerate ? w.za(j) : 0.0, degenerate ? w.zb(j) : 0.0, o.min_tie_takes_b);
        w.da(j) = dp.da;
        w.db(j) = dp.db;
      }
      pattern_changed = w.UpdatePattern(m);
      w.FillJacobian();
      w.grad.noalias() = w.J.transpose() * w.phi;  // grad psi = J' Phi (eq. 24)
    }

    // Trace, log, callback for iterate k.
    record.iteration = k;
    record.phi_inf = phi_inf;
    record.psi = psi;
    record.grad_psi_inf = (jacobian_ok && !converged && k < o.max_iterations)
                              ? w.grad.lpNorm<Eigen::Infinity>()
                              : 0.0;
    record.degenerate_pairs = degenerate_count;
    record.time_s = Seconds(start);
    if (o.keep_trace) s.trace.push_back(record);
    if (o.log_to_stderr)
      std::fprintf(stderr, "%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n", k, phi_inf, psi,
                   record.grad_psi_inf, record.step_length, record.backtracks,
                   record.gradient_step ? "yes" : "no", degenerate_count);
    if (o.callback && !o.callback(record)) {
      finish(TerminationType::kUserAbort, "the iteration callback stopped the solve at iteration " +
                                              std::to_string(k));
      return;
    }

    if (converged) {
      finish(TerminationType::kConverged, "||Phi||_inf = " + Fmt("%.3e", phi_inf) + " <= " +
                                              Fmt("%.3e", o.tolerance) + " after " +
                                              std::to_string(k) + " iterations");
      return;
    }
    if (k >= o.max_iterations) {
      finish(TerminationType::kMaxIterations,
             "reached max_iterations = " + std::to_string(o.max_iterations) +
                 " with ||Phi||_inf = " + Fmt("%.3e", phi_inf));
      return;
    }
    if (!jacobian_ok) {
      finish(TerminationType::kEvaluationFailure,
             "MixedProblem::Jacobian returned false at iteration " + std::to_string(k));
      return;
    }
    const double grad_inf = w.grad.lpNorm<Eigen::Infinity>();
    const size_t kk = static_cast<size_t>(k);
    psi_ring[kk % (window + 1)] = psi;
    const double psi_window_ago = psi_ring[(kk + 1) % (window + 1)];  // psi at k - window
    if (window > 0 && kk >= window && psi_window_ago - psi <= o.stagnation_tolerance * psi_window_ago) {
      finish(TerminationType::kStationaryPoint,
             "psi decreased by less than " + Fmt("%.1e", o.stagnation_tolerance) +
                 " relative over the last " + std::to_string(window) +
                 " iterations (||Phi||_inf = " + Fmt("%.3e", phi_inf) + ", ||grad psi||_inf = " +
                 Fmt("%.3e", grad_inf) +
                 "): the iterates approach a stationary point of psi that is not a solution");
      return;
    }
    if (grad_inf == 0.0) {
      finish(TerminationType::kStationaryPoint,
             "grad psi = J' Phi = 0 with ||Phi||_inf = " + Fmt("%.3e", phi_inf) +
                 ": a stationary point of psi that is not a solution");
      return;
    }

    // Newton direction J d = -Phi (eq. 21), or the gradient fallback (step 2).
    bool use_gradient = false;
    {
      const auto t0 = Clock::now();
      w.newton_rhs = -w.phi;
      bool solved = w.linear_solver->Factorize(w.J, pattern_changed) &&
                    w.linear_solver->Solve(w.newton_rhs, &w.d) && AllFinite(w.d);
      if (solved) {
        // Guard against a numerically singular factorization that "succeeded": the
        // computed d must satisfy J d = -Phi to a small relative residual.
        w.newton_residual.noalias() = w.J * w.d;
        const double jd_inf = w.newton_residual.lpNorm<Eigen::Infinity>();
        w.newton_residual += w.phi;
        solved = w.newton_residual.lpNorm<Eigen::Infinity>() <= 1e-6 * (phi_inf + jd_inf);
      }
      s.linear_solver_time_s += Seconds(t0);
      if (!solved) {
        ++s.linear_solver_failures;
        if (!o.gradient_fallback) {
          finish(TerminationType::kLinearSolverFailure,
                 std::string("the Newton system is singular or the ") + ToString(resolved) +
                     " solve failed at iteration " + std::to_string(k) +
                     " and gradient_fallback is off");
          return;
        }
        use_gradient = true;
      }
    }
    double slope = 0.0;  // grad psi' d
    if (!use_gradient) {
      slope = w.grad.dot(w.d);
      const double d_norm = w.d.norm();
      if (slope > -o.descent_rho * std::pow(d_norm, o.descent_p)) {  // eq. (22) fails
        ++s.descent_test_failures;
        use_gradient = o.gradient_fallback;
      }
    }
    if (use_gradient) {
      w.d = -w.grad;
      slope = -w.grad.squaredNorm();
      ++s.gradient_steps;
    }

    // Armijo line search on psi with steps 2^-i (step 3, eq. 23). A trial point where the
    // problem cannot be evaluated, or evaluates to non-finite values, is rejected too.
    // Numerically, a step is only taken if it changes x and strictly decreases psi;
    // otherwise the iteration would stall at round-off level.
    double t = 1.0;
    bool accepted = false;
    int i = 0, trials = 0, non_finite_trials = 0, failed_trials = 0;
    const double d_inf = w.d.lpNorm<Eigen::Infinity>();
    const double x_inf = x.lpNorm<Eigen::Infinity>();
    for (; i <= o.max_backtracks; ++i, t *= 0.5) {
      if (t * d_inf <= std::numeric_limits<double>::epsilon() * x_inf) break;
      w.x_trial = x + t * w.d;
      ++trials;
      if (!evaluate(w.x_trial, &w.Et, &w.At, &w.Bt, &w.phi_trial)) {
        ++failed_trials;
        continue;
      }
      if (!AllFinite(w.phi_trial)) {
        ++non_finite_trials;
        continue;
      }
      const double psi_trial = 0.5 * w.phi_trial.squaredNorm();
      if (psi_trial <= psi + o.armijo_beta * t * slope && psi_trial < psi) {
        accepted = true;
        break;
      }
    }
    s.backtracks += std::min(i, o.max_backtracks);
    if (!accepted) {
      const std::string where = std::string(" along the ") +
                                (use_gradient ? "gradient" : "Newton") + " direction at iteration " +
                                std::to_string(k) + ", ||Phi||_inf = " + Fmt("%.3e", phi_inf) +
                                ", ||grad psi||_inf = " + Fmt("%.3e", grad_inf);
      if (trials > 0 && non_finite_trials == trials) {
        finish(TerminationType::kNonFiniteValues,
               "Phi has NaN or Inf entries at all " + std::to_string(trials) +
                   " trial points of the line search" + where);
      } else if (trials > 0 && failed_trials == trials) {
        finish(TerminationType::kEvaluationFailure,
               "the problem could not be evaluated at any of the " + std::to_string(trials) +
                   " trial points of the line search" + where);
      } else if (grad_inf <= o.stationarity_tolerance * phi_inf) {
        finish(TerminationType::kStationaryPoint,
               "no decrease of psi possible" + where +
                   ": a stationary point of psi that is not a solution");
      } else {
        finish(TerminationType::kLineSearchFailure,
               "no Armijo step of length >= 2^-" + std::to_string(o.max_backtracks) + where +
                   (non_finite_trials + failed_trials > 0
                        ? " (" + std::to_string(non_finite_trials) + " of " + std::to_string(trials) +
                              " trial points gave NaN/Inf, " + std::to_string(failed_trials) +
                              " could not be evaluated)"
                        : std::string()));
      }
      return;
    }

    // Step 4: accept.
    x.swap(w.x_trial);
    w.E.swap(w.Et);
    w.A.swap(w.At);
    w.B.swap(w.Bt);
    w.phi.swap(w.phi_trial);
    ++s.iterations;
    record.step_length = t;
    record.direction_norm = w.d.norm();
    record.backtracks = i;
    record.gradient_step = use_gradient;
  }
}

void Solver::Solve(SquareFunction& F, const Vector& lower, const Vector& upper, Vector* x,
                   Summary* summary) {
  internal::SolveBoxMcp(*this, F, lower, upper, x, summary);
}

void Solver::SolveNcp(SquareFunction& F, Vector* x, Summary* summary) {
  const int n = F.NumVariables();
  Solve(F, Vector::Zero(n), Vector::Constant(n, std::numeric_limits<double>::infinity()), x,
        summary);
}

void Solve(const Options& options, MixedProblem& problem, Vector* x, Summary* summary) {
  Solver(options).Solve(problem, x, summary);
}

void Solve(const Options& options, SquareFunction& F, const Vector& lower, const Vector& upper,
           Vector* x, Summary* summary) {
  Solver(options).Solve(F, lower, upper, x, summary);
}

void SolveNcp(const Options& options, SquareFunction& F, Vector* x, Summary* summary) {
  Solver(options).SolveNcp(F, x, summary);
}

}  // namespace ncp
