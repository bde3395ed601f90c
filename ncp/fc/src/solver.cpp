#include "ncp/fc/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "block_delassus.hpp"
#include "gauss_seidel.hpp"
#include "linear_solver.hpp"
#include "local_laws.hpp"
#include "ncp/fc/error.hpp"

namespace ncp::fc {

const char* ToString(Formulation f) {
  switch (f) {
    case Formulation::kAlartCurnier:
      return "alart-curnier";
    case Formulation::kNaturalMap:
      return "natural-map";
    case Formulation::kFischerBurmeister:
      return "fischer-burmeister";
    case Formulation::kHybrid:
      return "hybrid";
  }
  return "unknown";
}

const char* ToString(Termination t) {
  switch (t) {
    case Termination::kNotSolved:
      return "not_solved";
    case Termination::kConverged:
      return "converged";
    case Termination::kMaxIterations:
      return "max_iterations";
    case Termination::kTimeLimit:
      return "time_limit";
    case Termination::kLineSearchFailure:
      return "line_search_failure";
    case Termination::kLinearSolverFailure:
      return "linear_solver_failure";
    case Termination::kStalled:
      return "stalled";
    case Termination::kNonFiniteValues:
      return "non_finite_values";
  }
  return "unknown";
}

Formulation ParseFormulation(const std::string& name) {
  if (name == "ac" || name == "alart-curnier") return Formulation::kAlartCurnier;
  if (name == "nm" || name == "natural-map") return Formulation::kNaturalMap;
  if (name == "fb" || name == "fischer-burmeister")
    return Formulation::kFischerBurmeister;
  if (name == "hybrid") return Formulation::kHybrid;
  throw std::invalid_argument("unknown formulation '" + name +
                              "' (expected ac, nm, fb or hybrid)");
}

bool Options::IsValid(std::string* error) const {
  auto fail = [error](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(tolerance > 0.0)) return fail("tolerance must be > 0");
  if (max_iterations < 0) return fail("max_iterations must be >= 0");
  if (!(acceptable_tolerance >= 0.0)) return fail("acceptable_tolerance must be >= 0");
  if (!(max_time_s >= 0.0)) return fail("max_time_s must be >= 0");
  if (!(rho_scale > 0.0) || !std::isfinite(rho_scale))
    return fail("rho_scale must be > 0");
  if (!(armijo_beta > 0.0 && armijo_beta < 0.5))
    return fail("armijo_beta must be in (0, 1/2)");
  if (nonmonotone_window < 1) return fail("nonmonotone_window must be >= 1");
  if (gauss_seidel_sweeps < 0) return fail("gauss_seidel_sweeps must be >= 0");
  if (gauss_seidel_fallback_sweeps < 0) return fail("gauss_seidel_fallback_sweeps must be >= 0");
  if (max_backtracks < 0) return fail("max_backtracks must be >= 0");
  if (stall_window < 1) return fail("stall_window must be >= 1");
  if (!(regularization > 0.0)) return fail("regularization must be > 0");
  if (!(newton_residual > 0.0 && newton_residual < 1.0))
    return fail("newton_residual must be in (0, 1)");
  if (dense_threshold < 0) return fail("dense_threshold must be >= 0");
  if (krylov_max_iterations < 1) return fail("krylov_max_iterations must be >= 1");
  return true;
}

std::string Summary::BriefReport() const {
  std::ostringstream out;
  out << "fc: " << ToString(termination) << " (" << message << "), "
      << ToString(formulation_final) << ", Gauss-Seidel sweeps " << gauss_seidel_sweeps
      << " + " << fallback_sweeps << " (fallback)"
      << ", iterations " << iterations << ", attempts " << attempts << ", error "
      << initial_error << " -> " << final_error << ", time " << total_time_s << " s";
  return out.str();
}

namespace {

using internal::Block;
using Clock = std::chrono::steady_clock;

/// Everything one Solve() shares between the attempts of the hybrid.
class NewtonSolver {
 public:
  NewtonSolver(const Options& options, const FrictionProblem& problem, Summary* summary)
      : options_(options),
        problem_(problem),
        W_(problem),
        summary_(summary),
        d_(problem.dimension),
        nc_(problem.num_contacts),
        A_(nc_),
        B_(nc_),
        start_(Clock::now()) {
    LinearSolverType type = options.linear_solver;
    if (type == LinearSolverType::kAuto)
      type = nc_ <= options.dense_threshold ? LinearSolverType::kDenseLU
                                            : LinearSolverType::kUmfpack;
    linear_solver_ = ncp::internal::MakeLinearSolver(type);
    summary_->linear_solver_used = type;
    ComputeBaseRho();
  }

  /// Runs the attempts from *r; returns the best iterate in *r.
  void Run(Vector* r) {
    best_r_ = *r;
    best_error_ = NaturalMapError(problem_, best_r_);
    summary_->initial_error = best_error_;
    Termination status = Termination::kConverged;
    if (!std::isfinite(best_error_))
      status = Termination::kNonFiniteValues;
    else
      WarmStart();
    const std::vector<std::pair<Formulation, double>> attempts =
        internal::AttemptSequence(options_.formulation);
    for (const auto& [formulation, rho_factor] : attempts) {
      if (status == Termination::kNonFiniteValues || best_error_ <= options_.tolerance)
        break;
      ++summary_->attempts;
      summary_->formulation_final = formulation;
      status = RunAttempt(formulation, rho_factor);
      if (status == Termination::kConverged || status == Termination::kMaxIterations ||
          status == Termination::kTimeLimit || status == Termination::kNonFiniteValues)
        break;
      // The first attempt of the hybrid stalled: try Gauss-Seidel before the next one.
      if (summary_->attempts == 1 && options_.formulation == Formulation::kHybrid &&
          GaussSeidelTrial()) {
        status = Termination::kConverged;
        break;
      }
    }
    // Not solved: the Gauss-Seidel point if it came closer than every Newton iterate.
    if (best_error_ > options_.tolerance && gs_error_ < best_error_) {
      best_error_ = gs_error_;
      best_r_ = gs_r_;
    }
    *r = best_r_;
    summary_->final_error = NaturalMapError(problem_, *r);
    if (summary_->final_error <= options_.tolerance) status = Termination::kConverged;
    summary_->termination = status;
    summary_->message = Message(status);
    summary_->symbolic_factorizations = linear_solver_->symbolic_factorizations();
  }

 private:
  double Elapsed() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }

  /// Per-contact rho from the diagonal block of W (internal::RhoFromDiagonal); a zero
  /// diagonal (contact W does not see) falls back to 1 / max diag W, or 1 when W = 0.
  /// Units: velocity per force inverted, so rho u is a force.
  void ComputeBaseRho() {
    double largest = 0.0;
    for (int a = 0; a < nc_; ++a)
      largest = std::max(largest, W_.Diagonal(a).diagonal().maxCoeff());
    const double fallback = largest > 0.0 ? 1.0 / largest : 1.0;
    rho_.resize(nc_);
    for (int a = 0; a < nc_; ++a) {
      const Eigen::Vector3d diagonal = W_.Diagonal(a).diagonal();
      rho_[a] = internal::RhoFromDiagonal(d_, diagonal.data(), fallback);
    }
  }

  /// Options::gauss_seidel_sweeps sweeps from best_r_, keeping the result if it is
  /// better.
  void WarmStart() {
    Vector r = best_r_;
    for (int k = 0; k < options_.gauss_seidel_sweeps && best_error_ > options_.tolerance;
         ++k) {
      internal::GaussSeidelSweep(problem_, W_, rho_, &r);
      ++summary_->gauss_seidel_sweeps;
      const double error = NaturalMapError(problem_, r);
      if (!std::isfinite(error)) return;
      if (error < best_error_) {
        best_error_ = error;
        best_r_ = r;
      }
    }
  }

  /// Options::gauss_seidel_fallback_sweeps projected Gauss-Seidel sweeps from best_r_, as a
  /// side trial: true (best_r_ replaced) when they reach the tolerance; otherwise their best
  /// point is kept apart (gs_r_, gs_error_) and the Newton attempts go on from best_r_. The
  /// sweeps stop early when the error, tested every kCheckEvery sweeps, has not halved over
  /// kHalvingWindow sweeps (Gauss-Seidel converges linearly: a slow rate will not reach
  /// the tolerance within the budget), or at the time limit.
  bool GaussSeidelTrial() {
    constexpr int kCheckEvery = 10, kHalvingWindow = 200;
    Vector r = best_r_;
    gs_error_ = best_error_;
    double window_start_error = gs_error_;
    for (int k = 1; k <= options_.gauss_seidel_fallback_sweeps; ++k) {
      if (options_.max_time_s > 0.0 && Elapsed() > options_.max_time_s) break;
      internal::GaussSeidelSweep(problem_, W_, rho_, &r);
      ++summary_->fallback_sweeps;
      if (k % kCheckEvery != 0) continue;
      const double error = NaturalMapError(problem_, r);
      if (!std::isfinite(error)) break;
      if (error < gs_error_) {
        gs_error_ = error;
        gs_r_ = r;
      }
      if (gs_error_ <= options_.tolerance) {
        best_error_ = gs_error_;
        best_r_ = gs_r_;
        return true;
      }
      if (k % kHalvingWindow == 0) {
        if (!(gs_error_ <= 0.5 * window_start_error)) break;
        window_start_error = gs_error_;
      }
    }
    return false;
  }

  /// Phi(r) of the formulation into *phi, with the Jacobian blocks A_, B_; returns psi.
  double Evaluate(Formulation formulation, double rho_factor, const Vector& r,
                  Vector* phi) {
    const Vector u = problem_.W * r + problem_.q;
    phi->resize(r.size());
    const double s = options_.rho_scale * rho_factor;
    for (int a = 0; a < nc_; ++a) {
      const double* ra = r.data() + d_ * a;
      const double* ua = u.data() + d_ * a;
      double* pa = phi->data() + d_ * a;
      internal::EvaluateLaw(formulation, d_, problem_.mu[a], rho_[a], s, ra, ua, pa, &A_[a], &B_[a]);
  }
    return 0.5 * phi->squaredNorm();
  }

  /// The Newton direction of the shifted matrix, (J + delta I) d = -phi with
  /// delta = regularization max |J_ii| (1e-10: the step changes by O(1e-10) relative
  /// where J is regular, and stays defined where J is singular, as when sticking contacts
  /// make J = rho W with W rank-deficient), kept when it passes the inexact-Newton test
  /// ||J d + phi|| <= eta ||phi||, eta = Options::newton_residual < 1, which makes d a
  /// descent direction of psi: grad psi' d = phi' (J d + phi) - ||phi||^2 < 0. Otherwise
  /// the Levenberg-Marquardt direction (J'J + m I) d = -J' phi, m = max(||phi||,
  /// regularization) (Yamashita & Fukushima 2001), a descent direction for any m > 0.
  /// Measured on data/fc3d: one shifted factorization per step instead of J
  /// first and J + delta I after a failure took Capsules-i101-404 from 111 steps, 0.45 s
  /// to 104 steps, 0.27 s, with the same steps on the other 14 problems. false: both
  /// failed.
  bool Direction(const Vector& phi, Vector* direction) {
    W_.AssembleJacobian(A_, B_, &J_);
    SparseMatrix shifted = J_;
    const double delta =
        options_.regularization * std::max(1.0, J_.diagonal().cwiseAbs().maxCoeff());
    for (int i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) += delta;
    const bool first = !factorized_once_;
    factorized_once_ = true;
    if (linear_solver_->Analyze(shifted, first) && linear_solver_->Factorize(shifted) &&
        linear_solver_->Solve(-phi, direction) && direction->allFinite() &&
        (J_ * *direction + phi).norm() <= options_.newton_residual * phi.norm())
      return true;
    ++summary_->linear_solver_failures;
    ++summary_->levenberg_marquardt_steps;
    normal_matrix_ = SparseMatrix(J_.transpose()) * J_;
    const double m = std::max(phi.norm(), options_.regularization);
    for (int i = 0; i < normal_matrix_.rows(); ++i) normal_matrix_.coeffRef(i, i) += m;
    if (!normal_solver_)
      normal_solver_ = ncp::internal::MakeLinearSolver(summary_->linear_solver_used);
    const bool first_normal = !normal_factorized_once_;
    normal_factorized_once_ = true;
    const Vector gradient = J_.transpose() * phi;
    return normal_solver_->Analyze(normal_matrix_, first_normal) &&
           normal_solver_->Factorize(normal_matrix_) &&
           normal_solver_->Solve(-gradient, direction) && direction->allFinite();
  }

  Termination RunAttempt(Formulation formulation, double rho_factor) {
    Vector r = best_r_, phi, trial_phi, direction, trial;
    double psi = Evaluate(formulation, rho_factor, r, &phi);
    if (!std::isfinite(psi)) return Termination::kNonFiniteValues;
    std::deque<double> recent_psi{psi};
    internal::AttemptProgress progress(options_, best_error_);
    while (true) {
      if (summary_->iterations >= options_.max_iterations)
        return Termination::kMaxIterations;
      if (options_.max_time_s > 0.0 && Elapsed() > options_.max_time_s)
        return Termination::kTimeLimit;
      if (!Direction(phi, &direction)) return Termination::kLinearSolverFailure;
      // Nonmonotone Armijo: psi(r + t d) <= max(recent psi) - 2 beta t psi(r).
      const double reference = *std::max_element(recent_psi.begin(), recent_psi.end());
      double t = 1.0, trial_psi = 0.0;
      bool accepted = false;
      for (int i = 0; i <= options_.max_backtracks; ++i, t *= 0.5) {
        trial = r + t * direction;
        trial_psi = Evaluate(formulation, rho_factor, trial, &trial_phi);
        if (std::isfinite(trial_psi) &&
            trial_psi <= reference - 2.0 * options_.armijo_beta * t * psi) {
          accepted = true;
          break;
        }
        ++summary_->backtracks;
      }
      if (!accepted) return Termination::kLineSearchFailure;
      // Evaluate() of the accepted trial left A_, B_ at the new iterate.
      r.swap(trial);
      phi.swap(trial_phi);
      psi = trial_psi;
      recent_psi.push_back(psi);
      if (static_cast<int>(recent_psi.size()) > options_.nonmonotone_window)
        recent_psi.pop_front();
      ++summary_->iterations;
      const double error = NaturalMapError(problem_, r);
      if (!std::isfinite(error)) return Termination::kNonFiniteValues;
      Record(formulation, error, psi, t);
      const Termination status = progress.Update(error, r, &best_error_, &best_r_);
      if (status != Termination::kNotSolved) return status;
    }
  }

  void Record(Formulation formulation, double error, double psi, double t) {
    IterationRecord record;
    record.iteration = summary_->iterations;
    record.formulation = formulation;
    record.error = error;
    record.psi = psi;
    record.step_length = t;
    record.time_s = Elapsed();
    summary_->trace.push_back(record);
    if (options_.log_to_stderr)
      std::fprintf(stderr, "fc %4d %-13s error %.3e psi %.3e step %.3g\n",
                   record.iteration, ToString(formulation), error, psi, t);
  }

  std::string Message(Termination status) const {
    std::ostringstream out;
    out << internal::ErrorReport(options_, status == Termination::kConverged, summary_->final_error)
        << " after " << summary_->iterations << " Newton steps";
    if (status != Termination::kConverged)
      out << "; last attempt ended: " << ToString(status);
    return out.str();
  }

  const Options& options_;
  const FrictionProblem& problem_;
  internal::BlockDelassus W_;
  Summary* summary_;
  int d_, nc_;
  std::vector<Block> A_, B_;
  std::vector<internal::Rho> rho_;
  SparseMatrix J_, normal_matrix_;
  std::unique_ptr<ncp::internal::LinearSolver> normal_solver_;
  bool normal_factorized_once_ = false;
  std::unique_ptr<ncp::internal::LinearSolver> linear_solver_;
  bool factorized_once_ = false;
  Vector best_r_;
  double best_error_ = 0.0;
  Vector gs_r_;  // best point of GaussSeidelTrial (when it did not converge)
  double gs_error_ = std::numeric_limits<double>::infinity();
  Clock::time_point start_;
};

}  // namespace

void Solve(const Options& options, const FrictionProblem& problem, Vector* r,
           Summary* summary) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("ncp::fc::Options: " + why);
  problem.Validate();
  if (!r || !summary)
    throw std::invalid_argument("ncp::fc::Solve: r and summary must not be null");
  if (r->size() == 0) r->setZero(problem.size());
  if (r->size() != problem.size())
    throw std::invalid_argument("ncp::fc::Solve: start point must have " +
                                std::to_string(problem.size()) + " entries, got " +
                                std::to_string(r->size()));
  if (!r->allFinite())
    throw std::invalid_argument("ncp::fc::Solve: start point not finite");
  *summary = Summary();
  summary->formulation_requested = options.formulation;
  summary->num_contacts = problem.num_contacts;
  summary->iterations = 0;
  summary->gauss_seidel_sweeps = 0;
  summary->fallback_sweeps = 0;
  summary->attempts = 0;
  summary->backtracks = 0;
  summary->linear_solver_failures = 0;
  summary->levenberg_marquardt_steps = 0;
  const auto start = Clock::now();
  NewtonSolver solver(options, problem, summary);
  solver.Run(r);
  summary->total_time_s = std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace ncp::fc
