// Algorithm 1 of the thesis (section 3.1), the globalized semismooth Newton method of
// De Luca, Facchinei and Kanzow (1996), written once for every back end. The loop and
// every decision (stopping tests, the choice of direction, the Armijo line search, merit
// restarts, the hybrid's strategy switches) live here; a back end (the serial
// ncp::Solver::Iteration on Eigen, ncp::petsc::Iteration on distributed PETSc Vec/Mat)
// derives from SemismoothNewton<Backend> and supplies the vector and matrix work:
//
//   Start()                                 sizes, Phi(x^0); false when the solve ended
//   ResidualNorms()                         {||Phi(x^k)||_inf, psi(x^k)}
//   EvaluateJacobian(k)                     J^k, grad psi = J' Phi (eq. 24); false: ended
//   GradientNormAndRoundoffFloor()          sets iterate_.grad_inf; every row within the
//                                           round-off floor (Options::roundoff_ulps)?
//   NewtonDirection(k), MinimumNormDirection(), RegularizedDirection(),
//   GradientDirection()                     d of step 2 (the last sets iterate_.slope)
//   SlopeAndDirectionNorm()                 {grad psi' d, ||d||_2}
//   TimedDirection(choose)                  choose(), timed as the back end times it
//   TrialStep(t)                            x^k + t d evaluated: a LineSearchTrial
//   CopyCurrentToTrial(), CopyBestToTrial() restart points into the trial buffers
//   EvaluateRestartTrial()                  RestartPoint, Phi there; false: not usable
//   AcceptTrialPoint()                      x <- the trial point with its Phi
//   ObserveProgress(kk, k)                  psi(x^k) to the hybrid's progress record
//   DirectionNorm()                         ||d||_2 of the accepted step
//   TimeLimitPassed()                       Options::max_seconds passed (every rank)
//   OnAnyRank(b)                            b on some rank (serial: b)
//   Progress()                              the hybrid's StrategyProgress
//   Print(format, ...)                      a log line to stderr (once)
//   CompleteSummary()                       final residuals and counters at the end
//   NewtonSolveName(), JacobianFailure()    words of the messages
//   LineSearchScope                         a type constructed around the line search
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "globalization.hpp"
#include "ncp/solver.hpp"
#include "strategy.hpp"

namespace ncp::internal {

/// The direction d of step 2 that the line search of iteration k searched along.
enum class Direction { kNewton, kMinimumNorm, kRegularized, kGradient };

inline const char* DirectionName(Direction direction) {
  return direction == Direction::kGradient      ? "gradient"
         : direction == Direction::kRegularized ? "regularized"
         : direction == Direction::kMinimumNorm ? "minimum-norm"
                                                : "Newton";
}

/// What the phases of one iteration find out about x^k, set afresh by BeginIterate.
struct IterateState {
  double phi_inf = 0.0, psi = 0.0;  // ||Phi(x^k)||_inf, psi(x^k) = 1/2 ||Phi(x^k)||_2^2
  bool converged = false;           // phi_inf <= tolerance, or within the round-off floor
  bool roundoff_limited = false;    // converged by the round-off floor, not the tolerance
  bool have_jacobian = false;       // J^k is to be evaluated (not converged, k < max)
  bool jacobian_ok = true;          // the problem's Jacobian succeeded at x^k
  bool pattern_changed = false;     // J^k's sparsity pattern differs from J^(k-1)'s
  int degenerate_count = 0;         // |gamma|, pairs in the degenerate set (eq. 13)
  double grad_inf = 0.0;            // ||grad psi(x^k)||_inf
  double slope = 0.0;               // grad psi' d of the chosen direction
  double step = 0.0;                // the accepted step 2^-i ...
  int backtracks = 0;               // ... and its i
};

template <class Backend>
class SemismoothNewton {
 public:
  /// The solve, phase by phase (the layout follows Ceres' LineSearchMinimizer).
  void Run() {
    if (!backend().Start()) return;
    for (int k = 0;;) {
      BeginIterate(k);
      if (iterate_.have_jacobian && !backend().EvaluateJacobian(k)) return;
      if (iterate_.have_jacobian && iterate_.jacobian_ok)
        iterate_.converged = iterate_.roundoff_limited =
            backend().GradientNormAndRoundoffFloor();
      if (!ReportIterate(k)) return;
      if (FinishIfStopTestMet(k)) {
        if (ContinueAfterFailure(k)) continue;
        return;
      }
      if (LeaveStrategy(k)) continue;
      const Direction direction =
          backend().TimedDirection([&] { return ChooseDirection(k); });
      if (finished_) {
        if (SwitchStrategy(k, SwitchReason::kStuck)) continue;
        return;
      }
      if (!LineSearch(k, direction)) {
        if (ContinueAfterFailure(k)) continue;
        return;
      }
      AcceptStep(direction);
      ++k;
    }
  }

 protected:
  using Clock = std::chrono::steady_clock;

  SemismoothNewton(const Options& options, Summary& summary,
                   NonmonotoneReference& armijo_reference, StagnationTest& stagnation,
                   StrategySchedule& schedule)
      : options_(options),
        summary_(summary),
        armijo_reference_(armijo_reference),
        stagnation_(stagnation),
        schedule_(schedule) {}

  static double Seconds(Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  }

  // ---- called by the back end's Start() ---------------------------------------------
  // The Summary of a new solve of n unknowns, m of them equations: every counter 0.
  void StartSummary(int n, int m) {
    summary_ = Summary();
    summary_.num_variables = n;
    summary_.num_equations = m;
    summary_.num_pairs = n - m;
    summary_.ncp_function = options_.ncp_function;
    summary_.iterations = summary_.jacobian_evaluations = summary_.residual_evaluations =
        0;
    summary_.gradient_steps = summary_.regularized_steps = summary_.merit_restarts = 0;
    summary_.minimum_norm_steps = summary_.equilibrated_factorizations = 0;
    summary_.linear_solver_failures = summary_.descent_test_failures =
        summary_.backtracks = 0;
    summary_.cholesky_fallbacks = 0;
    summary_.projected_start_components = summary_.projected_final_components = 0;
    summary_.evaluation_time_s = summary_.linear_solver_time_s = 0.0;
  }

  // The merit function, restarts and strategy of a new solve (before Phi(x^0)).
  void ResetStrategies() {
    function_ = options_.ncp_function;
    restarts_left_ = options_.merit_restarts;
    first_k_ = 0;
    regularized_ = options_.regularized_direction;
    strategy_start_ = 0;
    schedule_.Reset(options_);
  }

  // The nonmonotone memory, the stagnation window and the log's header (after Phi(x^0)).
  void ResetMemories() {
    stagnation_.Reset(options_.stagnation_window);
    armijo_reference_.Reset(options_.nonmonotone_memory);
    if (options_.log_to_stderr)
      backend().Print("%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter", "|Phi|_inf", "psi",
                      "|grad|_inf", "step", "bt", "dir", "|gam|");
  }

  // Ends the solve with `type`: the status, its message, the final residuals.
  void Finish(TerminationType type, const std::string& message) {
    finished_ = true;
    summary_.termination = type;
    summary_.message = message;
    if (summary_.merit_restarts > 0)
      summary_.message += RestartSuffix(summary_.merit_restarts);
    summary_.message += StrategySwitchSuffix(summary_.strategy_switches);
    backend().CompleteSummary();
  }

  // Options::max_seconds passed? Then the solve ends with kTimeLimit.
  bool FinishIfOutOfTime(const char* where, int k) {
    if (!std::isfinite(options_.max_seconds) || !backend().TimeLimitPassed())
      return false;
    Finish(TerminationType::kTimeLimit,
           TimeLimitMessage(options_, where, k, iterate_.phi_inf));
    return true;
  }

  const Options& options_;
  Summary& summary_;
  Clock::time_point start_;
  NcpFunction function_ = NcpFunction::kFischerBurmeister;  // current merit function
  bool regularized_ = false;  // the current strategy tries the LM direction
  bool finished_ = false;     // Finish was called (a restart clears it)
  IterateState iterate_;

 private:
  Backend& backend() { return static_cast<Backend&>(*this); }

  // ||Phi(x^k)||_inf and psi(x^k); the rest of iterate k reset in one assignment.
  void BeginIterate(int k) {
    iterate_ = IterateState();
    std::tie(iterate_.phi_inf, iterate_.psi) = backend().ResidualNorms();
    iterate_.converged = iterate_.phi_inf <= options_.tolerance;
    iterate_.have_jacobian = !iterate_.converged && k < options_.max_iterations;
  }

  // ---- trace, log, callback for iterate k; false when the callback stopped the solve
  bool ReportIterate(int k) {
    record_.iteration = k;
    record_.phi_inf = iterate_.phi_inf;
    record_.psi = iterate_.psi;
    record_.grad_psi_inf =
        iterate_.have_jacobian && iterate_.jacobian_ok ? iterate_.grad_inf : 0.0;
    record_.degenerate_pairs = iterate_.degenerate_count;
    const bool reported =
        options_.keep_trace || options_.log_to_stderr || options_.callback;
    record_.time_s = reported ? Seconds(start_) : 0.0;  // (a clock read: ~1% of a small
                                                        // iteration)
    if (options_.keep_trace) summary_.trace.push_back(record_);
    if (options_.log_to_stderr)
      backend().Print("%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n", k,
                      iterate_.phi_inf, iterate_.psi, record_.grad_psi_inf,
                      record_.step_length, record_.backtracks,
                      record_.gradient_step       ? "grad"
                      : record_.regularized_step  ? "reg"
                      : record_.minimum_norm_step ? "mnrm"
                                                  : "newt",
                      iterate_.degenerate_count);
    if (options_.callback && backend().OnAnyRank(!options_.callback(record_))) {
      Finish(
          TerminationType::kUserAbort,
          "the iteration callback stopped the solve at iteration " + std::to_string(k));
      return false;
    }
    return true;
  }

  // ---- step 1 and the safeguards: true when one of them ended the solve -------------
  bool FinishIfStopTestMet(int k) {
    if (iterate_.converged) {
      FinishConverged(k);
      return true;
    }
    if (k >= options_.max_iterations) {
      Finish(TerminationType::kMaxIterations,
             MaxIterationsMessage(options_, iterate_.phi_inf));
      return true;
    }
    if (FinishIfOutOfTime("at iteration ", k)) return true;
    if (!iterate_.jacobian_ok) {
      Finish(TerminationType::kEvaluationFailure,
             std::string(backend().JacobianFailure()) + " at iteration " +
                 std::to_string(k));
      return true;
    }
    return FinishIfStagnated(k) || FinishIfStationary();
  }

  // ||Phi||_inf <= tolerance: kConverged; every row within the round-off floor above it:
  // kAtRoundoffFloor.
  void FinishConverged(int k) {
    summary_.roundoff_limited = iterate_.roundoff_limited;
    Finish(iterate_.roundoff_limited ? TerminationType::kAtRoundoffFloor
                                     : TerminationType::kConverged,
           ConvergedMessage(options_, backend().WeightedResidual(),
                            iterate_.roundoff_limited, iterate_.phi_inf, k));
  }

  // The stagnation test of globalization.hpp (Options::stagnation_window).
  bool FinishIfStagnated(int k) {
    if (!stagnation_.Stagnated(static_cast<size_t>(k - first_k_), iterate_.psi, options_))
      return false;
    Finish(TerminationType::kStationaryPoint,
           StagnationMessage(options_, iterate_.phi_inf, iterate_.grad_inf));
    return true;
  }

  // grad psi(x^k) = 0 at a non-solution: a stationary point of the merit function.
  bool FinishIfStationary() {
    if (iterate_.grad_inf != 0.0) return false;
    Finish(TerminationType::kStationaryPoint, ZeroGradientMessage(iterate_.phi_inf));
    return true;
  }

  // ---- step 2: the direction d and its slope grad psi' d ----------------------------
  // Newton J d = -Phi (eq. 21) kept if it passes the descent test (eq. 22); a singular J:
  // the least-squares step (Options::minimum_norm_step) if it passes the test; else, with
  // Options::regularized_direction, the Levenberg-Marquardt direction; else -grad psi.
  Direction ChooseDirection(int k) {
    const bool newton_solved = backend().NewtonDirection(k);
    if (finished_) return Direction::kNewton;
    if (newton_solved && PassesDescentTest()) return Direction::kNewton;
    if (newton_solved)
      ++summary_.descent_test_failures;
    else
      ++summary_.linear_solver_failures;
    if (!newton_solved && options_.minimum_norm_step &&
        backend().MinimumNormDirection() && PassesDescentTest()) {
      ++summary_.minimum_norm_steps;
      return Direction::kMinimumNorm;
    }
    if (!options_.gradient_fallback) {
      if (!newton_solved)
        Finish(TerminationType::kLinearSolverFailure,
               "the Newton system is singular or the " + backend().NewtonSolveName() +
                   " failed at iteration " + std::to_string(k) +
                   " and gradient_fallback is off");
      return Direction::kNewton;  // Algorithm 1 without step 2's fallback
    }
    if (regularized_ && backend().RegularizedDirection() && PassesDescentTest()) {
      ++summary_.regularized_steps;
      return Direction::kRegularized;
    }
    backend().GradientDirection();
    ++summary_.gradient_steps;
    return Direction::kGradient;
  }

  // grad psi' d <= -rho ||d||^p (eq. 22); sets the slope.
  bool PassesDescentTest() {
    const auto [slope, norm] = backend().SlopeAndDirectionNorm();
    iterate_.slope = slope;
    return internal::PassesDescentTest(slope, norm, options_);
  }

  // ---- step 3: Armijo line search on psi with steps 2^-i, monotone (eq. 23) or
  // nonmonotone (internal::ArmijoLineSearch); false when it ended the solve.
  bool LineSearch(int k, Direction direction) {
    [[maybe_unused]] const typename Backend::LineSearchScope scope;
    const double reference =
        armijo_reference_.Update(static_cast<size_t>(k - first_k_), iterate_.psi);
    const LineSearchResult r = ArmijoLineSearch(
        options_, reference, iterate_.slope,
        [&] { return FinishIfOutOfTime("in the line search of iteration ", k); },
        [&](double t) { return backend().TrialStep(t); });
    if (r.out_of_time) {
      summary_.backtracks += r.backtracks;
      return false;
    }
    summary_.backtracks += std::min(r.backtracks, options_.max_backtracks);
    iterate_.step = r.step;
    iterate_.backtracks = r.backtracks;
    if (!r.accepted) {
      const Ending ending = LineSearchFailure(options_, r, DirectionName(direction), k,
                                              iterate_.phi_inf, iterate_.grad_inf);
      Finish(ending.termination, ending.message);
    }
    return r.accepted;
  }

  // ---- step 4: x^{k+1} = x^k + t d ---------------------------------------------------
  void AcceptStep(Direction direction) {
    backend().AcceptTrialPoint();
    ++summary_.iterations;
    record_.step_length = iterate_.step;
    record_.direction_norm = backend().DirectionNorm();
    record_.backtracks = iterate_.backtracks;
    record_.gradient_step = direction == Direction::kGradient;
    record_.regularized_step = direction == Direction::kRegularized;
    record_.minimum_norm_step = direction == Direction::kMinimumNorm;
  }

  // ---- the fallback of a stuck solve: a merit restart, else the hybrid's next strategy
  bool ContinueAfterFailure(int k) {
    return Restart(k) || SwitchStrategy(k, SwitchReason::kStuck);
  }

  // Restart (Options::merit_restarts): an FB-family solve that ended at a non-solution
  // stationary point of psi or in a failed line search continues with the other member
  // of the family from the problem's restart point (x^k, or x^k projected onto the box);
  // Phi, psi, the nonmonotone memory and the stagnation window start afresh. The restart
  // point goes to the trial buffers, so that a failed restart leaves x^k untouched.
  bool Restart(int k) {
    if (!MeritRestartApplies(summary_.termination, restarts_left_, function_))
      return false;
    const NcpFunction stuck_function = function_;
    function_ = OtherMeritFunction(function_);  // the evaluation uses function_
    backend().CopyCurrentToTrial();
    if (!backend().EvaluateRestartTrial()) {
      function_ = stuck_function;
      return false;
    }
    backend().AcceptTrialPoint();
    --restarts_left_;
    ++summary_.merit_restarts;
    ContinueFrom(k);
    if (options_.log_to_stderr)
      backend().Print("restart %d at iteration %d with %s\n", summary_.merit_restarts, k,
                      ToString(function_));
    return true;
  }

  // ---- the hybrid default (Options::hybrid, strategy.hpp) ---------------------------
  // Records iterate k; true when the strategy was left for slow progress or its budget
  // and the next one continues from its best point.
  bool LeaveStrategy(int k) {
    if (!options_.hybrid) return false;
    const auto kk = static_cast<size_t>(k - first_k_);
    backend().ObserveProgress(kk, k);
    SwitchReason reason = SwitchReason::kStuck;
    return backend().Progress().ShouldLeave(kk, k - strategy_start_, options_, &reason) &&
           SwitchStrategy(k, reason);
  }

  // The next strategy of the schedule continues from the smallest-psi point of this one
  // (its restart point), at iterate k. kStuck applies to a solve that ended at a
  // non-solution stationary point, in a failed line search or a failed Newton solve;
  // false (nothing changed) when no strategy is left or the point cannot be evaluated.
  bool SwitchStrategy(int k, SwitchReason reason) {
    if (!options_.hybrid) return false;
    const bool stuck = summary_.termination == TerminationType::kStationaryPoint ||
                       summary_.termination == TerminationType::kLineSearchFailure ||
                       summary_.termination == TerminationType::kLinearSolverFailure;
    if (reason == SwitchReason::kStuck && !(finished_ && stuck)) return false;
    const Strategy from{function_, regularized_};
    if (!schedule_.Advance(from)) return false;
    const Strategy& to = schedule_.current();
    // A stuck strategy may not have recorded iterate k (the stop test came first).
    backend().ObserveProgress(static_cast<size_t>(k - first_k_), k);
    backend().CopyBestToTrial();
    function_ = to.ncp_function;  // the evaluation uses function_
    if (!backend().EvaluateRestartTrial()) {
      function_ = from.ncp_function;
      return false;
    }
    summary_.strategy_switches.push_back(
        backend().Progress().SwitchRecord(k, from, to, reason));
    backend().AcceptTrialPoint();
    regularized_ = to.regularized_direction;
    ContinueFrom(k);
    strategy_start_ = k;
    if (options_.log_to_stderr)
      backend().Print("strategy %s -> %s at iteration %d (%s), from iteration %d\n",
                      StrategyName(from).c_str(), StrategyName(to).c_str(), k,
                      ToString(reason), backend().Progress().best_iteration());
    return true;
  }

  // After a restart or a switch: iterate k is reported anew, the solve is open again.
  void ContinueFrom(int k) {
    if (options_.keep_trace && !summary_.trace.empty()) summary_.trace.pop_back();
    finished_ = false;
    summary_.termination = TerminationType::kNotSolved;
    first_k_ = k;
  }

  NonmonotoneReference& armijo_reference_;
  StagnationTest& stagnation_;
  StrategySchedule& schedule_;
  int restarts_left_ = 0, first_k_ = 0;  // first_k_: iterate of the last (re)start
  int strategy_start_ = 0;               // iterate the current strategy began at
  IterationRecord record_;
};

}  // namespace ncp::internal
