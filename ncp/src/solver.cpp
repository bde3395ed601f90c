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

#include "box_mcp.hpp"
#include "format_number.hpp"
#include "globalization.hpp"
#include "linear_solver.hpp"
#include "ncp/blas_threads.hpp"
#include "ncp_function_internal.hpp"
#include "strategy.hpp"
#include "workspace.hpp"

namespace ncp {
namespace {

using internal::FormatNumber;
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

void CheckJacobianShape(const SparseMatrix& S, Eigen::Index rows, Eigen::Index cols,
                        const char* name) {
  if (S.rows() != rows || S.cols() != cols) {
    std::ostringstream msg;
    msg << "ncp::Solver: MixedProblem::Jacobian returned " << name << " of size "
        << S.rows() << " x " << S.cols() << ", expected " << rows << " x " << cols;
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

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
    throw std::invalid_argument(
        "ncp::Solver::Solve: need 0 <= NumEquations() <= NumVariables(), got " +
        std::to_string(m) + " equations and " + std::to_string(n) + " variables");
  }
  if (x.size() != n) {
    throw std::invalid_argument("ncp::Solver::Solve: start point has size " +
                                std::to_string(x.size()) +
                                ", expected NumVariables() = " + std::to_string(n));
  }
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(x(i))) {
      throw std::invalid_argument("ncp::Solver::Solve: start point x[" +
                                  std::to_string(i) + "] = " + std::to_string(x(i)) +
                                  " is not finite");
    }
  }
  for (int j = 0; j < n - m; ++j) {
    const int v = problem.PairVariable(j);
    if (v < 0 || v >= n)
      throw std::invalid_argument("ncp::Solver::Solve: PairVariable(" +
                                  std::to_string(j) + ") = " + std::to_string(v) +
                                  " is outside [0, n)");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Algorithm 1, one named phase per step. Solver::Iteration holds the state of one solve:
// Run() reads like the algorithm,
//
//   Start                      Phi(x^0), sizes, backend, row weights
//   loop k = 0, 1, ...
//     BeginIterate             ||Phi(x^k)||_inf, psi(x^k)
//     EvaluateJacobian         J^k in the B-subdifferential, grad psi = J' Phi   (eq. 24)
//     WithinRoundoffFloor      converged to the accuracy double precision allows
//     Report                   trace, log, callback
//     TestStop                 step 1: ||Phi||_inf <= tolerance; safeguards
//     ChooseDirection          step 2: Newton (eq. 21, 22), regularized, -grad psi
//     LineSearch               step 3: Armijo, monotone (eq. 23) or nonmonotone
//     Accept                   step 4
//
// (the layout follows Ceres' LineSearchMinimizer::Minimize).

class Solver::Iteration {
 public:
  /// dense_jacobian: the problem's Jacobian of Phi written dense (a box MCP), used on
  /// the dense backend without row weights; nullptr: MixedProblem::Jacobian.
  Iteration(const Options& options, Workspace& workspace, MixedProblem& problem,
            internal::DenseMixedJacobian* dense_jacobian, Vector& x, Summary& summary)
      : options_(options),
        work_(workspace),
        problem_(problem),
        offered_dense_jacobian_(dense_jacobian),
        x_(x),
        summary_(summary),
        n_(problem.NumVariables()),
        m_(problem.NumEquations()),
        p_(n_ - m_) {}

  void Run() {
    if (!Start()) return;
    for (int k = 0;;) {
      BeginIterate(k);
      if (iterate_.have_jacobian && !EvaluateJacobian(k)) return;
      if (iterate_.have_jacobian && iterate_.jacobian_ok)
        iterate_.converged = iterate_.roundoff_limited = WithinRoundoffFloor();
      if (!Report(k)) return;
      if (TestStop(k)) {
        if (Restart(k) || SwitchStrategy(k, SwitchReason::kStuck)) continue;
        return;
      }
      if (LeaveStrategy(k)) continue;
      const Direction direction = TimedChooseDirection(k);
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
  enum class Direction { kNewton, kMinimumNorm, kRegularized, kGradient };

  // ||Phi(x^k)||_inf and psi(x^k); the rest of iterate k reset in one assignment.
  void BeginIterate(int k) {
    iterate_ = Iterate();
    iterate_.phi_inf = work_.phi.lpNorm<Eigen::Infinity>();
    iterate_.psi = 0.5 * work_.phi.squaredNorm();
    iterate_.converged = iterate_.phi_inf <= threshold_;
    iterate_.have_jacobian = !iterate_.converged && k < options_.max_iterations;
  }

  // ---- Start: sizes, backend, weights, Phi(x^0) ------------------------------------
  bool Start() {
    start_ = Clock::now();
    InitializeSummary();
    SelectBackend();
    work_.Resize(n_, m_);

    // Row weights from the problem's own scales (MixedProblem::Scales), once per solve.
    work_.SetWeights(problem_, x_, m_, p_, options_.tolerance);
    summary_.weighted_residual = work_.weighted;
    dense_jacobian_ = work_.dense && !work_.weighted ? offered_dense_jacobian_ : nullptr;
    threshold_ = options_.tolerance;  // on ||Phi||_inf, weighted (relative) or not
    function_ = options_.ncp_function;
    restarts_left_ = options_.merit_restarts;
    first_k_ = 0;
    regularized_ = options_.regularized_direction;
    strategy_start_ = 0;
    work_.schedule.Reset(options_);
    work_.progress.Reset(options_, n_);

    if (!Evaluate(x_, &work_.E, &work_.A, &work_.B, &work_.phi)) {
      work_.phi.setConstant(std::numeric_limits<double>::quiet_NaN());
      Finish(TerminationType::kEvaluationFailure,
             "the problem cannot be evaluated at the start point");
      return false;
    }
    summary_.initial_phi_inf = work_.phi.lpNorm<Eigen::Infinity>();
    if (!AllFinite(work_.phi)) {
      Finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
      return false;
    }
    work_.stagnation.Reset(options_.stagnation_window);
    work_.armijo_reference.Reset(options_.nonmonotone_memory);
    if (options_.log_to_stderr)
      std::fprintf(stderr, "%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter", "|Phi|_inf",
                   "psi", "|grad|_inf", "step", "bt", "dir", "|gam|");
    return true;
  }

  // The linear solver (kAuto: dense LU up to Options::dense_threshold unknowns, else
  // UMFPACK); the workspace's solvers and pattern are kept while the backend stays.
  void SelectBackend() {
    resolved_ = options_.linear_solver;
    if (resolved_ == LinearSolverType::kAuto)
      resolved_ = n_ <= options_.dense_threshold ? LinearSolverType::kDenseLU
                                                 : LinearSolverType::kUmfpack;
    if (work_.backend != resolved_) {
      work_.backend = resolved_;
      work_.dense = resolved_ == LinearSolverType::kDenseLU;
      work_.linear_solver = work_.dense ? nullptr : internal::MakeLinearSolver(resolved_);
      work_.regularized_solver
          .reset();  // made on first use (Options::regularized_direction)
      work_.have_pattern = false;
      work_.measured_flop_rate = 0.0;
    }
    symbolic_before_ = SymbolicFactorizations();
    fallbacks_before_ = Fallbacks();
    summary_.linear_solver_used = resolved_;
  }

  void InitializeSummary() {
    summary_ = Summary();
    summary_.num_variables = n_;
    summary_.num_equations = m_;
    summary_.num_pairs = p_;
    summary_.ncp_function = options_.ncp_function;
    summary_.linear_solver_requested = options_.linear_solver;
    summary_.iterations = summary_.jacobian_evaluations = summary_.residual_evaluations =
        0;
    summary_.gradient_steps = summary_.regularized_steps = summary_.merit_restarts = 0;
    summary_.minimum_norm_steps = summary_.equilibrated_factorizations = 0;
    summary_.linear_solver_failures = summary_.descent_test_failures =
        summary_.backtracks = 0;
    summary_.projected_start_components = summary_.projected_final_components = 0;
    summary_.evaluation_time_s = summary_.linear_solver_time_s = 0.0;
  }

  // ---- Phi(x) = [E; phi(A_j, B_j)] (thesis eq. 15), rows weighted by the scales ----
  bool Evaluate(const Vector& point, Vector* E, Vector* A, Vector* B, Vector* phi) {
    ++summary_.residual_evaluations;
    if (!problem_.Evaluate(point, E, A, B)) return false;
    if (E->size() != m_ || A->size() != p_ || B->size() != p_)
      throw std::invalid_argument(
          "ncp::Solver: MixedProblem::Evaluate resized its outputs");
    if (work_.weighted) {
      E->array() *= work_.we.array();
      A->array() *= work_.wa.array();
      B->array() *= work_.wb.array();
    }
    phi->head(m_) = *E;
    for (int j = 0; j < p_; ++j)
      (*phi)(m_ + j) =
          internal::PhiValue(function_, options_.penalized_fb_lambda, (*A)(j), (*B)(j));
    return true;
  }

  // ---- J^k in the B-subdifferential (step 2) and grad psi = J' Phi (eq. 24) ---------
  // Returns false only when the solve has finished (non-finite Jacobian); a Jacobian()
  // that returned false is reported by TestStop after the callback has seen iterate k.
  bool EvaluateJacobian(int k) {
    ++summary_.jacobian_evaluations;
    if (dense_jacobian_) return EvaluateDenseJacobian(k);
    iterate_.jacobian_ok = problem_.Jacobian(x_, &work_.JE, &work_.JA, &work_.JB);
    if (!iterate_.jacobian_ok) return true;
    CheckJacobianShape(work_.JE, m_, n_, "JE");
    CheckJacobianShape(work_.JA, p_, n_, "JA");
    CheckJacobianShape(work_.JB, p_, n_, "JB");
    for (SparseMatrix* S : {&work_.JE, &work_.JA, &work_.JB}) S->makeCompressed();
    if (work_.weighted) work_.WeightJacobianRows();
    if (!AllFinite(work_.JE) || !AllFinite(work_.JA) || !AllFinite(work_.JB)) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    PhiPartials();
    if (work_.dense) {
      work_.FillDenseJacobian(m_, x_);
    } else {
      iterate_.pattern_changed = work_.UpdatePattern(m_);
      work_.FillJacobian(m_, x_);
    }
    work_.MultiplyJacobianTransposed(work_.phi,
                                     &work_.grad);  // grad psi = J' Phi (eq. 24)
    return true;
  }

  // The same, written dense by the problem (internal::DenseMixedJacobian): no JE, JA, JB.
  bool EvaluateDenseJacobian(int k) {
    iterate_.jacobian_ok = dense_jacobian_->EvaluateDerivative(x_);
    if (!iterate_.jacobian_ok) return true;
    PhiPartials();
    if (!dense_jacobian_->Fill(work_.da, work_.db, x_, &work_.Jd, &work_.sensitivity)) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    work_.MultiplyJacobianTransposed(work_.phi,
                                     &work_.grad);  // grad psi = J' Phi (eq. 24)
    return true;
  }

  // da_j, db_j: the partials of phi at (A_j, B_j). Degenerate set gamma = {j : A_j = B_j
  // = 0} (eq. 13) and the z-vector rule: z_v = 1 at the variable of every degenerate pair
  // (DFK 1996, eq. 27; thesis 3.1).
  void PhiPartials() {
    iterate_.degenerate_count = 0;
    const bool fb_family = function_ != NcpFunction::kMin;
    auto degenerate = [&](int j) {
      return internal::InDegenerateSet(function_, options_.degenerate_tolerance,
                                       work_.A(j), work_.B(j));
    };
    if (fb_family) {
      work_.z.setZero();
      for (int j = 0; j < p_; ++j) {
        if (!degenerate(j)) continue;
        work_.z(problem_.PairVariable(j)) = 1.0;
        ++iterate_.degenerate_count;
      }
      if (iterate_.degenerate_count > 0 && dense_jacobian_) {
        dense_jacobian_->MultiplyPairJacobians(work_.z, &work_.za, &work_.zb);
      } else if (iterate_.degenerate_count > 0) {
        work_.za.noalias() = work_.JA * work_.z;
        work_.zb.noalias() = work_.JB * work_.z;
      }
    }
    for (int j = 0; j < p_; ++j) {
      const bool gamma = degenerate(j);
      const internal::PhiPartials dp = internal::PhiDerivatives(
          function_, options_.penalized_fb_lambda, work_.A(j), work_.B(j), gamma,
          gamma ? work_.za(j) : 0.0, gamma ? work_.zb(j) : 0.0, options_.min_tie_takes_b);
      work_.da(j) = dp.da;
      work_.db(j) = dp.db;
    }
  }

  // ---- the round-off floor of the test (Options::roundoff_ulps) ----------------------
  // Moving x to a neighbouring double (x_j (1 + delta_j), |delta_j| <= eps) changes row i
  // of Phi by up to eps r_i with r = |J_E||x| for equations and |da| |J_A||x| + |db|
  // |J_B||x| for pairs (to first order; J_E, J_A, J_B weighted like the rows). No x
  // closer to the solution is representable below that, so a row within tolerance +
  // roundoff_ulps eps r_i is as converged as double precision allows. Needs J at x^k
  // (EvaluateJacobian). (r = Workspace::sensitivity, summed while J was filled: no extra
  // pass over J.)
  bool WithinRoundoffFloor() {
    if (options_.roundoff_ulps == 0.0) return false;
    for (int i = 0; i < n_; ++i)
      if (!internal::RowWithinRoundoffFloor(work_.phi(i), threshold_,
                                            options_.roundoff_ulps, work_.sensitivity(i)))
        return false;
    return true;
  }

  // ---- trace, log, callback for iterate k; false when the callback stopped ----------
  bool Report(int k) {
    record_.iteration = k;
    record_.phi_inf = iterate_.phi_inf;
    record_.psi = iterate_.psi;
    record_.grad_psi_inf = iterate_.have_jacobian && iterate_.jacobian_ok
                               ? work_.grad.lpNorm<Eigen::Infinity>()
                               : 0.0;
    record_.degenerate_pairs = iterate_.degenerate_count;
    const bool reported =
        options_.keep_trace || options_.log_to_stderr || options_.callback;
    record_.time_s = reported ? Seconds(start_)
                              : 0.0;  // (a clock read costs ~1% of a small iteration)
    if (options_.keep_trace) summary_.trace.push_back(record_);
    if (options_.log_to_stderr)
      std::fprintf(stderr, "%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n", k,
                   iterate_.phi_inf, iterate_.psi, record_.grad_psi_inf,
                   record_.step_length, record_.backtracks,
                   record_.gradient_step       ? "grad"
                   : record_.regularized_step  ? "reg"
                   : record_.minimum_norm_step ? "mnrm"
                                               : "newt",
                   iterate_.degenerate_count);
    if (options_.callback && !options_.callback(record_)) {
      Finish(
          TerminationType::kUserAbort,
          "the iteration callback stopped the solve at iteration " + std::to_string(k));
      return false;
    }
    return true;
  }

  // ---- step 1 and the safeguards; true when the solve ends here ----------------------
  bool TestStop(int k) {
    if (iterate_.converged) {
      summary_.roundoff_limited = iterate_.roundoff_limited;
      Finish(TerminationType::kConverged,
             internal::ConvergedMessage(options_, work_.weighted,
                                        iterate_.roundoff_limited, iterate_.phi_inf, k));
      return true;
    }
    if (k >= options_.max_iterations) {
      Finish(TerminationType::kMaxIterations,
             internal::MaxIterationsMessage(options_, iterate_.phi_inf));
      return true;
    }
    if (OutOfTime("at iteration ", k)) return true;
    if (!iterate_.jacobian_ok) {
      Finish(TerminationType::kEvaluationFailure,
             "MixedProblem::Jacobian returned false at iteration " + std::to_string(k));
      return true;
    }
    iterate_.grad_inf = work_.grad.lpNorm<Eigen::Infinity>();
    return Stagnated(k) || StationaryPoint();
  }

  // Options::max_seconds passed? (no allocation unless it did: checked every trial)
  bool OutOfTime(const char* where, int k) {
    if (!std::isfinite(options_.max_seconds) || !(Seconds(start_) > options_.max_seconds))
      return false;
    Finish(TerminationType::kTimeLimit,
           internal::TimeLimitMessage(options_, where, k, iterate_.phi_inf));
    return true;
  }

  // The stagnation test of globalization.hpp (Options::stagnation_window).
  bool Stagnated(int k) {
    if (!work_.stagnation.Stagnated(static_cast<size_t>(k - first_k_), iterate_.psi,
                                    options_))
      return false;
    Finish(TerminationType::kStationaryPoint,
           internal::StagnationMessage(options_, iterate_.phi_inf, iterate_.grad_inf));
    return true;
  }

  bool StationaryPoint() {
    if (iterate_.grad_inf != 0.0) return false;
    Finish(TerminationType::kStationaryPoint,
           internal::ZeroGradientMessage(iterate_.phi_inf));
    return true;
  }

  // ---- step 2: the direction d and its slope grad psi' d --------------------------
  // Newton J d = -Phi (eq. 21) kept if it passes the descent test (eq. 22); a singular J:
  // the rank-revealing least-squares step (Options::minimum_norm_step) if it passes the
  // test; else, with Options::regularized_direction, the Levenberg-Marquardt direction;
  // else -grad psi.
  Direction ChooseDirection(int k) {
    const bool newton_solved = NewtonDirection(k);
    if (finished_) return Direction::kNewton;
    if (newton_solved && PassesDescentTest()) return Direction::kNewton;
    if (newton_solved)
      ++summary_.descent_test_failures;
    else
      ++summary_.linear_solver_failures;
    if (!newton_solved && options_.minimum_norm_step && MinimumNormDirection() &&
        PassesDescentTest()) {
      ++summary_.minimum_norm_steps;
      return Direction::kMinimumNorm;
    }
    if (!options_.gradient_fallback) {
      if (!newton_solved)
        Finish(TerminationType::kLinearSolverFailure,
               std::string("the Newton system is singular or the ") +
                   ToString(resolved_) + " solve failed at iteration " +
                   std::to_string(k) + " and gradient_fallback is off");
      return Direction::kNewton;  // Algorithm 1 without step 2's fallback
    }
    if (regularized_ && RegularizedDirection() && PassesDescentTest()) {
      ++summary_.regularized_steps;
      return Direction::kRegularized;
    }
    work_.d = -work_.grad;
    iterate_.slope = -work_.grad.squaredNorm();
    ++summary_.gradient_steps;
    return Direction::kGradient;
  }

  // ChooseDirection, its time added to Summary::linear_solver_time_s: two clock reads
  // per iteration, the only ones of an iteration (the rest of the iterations' time is
  // Summary::evaluation_time_s, computed in Finish).
  Direction TimedChooseDirection(int k) {
    const Clock::time_point t0 = Clock::now();
    const Direction direction = ChooseDirection(k);
    summary_.linear_solver_time_s += Seconds(t0);
    return direction;
  }

  // grad psi' d <= -rho ||d||^p (eq. 22); sets the slope.
  bool PassesDescentTest() {
    iterate_.slope = work_.grad.dot(work_.d);
    return internal::PassesDescentTest(iterate_.slope, work_.d.norm(), options_);
  }

  // J d = -Phi (eq. 21). A factorization predicted to take longer than the time left is
  // not started (the solve ends with kTimeLimit). false when singular or failed.
  bool NewtonDirection(int k) {
    work_.newton_rhs = -work_.phi;
    return FactorizeJacobian(k) && SolveFactorized(work_.newton_rhs, &work_.d) &&
           AllFinite(work_.d) && SolvesNewtonSystem();
  }

  // The backward-error guard of globalization.hpp: whether work_.d solves J d = -Phi as
  // accurately as a backward-stable solve would.
  bool SolvesNewtonSystem() {
    const double terms_inf = work_.ResidualAndTerms(
        work_.d, work_.phi, &work_.newton_residual, &work_.newton_terms);
    return internal::NewtonSolutionAccurate(
        work_.newton_residual.lpNorm<Eigen::Infinity>(), iterate_.phi_inf, terms_inf);
  }

  // Symbolic analysis (sparse backends), the time check, the numeric factorization of J.
  // Dense: an LU that calls J singular is tried again on J equilibrated when J's rows or
  // columns spread over more than 2^20 (Options::scale_newton_system; nothing is computed
  // for the scaling while the LU of J succeeds).
  bool FactorizeJacobian(int k) {
    if (work_.dense) {
      const double flops = internal::DenseLU::PredictedFlops(n_);
      if (!FactorizationFits(flops, internal::DenseLU::kTypicalFlopRate, k)) return false;
      work_.equilibrated = false;
      if (TimedFactorize(flops, [&] { return work_.dense_lu.Factorize(work_.Jd); }))
        return true;
      if (!options_.scale_newton_system || !work_.equilibration.Compute(work_.Jd))
        return false;
      work_.equilibrated = true;
      work_.equilibration.Scale(work_.Jd, &work_.Js);
      ++summary_.equilibrated_factorizations;
      return TimedFactorize(flops, [&] { return work_.dense_lu.Factorize(work_.Js); });
    }
    internal::LinearSolver& solver = *work_.linear_solver;
    if (!solver.Analyze(work_.J, iterate_.pattern_changed)) return false;
    const double flops = solver.PredictedFactorizationFlops();
    return FactorizationFits(flops, solver.TypicalFlopRate(), k) &&
           TimedFactorize(flops, [&] { return solver.Factorize(work_.J); });
  }

  // x = J^-1 rhs with the factorization of FactorizeJacobian (equilibrated: x = diag(c)
  // Js^-1 diag(r) rhs).
  bool SolveFactorized(const Vector& rhs, Vector* x) {
    if (!work_.dense) return work_.linear_solver->Solve(rhs, x);
    if (!work_.equilibrated) {
      work_.dense_lu.Solve(rhs, x);
      return true;
    }
    work_.scaled_rhs = work_.equilibration.row().cwiseProduct(rhs);
    work_.dense_lu.Solve(work_.scaled_rhs, x);
    x->array() *= work_.equilibration.column().array();
    return true;
  }

  // The least-squares step d = argmin ||J d + Phi|| of a rank-revealing factorization
  // (internal::RankRevealingSolver: minimum norm when dense), kept when it solves J d =
  // -Phi to the backward error asked of an LU solve: a singular but consistent Newton
  // system. (Taken on inconsistent systems too, the least-squares step lost 3 runs of the
  // collection, colvdual and vonthmcp; docs/ncp.md.) false when it failed or does not
  // solve the system.
  bool MinimumNormDirection() {
    work_.newton_rhs = -work_.phi;
    const bool solved =
        work_.dense ? work_.rank_revealing.Solve(work_.Jd, work_.newton_rhs, &work_.d)
                    : work_.rank_revealing.Solve(work_.J, work_.newton_rhs, &work_.d);
    return solved && SolvesNewtonSystem();
  }

  int SymbolicFactorizations() const {
    return work_.dense ? 0 : work_.linear_solver->symbolic_factorizations();
  }
  // Cholesky fallbacks of the Newton and the regularized (J'J + mu I) solver.
  int Fallbacks() const {
    if (work_.dense) return 0;
    return work_.linear_solver->fallbacks() +
           (work_.regularized_solver ? work_.regularized_solver->fallbacks() : 0);
  }

  // Predicted time of the numeric factorization = flops / rate (Options::max_seconds,
  // factorization_flop_rate; typical_rate: the backend's before one was timed); false
  // (and the solve finished) when it exceeds the time left.
  bool FactorizationFits(double flops, double typical_rate, int k) {
    summary_.predicted_factorization_flops = flops;
    const double rate = work_.measured_flop_rate > 0.0 ? work_.measured_flop_rate
                        : options_.factorization_flop_rate > 0.0
                            ? options_.factorization_flop_rate
                            : typical_rate;
    const double left = options_.max_seconds - Seconds(start_);
    if (!std::isfinite(options_.max_seconds) || !(flops / rate > left)) return true;
    Finish(TerminationType::kTimeLimit,
           "the factorization at iteration " + std::to_string(k) + " was not started: " +
               FormatNumber("%.3g", flops) + " flops at " + FormatNumber("%.3g", rate) +
               " flop/s predict " + FormatNumber("%.3g", flops / rate) +
               " s, more than the " + FormatNumber("%.3g", left) +
               " s left of max_seconds = " + FormatNumber("%.3g", options_.max_seconds) +
               " s (||Phi||_inf = " + FormatNumber("%.3e", iterate_.phi_inf) + ")");
    return false;
  }

  // factorize() returns false when singular. The measured rate (flops / seconds) only
  // serves FactorizationFits: timed under a finite max_seconds.
  template <class Factorize>
  bool TimedFactorize(double flops, Factorize&& factorize) {
    if (!std::isfinite(options_.max_seconds)) return factorize();
    const auto t0 = Clock::now();
    const bool ok = factorize();
    const double seconds = Seconds(t0);
    if (std::isfinite(flops) && flops > 0.0 && seconds > 0.0)
      work_.measured_flop_rate = flops / seconds;
    return ok;
  }

  // Levenberg-Marquardt direction (J'J + mu I) d = -J' Phi with mu = ||Phi||_2 (Fan and
  // Yuan 2005; the proximal perturbation of Munson et al. 2001, sec. 3): a descent
  // direction of psi whenever grad psi != 0, between Newton (mu -> 0) and -grad psi / mu.
  bool RegularizedDirection() {
    const double mu = std::sqrt(2.0 * iterate_.psi);
    if (!work_.regularized_solver)
      work_.regularized_solver = internal::MakeLinearSolver(resolved_);
    if (work_.identity.rows() != n_) {
      work_.identity.resize(n_, n_);
      work_.identity.setIdentity();
    }
    if (work_.dense)
      work_.J = work_.Jd.sparseView();  // (the option's sparse form; off by default)
    work_.normal_matrix = SparseMatrix(work_.J.transpose()) * work_.J;
    work_.normal_matrix += mu * work_.identity;
    work_.normal_matrix.makeCompressed();
    // The pattern of J'J + mu I follows J's; analysed again whenever J's changed.
    const bool changed = iterate_.pattern_changed || !work_.regularized_analyzed ||
                         work_.normal_matrix.nonZeros() != work_.regularized_nonzeros;
    work_.regularized_nonzeros = work_.normal_matrix.nonZeros();
    work_.newton_rhs = -work_.grad;
    work_.regularized_analyzed =
        work_.regularized_solver->Analyze(work_.normal_matrix, changed);
    internal::LinearSolver& solver = *work_.regularized_solver;
    return work_.regularized_analyzed &&
           TimedFactorize(solver.PredictedFactorizationFlops(),
                          [&] { return solver.Factorize(work_.normal_matrix); }) &&
           work_.regularized_solver->Solve(work_.newton_rhs, &work_.d) &&
           AllFinite(work_.d);
  }

  // ---- step 3: Armijo line search on psi with steps 2^-i
  // ------------------------------- Monotone (nonmonotone_memory = 1, eq. 23) or
  // nonmonotone; the rules are internal::ArmijoLineSearch's (globalization.hpp), this
  // supplies the trial points.
  bool LineSearch(int k, Direction direction) {
    const double reference =
        work_.armijo_reference.Update(static_cast<size_t>(k - first_k_), iterate_.psi);
    const internal::LineSearchResult r = internal::ArmijoLineSearch(
        options_, reference, iterate_.slope,
        [&] { return OutOfTime("in the line search of iteration ", k); },
        [&](double t) {
          work_.x_trial = x_ + t * work_.d;
          // (Component by component: a test t ||d||_inf <= eps ||x||_inf stopped the 2D
          // obstacle at 10^6 unknowns, whose last corrections, ~1e-15 on gaps of 5e-7,
          // are far below eps max|w| ~ 8e-16 x 3.5.)
          if (work_.x_trial == x_)
            return internal::LineSearchTrial{internal::LineSearchTrial::kUnchanged, 0.0};
          if (!Evaluate(work_.x_trial, &work_.Et, &work_.At, &work_.Bt, &work_.phi_trial))
            return internal::LineSearchTrial{internal::LineSearchTrial::kNotEvaluable,
                                             0.0};
          if (!AllFinite(work_.phi_trial))
            return internal::LineSearchTrial{internal::LineSearchTrial::kNonFinite, 0.0};
          return internal::LineSearchTrial{internal::LineSearchTrial::kEvaluated,
                                           0.5 * work_.phi_trial.squaredNorm()};
        });
    if (r.out_of_time) {
      summary_.backtracks += r.backtracks;
      return false;
    }
    summary_.backtracks += std::min(r.backtracks, options_.max_backtracks);
    iterate_.step = r.step;
    iterate_.backtracks = r.backtracks;
    if (!r.accepted) {
      const char* name = direction == Direction::kGradient      ? "gradient"
                         : direction == Direction::kRegularized ? "regularized"
                         : direction == Direction::kMinimumNorm ? "minimum-norm"
                                                                : "Newton";
      const internal::Ending ending = internal::LineSearchFailure(
          options_, r, name, k, iterate_.phi_inf, iterate_.grad_inf);
      Finish(ending.termination, ending.message);
    }
    return r.accepted;
  }

  // ---- restart strategy (Options::merit_restarts) -----------------------------------
  // An FB-family solve that ended at a non-solution stationary point of psi or in a
  // failed line search continues with the other member of the family from the problem's
  // restart point (MixedProblem::RestartPoint: x^k itself, or for a box MCP x^k projected
  // onto the box): Phi, psi, the nonmonotone memory and the stagnation window start
  // afresh.
  bool Restart(int k) {
    if (!internal::MeritRestartApplies(summary_.termination, restarts_left_, function_))
      return false;
    // The restart point and its Phi go to the trial buffers, so that a failed restart
    // leaves x^k, Phi(x^k) and the merit function of the finished solve untouched.
    const NcpFunction stuck_function = function_;
    function_ = internal::OtherMeritFunction(function_);
    work_.x_trial = x_;
    if (!problem_.RestartPoint(&work_.x_trial) || work_.x_trial.size() != n_ ||
        !Evaluate(work_.x_trial, &work_.Et, &work_.At, &work_.Bt, &work_.phi_trial) ||
        !AllFinite(work_.phi_trial)) {
      function_ = stuck_function;
      return false;
    }
    x_.swap(work_.x_trial);
    work_.E.swap(work_.Et);
    work_.A.swap(work_.At);
    work_.B.swap(work_.Bt);
    work_.phi.swap(work_.phi_trial);
    --restarts_left_;
    ++summary_.merit_restarts;
    if (options_.keep_trace && !summary_.trace.empty())
      summary_.trace.pop_back();  // iterate k is reported anew
    finished_ = false;
    summary_.termination = TerminationType::kNotSolved;
    first_k_ = k;
    if (options_.log_to_stderr)
      std::fprintf(stderr, "restart %d at iteration %d with %s\n",
                   summary_.merit_restarts, k, ToString(function_));
    return true;
  }

  // ---- the hybrid default (Options::hybrid, strategy.hpp) ---------------------------
  // Records iterate k; true when the strategy was left for slow progress or its budget
  // and the next one continues from its best point.
  bool LeaveStrategy(int k) {
    if (!options_.hybrid) return false;
    const size_t kk = static_cast<size_t>(k - first_k_);
    work_.progress.Observe(kk, iterate_.psi, x_, k);
    SwitchReason reason = SwitchReason::kStuck;
    return work_.progress.ShouldLeave(kk, k - strategy_start_, options_, &reason) &&
           SwitchStrategy(k, reason);
  }

  // The next strategy of the schedule continues from the smallest-psi point of this one
  // (its MixedProblem::RestartPoint), at iterate k; Phi, psi, the nonmonotone memory, the
  // stagnation window and the progress test start afresh. kStuck applies to a solve that
  // ended at a non-solution stationary point, in a failed line search or a failed Newton
  // solve; false (nothing changed) when no strategy is left or the point cannot be
  // evaluated.
  bool SwitchStrategy(int k, SwitchReason reason) {
    if (!options_.hybrid) return false;
    const bool stuck = summary_.termination == TerminationType::kStationaryPoint ||
                       summary_.termination == TerminationType::kLineSearchFailure ||
                       summary_.termination == TerminationType::kLinearSolverFailure;
    if (reason == SwitchReason::kStuck && !(finished_ && stuck)) return false;
    const Strategy from{function_, regularized_};
    if (!work_.schedule.Advance(from)) return false;
    const Strategy& to = work_.schedule.current();
    // A stuck strategy may not have recorded iterate k (TestStop came first).
    work_.progress.Observe(static_cast<size_t>(k - first_k_), iterate_.psi, x_, k);
    work_.x_trial = work_.progress.best_x();
    function_ = to.ncp_function;  // Evaluate() uses function_
    if (!problem_.RestartPoint(&work_.x_trial) || work_.x_trial.size() != n_ ||
        !Evaluate(work_.x_trial, &work_.Et, &work_.At, &work_.Bt, &work_.phi_trial) ||
        !AllFinite(work_.phi_trial)) {
      function_ = from.ncp_function;
      return false;
    }
    summary_.strategy_switches.push_back(
        work_.progress.SwitchRecord(k, from, to, reason));
    x_.swap(work_.x_trial);
    work_.E.swap(work_.Et);
    work_.A.swap(work_.At);
    work_.B.swap(work_.Bt);
    work_.phi.swap(work_.phi_trial);
    regularized_ = to.regularized_direction;
    if (options_.keep_trace && !summary_.trace.empty())
      summary_.trace.pop_back();  // iterate k anew
    finished_ = false;
    summary_.termination = TerminationType::kNotSolved;
    first_k_ = strategy_start_ = k;
    if (options_.log_to_stderr)
      std::fprintf(stderr, "strategy %s -> %s at iteration %d (%s), from iteration %d\n",
                   internal::StrategyName(from).c_str(),
                   internal::StrategyName(to).c_str(), k, ToString(reason),
                   work_.progress.best_iteration());
    return true;
  }

  // ---- step 4: x^{k+1} = x^k + t d ---------------------------------------------------
  void Accept(Direction direction) {
    x_.swap(work_.x_trial);
    work_.E.swap(work_.Et);
    work_.A.swap(work_.At);
    work_.B.swap(work_.Bt);
    work_.phi.swap(work_.phi_trial);
    ++summary_.iterations;
    record_.step_length = iterate_.step;
    record_.direction_norm = work_.d.norm();
    record_.backtracks = iterate_.backtracks;
    record_.gradient_step = direction == Direction::kGradient;
    record_.regularized_step = direction == Direction::kRegularized;
    record_.minimum_norm_step = direction == Direction::kMinimumNorm;
  }

  void Finish(TerminationType type, const std::string& message) {
    finished_ = true;
    summary_.termination = type;
    summary_.message = message;
    if (summary_.merit_restarts > 0)
      summary_.message += internal::RestartSuffix(summary_.merit_restarts);
    summary_.message += internal::StrategySwitchSuffix(summary_.strategy_switches);
    summary_.final_phi_inf = work_.phi.lpNorm<Eigen::Infinity>();
    summary_.final_psi = 0.5 * work_.phi.squaredNorm();
    summary_.symbolic_factorizations = SymbolicFactorizations() - symbolic_before_;
    summary_.cholesky_fallbacks = Fallbacks() - fallbacks_before_;
    // One clock read: the rest of the time outside the direction's linear algebra
    // (timed by TimedChooseDirection) is the evaluations' and the iterations' own work.
    summary_.total_time_s = Seconds(start_);
    summary_.evaluation_time_s =
        std::max(0.0, summary_.total_time_s - summary_.linear_solver_time_s);
  }

  const Options& options_;
  Workspace& work_;
  MixedProblem& problem_;
  internal::DenseMixedJacobian* const offered_dense_jacobian_;
  internal::DenseMixedJacobian* dense_jacobian_ = nullptr;  // used in this solve
  Vector& x_;
  Summary& summary_;
  const int n_, m_, p_;
  Clock::time_point start_;
  LinearSolverType resolved_ = LinearSolverType::kAuto;
  int symbolic_before_ = 0;
  int fallbacks_before_ = 0;
  double threshold_ = 0.0;
  NcpFunction function_ =
      NcpFunction::kFischerBurmeister;   // the current merit (restarts switch it)
  int restarts_left_ = 0, first_k_ = 0;  // first_k_: iterate of the last (re)start
  bool regularized_ =
      false;  // the current strategy tries the LM direction (hybrid switches it)
  int strategy_start_ = 0;  // iterate the current strategy of the hybrid began at
  IterationRecord record_;
  bool finished_ = false;  // Finish was called (a restart clears it)
  // Iterate k: what the phases of one iteration find out about x^k, set afresh by
  // BeginIterate.
  struct Iterate {
    double phi_inf = 0.0, psi = 0.0;  // ||Phi(x^k)||_inf, psi(x^k) = 1/2 ||Phi(x^k)||_2^2
    bool converged = false;  // phi_inf <= threshold_, or within the round-off floor
    bool roundoff_limited =
        false;  // converged by the round-off floor, not by the tolerance
    bool have_jacobian =
        false;  // J^k is to be evaluated (not converged, k < max_iterations)
    bool jacobian_ok = true;       // MixedProblem::Jacobian succeeded at x^k
    bool pattern_changed = false;  // J^k's sparsity pattern differs from J^(k-1)'s
    int degenerate_count = 0;      // |gamma|, pairs in the degenerate set (eq. 13)
    double grad_inf = 0.0;         // ||grad psi(x^k)||_inf
    double slope = 0.0;            // grad psi' d of the chosen direction
    double step = 0.0;             // the accepted step 2^-i ...
    int backtracks = 0;            // ... and its i
  } iterate_;
};

void Solver::Solve(MixedProblem& problem, Vector* x_ptr, Summary* summary_ptr) {
  if (x_ptr == nullptr || summary_ptr == nullptr)
    throw std::invalid_argument("ncp::Solver::Solve: x and summary must not be null");
  CheckProblem(problem, *x_ptr);
  const ScopedBlasThreads blas_threads(options_.blas_threads);
  Iteration(options_, *workspace_, problem, nullptr, *x_ptr, *summary_ptr).Run();
}

void Solver::Solve(SquareFunction& F, const Vector& lower, const Vector& upper, Vector* x,
                   Summary* summary) {
  if (x == nullptr || summary == nullptr)
    throw std::invalid_argument("ncp::Solver::Solve: x and summary must not be null");
  // The box MCP as a mixed problem (box_mcp.hpp), solved like any other.
  const ScopedBlasThreads blas_threads(options_.blas_threads);
  internal::BoxMcpSolve box_mcp(options_, &workspace_->box_mcp, F, lower, upper, x);
  if (box_mcp.ready()) {
    CheckProblem(box_mcp.problem(), box_mcp.unknowns());
    Iteration(options_, *workspace_, box_mcp.problem(), &box_mcp.dense_jacobian(),
              box_mcp.unknowns(), *summary)
        .Run();
  }
  box_mcp.Finish(summary);
}

void Solver::SolveNcp(SquareFunction& F, Vector* x, Summary* summary) {
  const int n = F.NumVariables();
  Solve(F, Vector::Zero(n), Vector::Constant(n, std::numeric_limits<double>::infinity()),
        x, summary);
}

void Solver::set_options(const Options& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("ncp::Solver: " + error);
  options_ = options;
}

namespace {

// The one-shot calls of small problems (n <= kPooledMaxVariables) borrow a Solver kept
// per thread, so that only the first call builds the workspace (~110 allocations, a few
// us: half the time of a small solve); everything a solve depends on is re-derived in
// Start() or checked (backend, box-MCP bounds, Jacobian pattern), so a borrowed workspace
// gives the same iterates as a fresh one. A call made while the thread's Solver is busy
// (from inside F) or for a larger problem, whose workspace should not outlive the call,
// gets a fresh Solver.
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
  if (pool.solver)
    pool.solver->set_options(options);
  else
    pool.solver = std::make_unique<Solver>(options);
  struct Borrow {  // released on return and on an exception
    bool& busy;
    explicit Borrow(bool& b) : busy(b) { busy = true; }
    ~Borrow() { busy = false; }
  } borrow(pool.busy);
  call(*pool.solver);
}

}  // namespace

void Solve(const Options& options, MixedProblem& problem, Vector* x, Summary* summary) {
  SolveOnce(options, problem.NumVariables(),
            [&](Solver& s) { s.Solve(problem, x, summary); });
}

void Solve(const Options& options, SquareFunction& F, const Vector& lower,
           const Vector& upper, Vector* x, Summary* summary) {
  SolveOnce(options, F.NumVariables(),
            [&](Solver& s) { s.Solve(F, lower, upper, x, summary); });
}

void SolveNcp(const Options& options, SquareFunction& F, Vector* x, Summary* summary) {
  SolveOnce(options, F.NumVariables(), [&](Solver& s) { s.SolveNcp(F, x, summary); });
}

}  // namespace ncp
