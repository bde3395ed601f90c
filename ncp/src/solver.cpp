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
#include "semismooth_newton.hpp"
#include "strategy.hpp"
#include "workspace.hpp"

namespace ncp {
namespace {

using internal::FormatNumber;

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
// One solve on Eigen vectors and matrices: the serial back end of Algorithm 1
// (internal::SemismoothNewton, semismooth_newton.hpp, holds the loop and its decisions).
//
//   Start                      Phi(x^0), sizes, backend, row weights
//   EvaluateJacobian           J^k in the B-subdifferential, grad psi = J' Phi   (eq. 24)
//   GradientNormAndRoundoffFloor  ||grad psi||_inf, converged to the accuracy double
//                              precision allows
//   NewtonDirection ...        step 2: Newton (eq. 21, 22), least-squares, regularized
//   TrialStep                  step 3: x^k + t d and psi there

class Solver::Iteration : public internal::SemismoothNewton<Solver::Iteration> {
 public:
  /// dense_jacobian: the problem's Jacobian of Phi written dense (a box MCP), used on
  /// the dense backend without row weights; nullptr: MixedProblem::Jacobian.
  Iteration(const Options& options, Workspace& workspace, MixedProblem& problem,
            internal::DenseMixedJacobian* dense_jacobian, Vector& x, Summary& summary)
      : SemismoothNewton(options, summary, workspace.armijo_reference,
                         workspace.stagnation, workspace.schedule),
        work_(workspace),
        problem_(problem),
        offered_dense_jacobian_(dense_jacobian),
        x_(x),
        n_(problem.NumVariables()),
        m_(problem.NumEquations()),
        p_(n_ - m_) {}

 private:
  friend class internal::SemismoothNewton<Solver::Iteration>;
  using Direction = internal::Direction;
  struct LineSearchScope {};  // (no profiling events in the serial solver)

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
    ResetStrategies();
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
    ResetMemories();
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
    StartSummary(n_, m_);
    summary_.linear_solver_requested = options_.linear_solver;
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
  // that returned false is reported by the stop test after the callback has seen iterate
  // k.
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

  // ---- ||grad psi||_inf and the round-off floor of the test (Options::roundoff_ulps) --
  // Moving x to a neighbouring double (x_j (1 + delta_j), |delta_j| <= eps) changes row i
  // of Phi by up to eps r_i with r = |J_E||x| for equations and |da| |J_A||x| + |db|
  // |J_B||x| for pairs (to first order; J_E, J_A, J_B weighted like the rows). No x
  // closer to the solution is representable below that, so a row within tolerance +
  // roundoff_ulps eps r_i is as converged as double precision allows. Needs J at x^k
  // (EvaluateJacobian). (r = Workspace::sensitivity, summed while J was filled: no extra
  // pass over J.) True when every row is within the floor.
  bool GradientNormAndRoundoffFloor() {
    iterate_.grad_inf = work_.grad.lpNorm<Eigen::Infinity>();
    if (options_.roundoff_ulps == 0.0) return false;
    for (int i = 0; i < n_; ++i)
      if (!internal::RowWithinRoundoffFloor(work_.phi(i), options_.tolerance,
                                            options_.roundoff_ulps, work_.sensitivity(i)))
        return false;
    return true;
  }

  std::pair<double, double> ResidualNorms() const {
    return {work_.phi.lpNorm<Eigen::Infinity>(), 0.5 * work_.phi.squaredNorm()};
  }

  // d = -grad psi, slope -||grad psi||^2.
  void GradientDirection() {
    work_.d = -work_.grad;
    iterate_.slope = -work_.grad.squaredNorm();
  }

  std::pair<double, double> SlopeAndDirectionNorm() const {
    return {work_.grad.dot(work_.d), work_.d.norm()};
  }

  double DirectionNorm() const { return work_.d.norm(); }

  // The direction's time is added to Summary::linear_solver_time_s: two clock reads per
  // iteration, the only ones of an iteration (the rest of the iterations' time is
  // Summary::evaluation_time_s, computed in CompleteSummary).
  template <class Choose>
  Direction TimedDirection(Choose&& choose) {
    const Clock::time_point t0 = Clock::now();
    const Direction direction = choose();
    summary_.linear_solver_time_s += Seconds(t0);
    return direction;
  }

  // ---- step 3's trial point x^k + t d, evaluated into the trial buffers -------------
  internal::LineSearchTrial TrialStep(double t) {
    using Trial = internal::LineSearchTrial;
    work_.x_trial = x_ + t * work_.d;
    // (Component by component: a test t ||d||_inf <= eps ||x||_inf stopped the 2D
    // obstacle at 10^6 unknowns, whose last corrections, ~1e-15 on gaps of 5e-7, are far
    // below eps max|w| ~ 8e-16 x 3.5.)
    if (work_.x_trial == x_) return Trial{Trial::kUnchanged, 0.0};
    if (!Evaluate(work_.x_trial, &work_.Et, &work_.At, &work_.Bt, &work_.phi_trial))
      return Trial{Trial::kNotEvaluable, 0.0};
    if (!AllFinite(work_.phi_trial)) return Trial{Trial::kNonFinite, 0.0};
    return Trial{Trial::kEvaluated, 0.5 * work_.phi_trial.squaredNorm()};
  }

  // ---- the points a restart or a new strategy continues from ------------------------
  void CopyCurrentToTrial() { work_.x_trial = x_; }
  void CopyBestToTrial() { work_.x_trial = work_.progress.best_x(); }

  // The trial point moved to MixedProblem::RestartPoint (x itself, or for a box MCP x
  // projected onto the box) and evaluated; false when it cannot be.
  bool EvaluateRestartTrial() {
    return problem_.RestartPoint(&work_.x_trial) && work_.x_trial.size() == n_ &&
           Evaluate(work_.x_trial, &work_.Et, &work_.At, &work_.Bt, &work_.phi_trial) &&
           AllFinite(work_.phi_trial);
  }

  // x^k, E, A, B, Phi <- the trial point's.
  void AcceptTrialPoint() {
    x_.swap(work_.x_trial);
    work_.E.swap(work_.Et);
    work_.A.swap(work_.At);
    work_.B.swap(work_.Bt);
    work_.phi.swap(work_.phi_trial);
  }

  void ObserveProgress(size_t kk, int k) {
    work_.progress.Observe(kk, iterate_.psi, x_, k);
  }
  const internal::StrategyProgress& Progress() const { return work_.progress; }

  bool TimeLimitPassed() const { return Seconds(start_) > options_.max_seconds; }
  static bool OnAnyRank(bool b) { return b; }
  template <class... Args>
  static void Print(const char* format, Args... args) {
    std::fprintf(stderr, format, args...);
  }
  bool WeightedResidual() const { return work_.weighted; }
  std::string NewtonSolveName() const {
    return std::string(ToString(resolved_)) + " solve";
  }
  static const char* JacobianFailure() { return "MixedProblem::Jacobian returned false"; }

  // The final residuals, counters and times of Summary (Finish).
  void CompleteSummary() {
    summary_.final_phi_inf = work_.phi.lpNorm<Eigen::Infinity>();
    summary_.final_psi = 0.5 * work_.phi.squaredNorm();
    summary_.symbolic_factorizations = SymbolicFactorizations() - symbolic_before_;
    summary_.cholesky_fallbacks = Fallbacks() - fallbacks_before_;
    // One clock read: the rest of the time outside the direction's linear algebra
    // (timed by TimedDirection) is the evaluations' and the iterations' own work.
    summary_.total_time_s = Seconds(start_);
    summary_.evaluation_time_s =
        std::max(0.0, summary_.total_time_s - summary_.linear_solver_time_s);
  }

  Workspace& work_;
  MixedProblem& problem_;
  internal::DenseMixedJacobian* const offered_dense_jacobian_;
  internal::DenseMixedJacobian* dense_jacobian_ = nullptr;  // used in this solve
  Vector& x_;
  const int n_, m_, p_;
  LinearSolverType resolved_ = LinearSolverType::kAuto;
  int symbolic_before_ = 0;
  int fallbacks_before_ = 0;
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
