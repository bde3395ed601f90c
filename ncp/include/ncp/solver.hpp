/// \file solver.hpp
/// Semismooth Newton method for complementarity problems: Algorithm 1 of the thesis
/// (section 3.1), i.e. the globalized method of De Luca, Facchinei and Kanzow (1996):
///
///   0. k = 0, start point x^0.
///   1. Stop if ||Phi(x^k)||_inf <= tolerance.
///   2. Take J^k in the B-subdifferential of Phi at x^k (z-vector rule, DFK eq. 27) and
///      solve J^k d = -Phi(x^k). If that fails, or the descent test
///          grad psi(x^k)' d <= -rho ||d||^p                                    (eq. 22)
///      fails, use d = -grad psi(x^k), where psi = 1/2 ||Phi||^2, grad psi = J' Phi.
///   3. Armijo: smallest i = 0, 1, ... with
///          psi(x^k + 2^-i d) <= psi(x^k) + beta 2^-i grad psi(x^k)' d          (eq. 23)
///   4. x^{k+1} = x^k + 2^-i d, k = k + 1, go to 1.
///
/// Options::Algorithm1() is exactly this. The defaults differ in step 3: psi(x^k) is
/// replaced by max psi over the last 3 iterates (nonmonotone, Grippo, Lampariello and
/// Lucidi 1986), and optionally (Options::regularized_direction) step 2 tries the
/// Levenberg-Marquardt direction before -grad psi (Munson et al. 2001).
///
/// Misuse (size mismatch, NaN/Inf in the start point, lower > upper, invalid options)
/// throws std::invalid_argument. Numerical trouble never throws: it ends the solve with a
/// TerminationType and a message in the Summary.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ncp/problem.hpp"
#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp {

/// State after one iteration, passed to the callback and stored in Summary::trace.
struct IterationRecord {
  int iteration = 0;               ///< k (0 = the start point, before any step)
  double phi_inf = 0.0;            ///< ||Phi(x^k)||_inf
  double psi = 0.0;                ///< psi(x^k) = 1/2 ||Phi(x^k)||_2^2
  double grad_psi_inf = 0.0;       ///< ||J' Phi||_inf at x^k
  double step_length = 0.0;        ///< 2^-i accepted to reach x^k (0 for k = 0)
  double direction_norm = 0.0;     ///< ||d||_2 of the step that reached x^k
  int backtracks = 0;              ///< i of the step that reached x^k
  bool gradient_step = false;      ///< the step that reached x^k was d = -grad psi
  bool regularized_step = false;   ///< ... was the Levenberg-Marquardt direction
  bool minimum_norm_step = false;  ///< ... was the rank-revealing least-squares step
  int degenerate_pairs = 0;        ///< |gamma| at x^k (pairs with A = B = 0)
  double time_s = 0.0;             ///< wall time since the solve started
};

/// Why the hybrid default (Options::hybrid) left a strategy for the next one.
enum class SwitchReason {
  kStuck,         ///< the strategy ended at a non-solution stationary point of its merit
                  ///< function, in a failed line search or a failed Newton solve (after
                  ///< its merit restarts, Options::merit_restarts)
  kSlowProgress,  ///< its best psi fell by less than the factor Options::hybrid_decrease
                  ///< over the last Options::hybrid_window iterations
  kBudget,        ///< it used its iteration budget (Options::hybrid_budget_per_unknown)
};
constexpr SwitchReason kLastSwitchReason = SwitchReason::kBudget;
const char* ToString(SwitchReason reason);

/// One strategy of the hybrid default: an NCP function and whether the
/// Levenberg-Marquardt direction is tried before -grad psi.
struct Strategy {
  NcpFunction ncp_function = NcpFunction::kFischerBurmeister;
  bool regularized_direction = false;
};

/// A switch of the hybrid default, recorded in Summary::strategy_switches.
struct StrategySwitch {
  int iteration = 0;       ///< k of the iterate the new strategy starts from
  Strategy from_strategy;  ///< the strategy left
  Strategy to_strategy;    ///< the strategy taken
  SwitchReason reason = SwitchReason::kStuck;
  int best_iteration = 0;  ///< k at which from_strategy reached that point (smallest psi)
  double best_psi =
      0.0;  ///< psi (merit of from_strategy) at that point, where to_strategy starts
};

/// Return false to stop the solve (TerminationType::kUserAbort).
using IterationCallback = std::function<bool(const IterationRecord&)>;

/// Largest Options::stagnation_window: the solver keeps that many values of psi.
inline constexpr int kMaxStagnationWindow = 1000000;

struct Options {
  NcpFunction ncp_function = NcpFunction::kFischerBurmeister;
  /// min function at a tie A_j = B_j: take grad B_j (true) or grad A_j (false) as the
  /// B-subdifferential element. false: x_j = 0 for a standard NCP pair (x, F); the
  /// contact module uses true (a touching node is closed), which keeps the Newton matrix
  /// regular for a body held only by contact.
  bool min_tie_takes_b = false;
  /// lambda of the penalized FB function, in (0, 1]; 1 gives plain FB (CCK 2000 use
  /// 0.95).
  double penalized_fb_lambda = 0.95;
  /// Converged when ||Phi(x)||_inf <= tolerance (thesis section 6.4, eq. 109), in the
  /// units of the rows. For a problem that states its own scales (MixedProblem::Scales)
  /// tolerance is relative instead: row i must satisfy |row_i| <= floor_i + tolerance *
  /// scale_i.
  double tolerance = 1e-10;
  /// Round-off floor of the test, in ulps: x^k is also converged when every row of Phi is
  /// within tolerance + roundoff_ulps * eps * r_i, r_i the change of row i caused by
  /// moving every x_j by one relative unit, r = |J_E||x| for an equation and |dphi/dA|
  /// |J_A||x| + |dphi/dB| |J_B||x| for a pair (eps = 2.2e-16; weighted rows use the
  /// weighted Jacobians). That is where a tolerance below what double precision resolves
  /// at x (e.g. rows scaled by h^-2 on a fine grid: eps h^-2 |u| > 1e-10) stops; the
  /// Summary then says so (Summary::roundoff_limited). Applies only where the rows' own
  /// accuracy ends, so a problem whose rows resolve the tolerance is tested exactly as
  /// before. 0 = off.
  double roundoff_ulps = 10.0;
  /// Stop with kMaxIterations after this many Newton/gradient steps.
  int max_iterations = 500;
  /// Stop with kTimeLimit when the wall time since Solve() began exceeds this [s].
  /// Checked at every iterate, at every line-search trial and before every numeric
  /// factorization: a factorization whose predicted time exceeds the time left is not
  /// started.
  double max_seconds = std::numeric_limits<double>::infinity();
  /// Rate [flop/s] that turns the predicted flop count of a factorization (from the
  /// symbolic analysis) into a predicted time until one factorization has been timed;
  /// afterwards the rate measured on the last factorization is used. 0 takes the typical
  /// rate of the backend (constants in linear_solver.cpp; their measurement:
  /// benchmarks/results/defaults/README.md).
  double factorization_flop_rate = 0.0;
  /// Newton direction kept only if grad psi' d <= -descent_rho ||d||_2^descent_p (eq.
  /// 22).
  double descent_rho = 1e-8;
  double descent_p = 2.1;
  /// Armijo constant beta in (0, 1/2) of eq. (23).
  double armijo_beta = 1e-4;
  /// Armijo reference: psi(x^k) replaced by the largest psi of the last
  /// nonmonotone_memory iterates (Grippo, Lampariello and Lucidi 1986). 1 is the monotone
  /// eq. (23) of Algorithm 1. The default 3 was chosen on the problem collection
  /// (benchmarks/results/defaults/README.md).
  int nonmonotone_memory = 3;
  /// Before falling back to -grad psi, try the Levenberg-Marquardt direction
  /// (J'J + mu I) d = -J' Phi, mu = ||Phi||_2, if it passes eq. (22) (a regularized
  /// Gauss-Newton step, Levenberg 1944, Marquardt 1963). Off by default: it solved fewer
  /// problems of the collection (benchmarks/results/defaults/README.md). Forms J'J
  /// (allocates per iteration).
  bool regularized_direction = false;
  /// Restart strategy: when a Fischer-Burmeister-family solve ends at a stationary point
  /// of psi that is not a solution (kStationaryPoint) or in a failed line search,
  /// continue from that point with the other member of the family (FB <-> penalized FB
  /// with penalized_fb_lambda), at most this many times; the iteration limit counts all.
  /// The two merit functions have different non-solution stationary points, so a point
  /// where one is stuck is generally not one of the other (Chen, Chen and Kanzow 2000 for
  /// the penalized FB function). No effect with the min function. 0 turns restarts off;
  /// the default 6 was chosen on the problem collection
  /// (benchmarks/results/defaults/README.md).
  int merit_restarts = 6;
  /// Hybrid default: a strategy (NCP function, direction) that stops making progress
  /// hands its best iterate to the next strategy instead of ending the solve. The
  /// sequence is the requested one (ncp_function, regularized_direction) followed by
  /// penalized FB, min, FB with the Levenberg-Marquardt direction and penalized FB with
  /// it, each taken once (skipping the requested one). A strategy is left
  /// (Summary::strategy_switches) when
  ///  - it ends stuck: a non-solution stationary point, a failed line search, a failed
  ///    Newton solve without fallback (merit_restarts are used up first);
  ///  - slow progress: its smallest psi fell by less than the factor hybrid_decrease over
  ///    the last hybrid_window iterations (Newton's local phase takes many orders of
  ///    magnitude per window; a gradient-like crawl or linear convergence at a singular
  ///    solution does not);
  ///  - budget: it took max(hybrid_window, hybrid_budget_per_unknown * n) iterations.
  /// The next strategy starts from the point of smallest psi of the strategy left
  /// (MixedProblem::RestartPoint of it). max_iterations and max_seconds count all
  /// strategies. The last strategy runs until the ordinary stopping tests. false: one
  /// strategy (with merit restarts), the solver before the hybrid default.
  bool hybrid = true;
  /// Window of the slow-progress test [iterations] (0 turns the test off). The defaults
  /// of the window and of hybrid_decrease were chosen on the problem collection
  /// (docs/ncp.md, "Hybrid default").
  int hybrid_window = 50;
  /// Slow progress when min psi now > hybrid_decrease * min psi hybrid_window iterations
  /// ago; in (0, 1). 0.01: two orders of magnitude of psi (one of ||Phi||) per window.
  double hybrid_decrease = 0.01;
  /// Iteration budget of one strategy = max(hybrid_window, hybrid_budget_per_unknown *
  /// n); > 0 (+inf: no budget).
  double hybrid_budget_per_unknown = 10.0;
  /// Largest i tried in the step 2^-i; failing it ends with kLineSearchFailure.
  int max_backtracks = 60;
  /// A pair belongs to the degenerate set gamma when hypot(A_j, B_j) <= this (DFK: 0).
  double degenerate_tolerance = 0.0;
  /// When the line search cannot decrease psi, the end is reported as kStationaryPoint
  /// (a local minimum of psi that is not a solution) if ||grad psi||_inf <=
  /// stationarity_tolerance * ||Phi||_inf, else as kLineSearchFailure. grad psi = 0
  /// exactly with Phi != 0 is always kStationaryPoint.
  double stationarity_tolerance = 1e-6;
  /// Stagnation: stop with kStationaryPoint when the smallest psi so far decreased by
  /// less than stagnation_tolerance of itself over the last stagnation_window iterations
  /// (the iterates approach a stationary point of psi that is not a solution). 0 disables
  /// the test.
  int stagnation_window =
      20;  ///< in [0, kMaxStagnationWindow] (a ring buffer of that many psi)
  double stagnation_tolerance = 1e-6;
  /// Algorithm 1 step 2: fall back to d = -grad psi. If false, a failed Newton solve
  /// ends with kLinearSolverFailure and a failed descent test keeps the Newton direction.
  bool gradient_fallback = true;
  /// Dense LU: when the LU calls J singular and J's row or column max-norms spread over
  /// more than 2^20, factor J equilibrated (rows, then columns, by powers of two;
  /// internal::Equilibration) instead. The Newton direction is the same; the pivots and
  /// the singularity test see rows of one size. The stopping tests stay in the problem's
  /// units. (UMFPACK and KLU scale rows themselves; CHOLMOD needs J symmetric.)
  bool scale_newton_system = true;
  /// When the LU of J reports singularity or fails the backward-error check, take the
  /// least-squares step of a rank-revealing factorization (minimum norm for the dense
  /// backend, SuiteSparseQR's basic solution for the sparse ones) if it passes the
  /// descent test (eq. 22), before the Levenberg-Marquardt direction and -grad psi.
  bool minimum_norm_step = true;
  LinearSolverType linear_solver = LinearSolverType::kAuto;
  /// At most this many BLAS threads during Solve() (ncp/blas_threads.hpp; OpenBLAS only,
  /// no effect with another BLAS); 0 leaves the count alone. The default 1: the
  /// factorizations call BLAS on small fronts, where OpenBLAS's threads cost more than
  /// they give and spin (sched_yield) between calls.
  int blas_threads = 1;
  /// kAuto uses dense LU for n <= dense_threshold, UMFPACK above.
  int dense_threshold = 100;
  /// Box MCP: a bound with |b| >= infinite_bound is infinite (GAMS and PATH write "no
  /// bound" as +-1e20). +inf keeps every finite bound finite.
  double infinite_bound = 1e20;
  /// Box MCP: replace the start point x0 by mid(l, u, x0), its projection onto [l, u].
  /// false uses x0 as given (FB and min are defined outside the box too; the obstacle
  /// problems of tests/ncp/test_obstacle_mesh.cpp start below the obstacle on purpose).
  bool project_start_point = true;
  /// Store an IterationRecord per iteration in Summary::trace.
  bool keep_trace = false;
  /// Print one line per iteration to stderr.
  bool log_to_stderr = false;
  /// Called after every iteration (and once for the start point; again for the iterate a
  /// merit restart continues from, whose trace record replaces the one before it).
  IterationCallback callback;

  /// Algorithm 1 of the thesis with its published constants (rho = 1e-8, p = 2.1,
  /// beta = 1e-4, monotone Armijo, d = -grad psi as the only fallback, one strategy).
  static Options Algorithm1();

  /// Rejects settings outside their ranges; *error says which and why.
  bool IsValid(std::string* error) const;
};

struct Summary {
  TerminationType termination = TerminationType::kNotSolved;
  std::string message = "not solved yet";

  int num_variables = -1;
  int num_equations = -1;
  int num_pairs = -1;
  NcpFunction ncp_function =
      NcpFunction::kFischerBurmeister;  ///< as requested (restarts may switch)
  LinearSolverType linear_solver_requested = LinearSolverType::kAuto;
  LinearSolverType linear_solver_used = LinearSolverType::kAuto;

  int iterations = -1;            ///< steps taken
  int jacobian_evaluations = -1;  ///< calls of Jacobian()
  int residual_evaluations = -1;  ///< calls of Evaluate() (line search included)
  int gradient_steps = -1;        ///< steps with d = -grad psi
  int regularized_steps = -1;     ///< steps along the Levenberg-Marquardt direction
  /// Steps along the rank-revealing least-squares direction (Options::minimum_norm_step).
  int minimum_norm_steps = -1;
  /// Dense LU factorizations of an equilibrated J after the LU of J called it singular
  /// (Options::scale_newton_system).
  int equilibrated_factorizations = -1;
  int merit_restarts = -1;  ///< switches FB <-> penalized FB (Options::merit_restarts)
  /// Options::hybrid: every switch of strategy, in order (empty when the first one solved
  /// the problem or the hybrid is off).
  std::vector<StrategySwitch> strategy_switches;
  int linear_solver_failures = -1;   ///< Newton solves that failed (singular, non-finite)
  int descent_test_failures = -1;    ///< Newton directions rejected by eq. (22)
  int backtracks = -1;               ///< total halvings in the line search
  int symbolic_factorizations = -1;  ///< sparse analyses (1 if the pattern never changed)
  /// LinearSolverType::kCholmod: Newton matrices factored by UMFPACK's LU instead because
  /// they were not symmetrizable or not positive definite (0 for the other backends).
  int cholesky_fallbacks = -1;
  /// Box MCP: components of the start point outside [l, u] moved onto the nearer bound
  /// (x0_i <- mid(l_i, u_i, x0_i)); 0 for a mixed problem.
  int projected_start_components = -1;
  /// Box MCP: components of the returned x that were outside [l, u] and were moved onto
  /// the nearer bound (the FB iterates may leave the box; the returned x never does).
  int projected_final_components = -1;
  /// TerminationType::kInfeasible: the Farkas certificate y (size n, one entry per row of
  /// F = M x + q) with y_i >= 0 on rows with only a lower bound, <= 0 with only an upper
  /// bound, 0 on two-sided or fixed rows, g = M'y with g_i <= 0 where u_i = +inf and g_i
  /// >= 0 where l_i = -inf, and q'y + sum_i max(g_i l_i, g_i u_i) < 0: then y'F(x) < 0
  /// for every x in [l, u], while a solution would have y'F(x) >= 0. Empty otherwise.
  Vector infeasibility_certificate;

  /// true when the problem gave its scales (MixedProblem::Scales): the residuals below
  /// are then of the relative system (rows divided by scale + floor / tolerance;
  /// converged when
  /// <= tolerance).
  bool weighted_residual = false;
  /// kAtRoundoffFloor: ||Phi||_inf > tolerance, every row within tolerance + its
  /// round-off floor (Options::roundoff_ulps); the tolerance asked for more digits than
  /// double precision carries at x.
  bool roundoff_limited = false;
  double initial_phi_inf = -1.0;  ///< ||Phi(x^0)||_inf
  double final_phi_inf = -1.0;    ///< ||Phi||_inf at the last iterate (box MCP: before
                                  ///< its projection, projected_final_components)
  double final_psi = -1.0;        ///< psi at the returned x

  /// Wall time of the solve [s]. The split below takes two clock reads per iteration, no
  /// more: on small problems reads around every evaluation were a visible part of an
  /// iteration (docs/ncp.md, "Small problems"). (ncp::petsc::Solver, whose iterations
  /// are large, times every evaluation and linear solve instead.)
  double total_time_s = -1.0;
  /// total_time_s - linear_solver_time_s [s]: the problem's Evaluate() and Jacobian(),
  /// the solver's assembly of Phi and J from them, the line search, the tests and the
  /// iteration callback (and the set-up of the solve).
  double evaluation_time_s = -1.0;
  /// Computing each direction [s]: the factorizations and solves of the Newton system,
  /// the fallback directions (least-squares, Levenberg-Marquardt, -grad psi) and the
  /// descent test.
  double linear_solver_time_s = -1.0;
  /// Predicted flops of the last factorization considered (NaN: the backend gives none).
  double predicted_factorization_flops = -1.0;

  std::vector<IterationRecord> trace;  ///< filled when Options::keep_trace

  /// One line: status, iterations, evaluations, residual, time.
  std::string BriefReport() const;
  /// Several lines with every counter.
  std::string FullReport() const;
  /// True for kConverged and kAtRoundoffFloor: x meets the tolerance, or is as accurate
  /// as double precision resolves at x (every row within its round-off floor).
  bool IsSolutionUsable() const {
    return termination == TerminationType::kConverged ||
           termination == TerminationType::kAtRoundoffFloor;
  }
};

/// Keeps the linear-solver state (symbolic factorization) between solves, so a sequence
/// of problems with the same Jacobian pattern (time steps) pays the analysis once.
class Solver {
 public:
  explicit Solver(const Options& options = Options());
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver& operator=(Solver&&) noexcept;

  const Options& options() const { return options_; }
  /// New options for the next solves; the workspace (symbolic factorization, box MCP
  /// form) is kept. Throws std::invalid_argument like the constructor.
  void set_options(const Options& options);

  /// Mixed problem; *x holds the start point on entry and the last iterate on return.
  void Solve(MixedProblem& problem, Vector* x, Summary* summary);
  /// Box MCP l <= x <= u perp F(x). Bounds with |b| >= Options::infinite_bound are
  /// infinite; a start point outside [l, u] is projected onto it (counted in
  /// Summary::projected_start_components and stated in Summary::message).
  void Solve(SquareFunction& F, const Vector& lower, const Vector& upper, Vector* x,
             Summary* summary);
  /// Standard NCP x >= 0 perp F(x) >= 0.
  void SolveNcp(SquareFunction& F, Vector* x, Summary* summary);

 private:
  Options options_;
  struct Workspace;
  class Iteration;  // one solve, phase by phase (solver.cpp)
  std::unique_ptr<Workspace> workspace_;
};

/// One-shot conveniences. Problems with n <= 100 borrow a Solver kept per thread (the
/// workspace is built once, not in every call; results are those of a fresh Solver);
/// larger problems and calls nested inside a running one-shot solve use a fresh Solver.
void Solve(const Options& options, MixedProblem& problem, Vector* x, Summary* summary);
void Solve(const Options& options, SquareFunction& F, const Vector& lower,
           const Vector& upper, Vector* x, Summary* summary);
void SolveNcp(const Options& options, SquareFunction& F, Vector* x, Summary* summary);

}  // namespace ncp
