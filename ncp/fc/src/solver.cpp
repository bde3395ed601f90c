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
    case Termination::kAtRoundoffFloor:
      return "at_roundoff_floor";
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
  if (gauss_seidel_fallback_sweeps < 0)
    return fail("gauss_seidel_fallback_sweeps must be >= 0");
  if (max_backtracks < 0) return fail("max_backtracks must be >= 0");
  if (stall_window < 1) return fail("stall_window must be >= 1");
  if (!(regularization > 0.0)) return fail("regularization must be > 0");
  if (!(shift_error_cap >= 0.0 && shift_error_cap < 1.0))
    return fail("shift_error_cap must be in [0, 1)");
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

using Clock = std::chrono::steady_clock;

namespace internal {

/// The semismooth Newton solver of one problem, kept between solves (Solver): W's block
/// form, rho per contact, the Jacobian's pattern, the linear solver with its symbolic
/// analysis and the work vectors. Run() shares its state between the attempts of the
/// hybrid.
class NewtonSolver {
 public:
  explicit NewtonSolver(const FrictionProblem& problem)
      : problem_(problem),
        W_(problem),
        d_(problem.dimension),
        nc_(problem.num_contacts),
        A_(nc_),
        B_(nc_) {
    ComputeBaseRho();
  }

  /// problem.W = scale W0 (W0 of the constructor's pattern) with the blocks and rho to
  /// match; false (nothing changed) when an entry is not finite.
  bool ScaleW(double scale, const SparseMatrix& W0, SparseMatrix* W) {
    if (!W_.SetScaledValues(scale, W0, W)) return false;
    ComputeBaseRho();
    return true;
  }

  /// Runs the attempts from *r; returns the best iterate in *r.
  void Run(const Options& options, Vector* r, Summary* summary) {
    options_ = &options;
    summary_ = summary;
    start_ = Clock::now();
    gs_error_ = std::numeric_limits<double>::infinity();
    SetLinearSolver();
    q_norm_ = problem_.q.norm();
    best_r_ = *r;
    best_error_ = Error(best_r_);
    summary_->initial_error = best_error_;
    Termination status = Termination::kConverged;
    if (!std::isfinite(best_error_))
      status = Termination::kNonFiniteValues;
    else
      WarmStart();
    if (best_error_ > options.tolerance && status != Termination::kNonFiniteValues)
      status = RunAttempts();
    // Not solved: the Gauss-Seidel point if it came closer than every Newton iterate.
    if (best_error_ > options.tolerance && gs_error_ < best_error_) {
      best_error_ = gs_error_;
      best_r_ = gs_r_;
    }
    *r = best_r_;
    summary_->final_error = Error(*r);
    if (summary_->final_error <= options.tolerance) status = Termination::kConverged;
    status = internal::RoundoffFloorStatus(options, status, summary_->final_error);
    summary_->termination = status;
    SetMessage(status);
    summary_->symbolic_factorizations =
        linear_solver_->symbolic_factorizations() - symbolic_before_;
  }

 private:
  double Elapsed() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }

  /// The linear solver of Options (kept while the options ask for the same type; its
  /// symbolic analysis then carries over to the next solve).
  void SetLinearSolver() {
    LinearSolverType type = options_->linear_solver;
    if (type == LinearSolverType::kAuto)
      type = nc_ <= options_->dense_threshold ? LinearSolverType::kDenseLU
                                              : LinearSolverType::kUmfpack;
    if (!linear_solver_ || linear_solver_->type() != type) {
      linear_solver_ = ncp::internal::MakeLinearSolver(type);
      normal_solver_.reset();
      factorized_once_ = normal_factorized_once_ = false;
    }
    summary_->linear_solver_used = type;
    if (type == LinearSolverType::kDenseLU) ReserveReduced();
    symbolic_before_ = linear_solver_->symbolic_factorizations();
  }

  /// ReducedDirection's storage for its largest system, all contacts coupled (the dense
  /// J of the same size is formed anyway): its size then follows the coupled set
  /// without allocating.
  void ReserveReduced() {
    const Eigen::Index n = static_cast<Eigen::Index>(d_) * nc_;
    if (reduced_storage_.size() < n * n) reduced_storage_.resize(n * n);
    if (reduced_rhs_.size() < n) {
      reduced_rhs_.resize(n);
      reduced_solution_.resize(n);
    }
    coupled_.reserve(static_cast<size_t>(nc_));
    reduced_lu_.Reserve(n);
  }

  /// The hybrid's attempts (or the one formulation asked for) until one ends the solve.
  Termination RunAttempts() {
    Termination status = Termination::kConverged;
    for (const auto& [formulation, rho_factor] :
         internal::AttemptSequence(options_->formulation)) {
      if (best_error_ <= options_->tolerance) break;
      ++summary_->attempts;
      summary_->formulation_final = formulation;
      status = RunAttempt(formulation, rho_factor);
      if (status == Termination::kConverged || status == Termination::kMaxIterations ||
          status == Termination::kTimeLimit || status == Termination::kNonFiniteValues)
        break;
      // The first attempt of the hybrid stalled: try Gauss-Seidel before the next one.
      if (summary_->attempts == 1 && options_->formulation == Formulation::kHybrid &&
          GaussSeidelTrial())
        return Termination::kConverged;
    }
    return status;
  }

  /// NaturalMapError(problem_, r) (error.hpp) with u = W r + q in a kept buffer.
  double Error(const Vector& r) {
    u_.noalias() = problem_.W * r;
    u_ += problem_.q;
    return NaturalMapResidual(d_, problem_.mu, r, u_) / (1.0 + q_norm_);
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
    if (options_->gauss_seidel_sweeps == 0) return;
    Vector r = best_r_;
    for (int k = 0;
         k < options_->gauss_seidel_sweeps && best_error_ > options_->tolerance; ++k) {
      internal::GaussSeidelSweep(problem_, W_, rho_, &r);
      ++summary_->gauss_seidel_sweeps;
      const double error = Error(r);
      if (!std::isfinite(error)) return;
      if (error < best_error_) {
        best_error_ = error;
        best_r_ = r;
      }
    }
  }

  /// Options::gauss_seidel_fallback_sweeps projected Gauss-Seidel sweeps from best_r_, as
  /// a side trial: true (best_r_ replaced) when they reach the tolerance; otherwise their
  /// best point is kept apart (gs_r_, gs_error_) and the Newton attempts go on from
  /// best_r_. The sweeps stop early when the error, tested every kCheckEvery sweeps, has
  /// not halved over kHalvingWindow sweeps (Gauss-Seidel converges linearly: a slow rate
  /// will not reach the tolerance within the budget), or at the time limit.
  bool GaussSeidelTrial() {
    constexpr int kCheckEvery = 10, kHalvingWindow = 200;
    Vector r = best_r_;
    gs_error_ = best_error_;
    double window_start_error = gs_error_;
    for (int k = 1; k <= options_->gauss_seidel_fallback_sweeps; ++k) {
      if (options_->max_time_s > 0.0 && Elapsed() > options_->max_time_s) break;
      internal::GaussSeidelSweep(problem_, W_, rho_, &r);
      ++summary_->fallback_sweeps;
      if (k % kCheckEvery != 0) continue;
      const double error = Error(r);
      if (!std::isfinite(error)) break;
      if (error < gs_error_) {
        gs_error_ = error;
        gs_r_ = r;
      }
      if (gs_error_ <= options_->tolerance) {
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
    u_.noalias() = problem_.W * r;
    u_ += problem_.q;
    phi->resize(r.size());
    const double s = options_->rho_scale * rho_factor;
    for (int a = 0; a < nc_; ++a) {
      const double* ra = r.data() + d_ * a;
      const double* ua = u_.data() + d_ * a;
      double* pa = phi->data() + d_ * a;
      internal::EvaluateLaw(formulation, d_, problem_.mu[a], rho_[a], s, ra, ua, pa,
                            &A_[a], &B_[a]);
    }
    return 0.5 * phi->squaredNorm();
  }

  /// The Newton direction of the shifted matrix, (J + delta I) d = -phi with
  /// delta = max(regularization, min(shift_error_cap, error)) max(1, max |J_ii|), error
  /// the natural-map error of the iterate (Options::shift_error_cap: the step stays
  /// defined where J is singular, as when sticking contacts make J = rho W with W
  /// rank-deficient, and bounded along W's near-null directions), kept when it passes the
  /// inexact-Newton test
  /// ||J d + phi|| <= eta ||phi||, eta = Options::newton_residual < 1, which makes d a
  /// descent direction of psi: grad psi' d = phi' (J d + phi) - ||phi||^2 < 0. Otherwise
  /// the Levenberg-Marquardt direction (J'J + m I) d = -J' phi, m = max(||phi||,
  /// regularization) (Yamashita & Fukushima 2001), a descent direction for any m > 0.
  /// Measured on data/fc3d: one shifted factorization per step instead of J
  /// first and J + delta I after a failure took Capsules-i101-404 from 111 steps, 0.45 s
  /// to 104 steps, 0.27 s, with the same steps on the other 14 problems. false: both
  /// failed. J and J + delta I keep their patterns (and storage) from solve to solve.
  bool Direction(const Vector& phi, double error, Vector* direction) {
    const double relative_shift =
        std::max(options_->regularization, std::min(options_->shift_error_cap, error));
    const double delta = relative_shift * std::max(1.0, LargestJacobianDiagonal());
    bool solved = false, assembled = false;
    if (summary_->linear_solver_used == LinearSolverType::kDenseLU && SplitDecoupled()) {
      solved = ReducedDirection(delta, phi, direction);
    } else {
      AssembleShifted(delta);
      assembled = true;
      const bool first = !factorized_once_;
      factorized_once_ = true;
      rhs_ = -phi;
      solved = linear_solver_->Analyze(shifted_, first) &&
               linear_solver_->Factorize(shifted_) &&
               linear_solver_->Solve(rhs_, direction);
    }
    if (solved && direction->allFinite() &&
        JacobianResidualNorm(*direction, phi) <= options_->newton_residual * phi.norm())
      return true;
    if (!assembled) W_.AssembleJacobian(A_, B_, &J_);
    ++summary_->linear_solver_failures;
    ++summary_->levenberg_marquardt_steps;
    normal_matrix_ = SparseMatrix(J_.transpose()) * J_;
    const double m = std::max(phi.norm(), options_->regularization);
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

  /// max_i |J_ii| of J = A + B W, from the diagonal blocks A_a + B_a W_aa.
  double LargestJacobianDiagonal() const {
    double largest = 0.0;
    for (int a = 0; a < nc_; ++a) {
      Block Jaa = B_[a] * W_.Diagonal(a);
      Jaa += A_[a];
      largest = std::max(largest, Jaa.diagonal().head(d_).cwiseAbs().maxCoeff());
    }
    return largest;
  }

  /// J_ = A + B W and shifted_ = J_ + delta I (patterns and storage kept between calls).
  void AssembleShifted(double delta) {
    W_.AssembleJacobian(A_, B_, &J_);
    if (shifted_.nonZeros() != J_.nonZeros() || shifted_.rows() != J_.rows())
      shifted_ = J_;
    std::copy(J_.valuePtr(), J_.valuePtr() + J_.nonZeros(), shifted_.valuePtr());
    for (int i = 0; i < shifted_.rows(); ++i) shifted_.coeffRef(i, i) += delta;
  }

  /// ||J d + phi|| with J d = A d + B (W d), block by block (J itself not needed).
  double JacobianResidualNorm(const Vector& d, const Vector& phi) {
    Wd_.noalias() = problem_.W * d;
    double sum = 0.0;
    for (int a = 0; a < nc_; ++a) {
      Eigen::Vector3d da = Eigen::Vector3d::Zero(), wa = Eigen::Vector3d::Zero();
      da.head(d_) = d.segment(d_ * a, d_);
      wa.head(d_) = Wd_.segment(d_ * a, d_);
      const Eigen::Vector3d row = A_[a] * da + B_[a] * wa;
      sum += (row.head(d_) + phi.segment(d_ * a, d_)).squaredNorm();
    }
    return std::sqrt(sum);
  }

  /// coupled_: the contacts whose block B_a is not zero, position_[a] their place among
  /// them (-1 for the others: the decoupled contacts). True when some contact is
  /// decoupled.
  bool SplitDecoupled() {
    coupled_.clear();
    position_.assign(static_cast<size_t>(nc_), -1);
    for (int a = 0; a < nc_; ++a)
      if (!B_[a].isZero(0.0)) {
        position_[static_cast<size_t>(a)] = static_cast<int>(coupled_.size());
        coupled_.push_back(a);
      }
    return static_cast<int>(coupled_.size()) < nc_;
  }

  /// The direction of (J + delta I) d = -phi with the decoupled contacts eliminated
  /// (SplitDecoupled). Row a of J is A_a e_a + B_a W_a, so a contact with B_a = 0 (e.g.
  /// Alart-Curnier at a separated contact, Phi_a = r_a) has (A_a + delta I) d_a = -phi_a
  /// on its own, and the coupled contacts C solve the dense system
  ///   sum_{b in C} (J_ab + delta I [a = b]) d_b = -phi_a - B_a sum_{b not in C} W_ab
  ///   d_b.
  /// Exact block elimination (J is block triangular with the decoupled contacts first):
  /// the direction of the full system with a dense LU over the coupled contacts only (2/3
  /// (d |C|)^3 flops instead of 2/3 (d n_c)^3). false when a system is singular.
  bool ReducedDirection(double delta, const Vector& phi, Vector* direction) {
    direction->resize(phi.size());
    for (int a = 0; a < nc_; ++a) {
      if (position_[static_cast<size_t>(a)] >= 0) continue;
      Block shifted_block = A_[a] + delta * Block::Identity();
      for (int i = d_; i < 3; ++i) shifted_block(i, i) = 1.0;  // the padding of d = 2
      const Eigen::FullPivLU<Block> lu(shifted_block);
      if (!lu.isInvertible()) return false;
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      rhs.head(d_) = -phi.segment(d_ * a, d_);
      direction->segment(d_ * a, d_) = lu.solve(rhs).head(d_);
    }
    // The system in storage that only grows (its size follows the coupled set).
    const Eigen::Index n = d_ * static_cast<Eigen::Index>(coupled_.size());
    if (reduced_storage_.size() < n * n) reduced_storage_.resize(n * n);
    if (reduced_rhs_.size() < n) {
      reduced_rhs_.resize(n);
      reduced_solution_.resize(n);
    }
    Eigen::Map<DenseMatrix> reduced(reduced_storage_.data(), n, n);
    auto reduced_rhs = reduced_rhs_.head(n);
    auto reduced_solution = reduced_solution_.head(n);
    reduced.setZero();
    for (size_t i = 0; i < coupled_.size(); ++i) {
      const int a = coupled_[i];
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      rhs.head(d_) = -phi.segment(d_ * a, d_);
      Eigen::Vector3d decoupled_motion =
          Eigen::Vector3d::Zero();  // sum_{b not in C} W_ab d_b
      for (int k = W_.RowBegin(a); k < W_.RowEnd(a); ++k) {
        const int b = W_.Column(k), j = position_[static_cast<size_t>(b)];
        if (j < 0) {
          Eigen::Vector3d db = Eigen::Vector3d::Zero();
          db.head(d_) = direction->segment(d_ * b, d_);
          decoupled_motion += W_.BlockAt(k) * db;
          continue;
        }
        Block Jab = B_[a] * W_.BlockAt(k);
        if (b == a) Jab += A_[a] + delta * Block::Identity();
        reduced.block(d_ * static_cast<Eigen::Index>(i), d_ * j, d_, d_) =
            Jab.topLeftCorner(d_, d_);
      }
      rhs -= B_[a] * decoupled_motion;
      reduced_rhs.segment(d_ * static_cast<Eigen::Index>(i), d_) = rhs.head(d_);
    }
    if (n > 0) {
      if (!reduced_lu_.Factorize(reduced)) return false;
      reduced_lu_.Solve(reduced_rhs, reduced_solution);
    }
    for (size_t i = 0; i < coupled_.size(); ++i)
      direction->segment(d_ * coupled_[i], d_) =
          reduced_solution.segment(d_ * static_cast<Eigen::Index>(i), d_);
    return true;
  }

  Termination RunAttempt(Formulation formulation, double rho_factor) {
    Vector& r = r_;
    r = best_r_;
    double psi = Evaluate(formulation, rho_factor, r, &phi_);
    if (!std::isfinite(psi)) return Termination::kNonFiniteValues;
    // psi of the last Options::nonmonotone_window iterates, oldest first.
    recent_psi_.clear();
    recent_psi_.push_back(psi);
    internal::AttemptProgress progress(*options_, best_error_);
    while (true) {
      if (summary_->iterations >= options_->max_iterations)
        return Termination::kMaxIterations;
      if (options_->max_time_s > 0.0 && Elapsed() > options_->max_time_s)
        return Termination::kTimeLimit;
      if (!Direction(phi_, progress.previous_error(), &direction_))
        return Termination::kLinearSolverFailure;
      // Nonmonotone Armijo: psi(r + t d) <= max(recent psi) - 2 beta t psi(r).
      const double reference = *std::max_element(recent_psi_.begin(), recent_psi_.end());
      double t = 1.0, trial_psi = 0.0;
      bool accepted = false;
      for (int i = 0; i <= options_->max_backtracks; ++i, t *= 0.5) {
        trial_ = r + t * direction_;
        trial_psi = Evaluate(formulation, rho_factor, trial_, &trial_phi_);
        if (std::isfinite(trial_psi) &&
            trial_psi <= reference - 2.0 * options_->armijo_beta * t * psi) {
          accepted = true;
          break;
        }
        ++summary_->backtracks;
      }
      if (!accepted) return Termination::kLineSearchFailure;
      // Evaluate() of the accepted trial left A_, B_ at the new iterate.
      r.swap(trial_);
      phi_.swap(trial_phi_);
      psi = trial_psi;
      if (static_cast<int>(recent_psi_.size()) >= options_->nonmonotone_window)
        recent_psi_.erase(recent_psi_.begin());
      recent_psi_.push_back(psi);
      ++summary_->iterations;
      const double error = Error(r);
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
    if (options_->log_to_stderr)
      std::fprintf(stderr, "fc %4d %-13s error %.3e psi %.3e step %.3g\n",
                   record.iteration, ToString(formulation), error, psi, t);
  }

  /// Summary::message, written into its kept storage.
  void SetMessage(Termination status) const {
    std::string& message = summary_->message;
    const bool usable = internal::Usable(status);
    internal::ErrorReport(*options_, usable, summary_->final_error, &message);
    char count[48];
    std::snprintf(count, sizeof count, " after %d Newton steps", summary_->iterations);
    message += count;
    if (!usable) (message += "; last attempt ended: ") += ToString(status);
  }

  const FrictionProblem& problem_;
  internal::BlockDelassus W_;
  const Options* options_ = nullptr;  // of the current Run
  Summary* summary_ = nullptr;        // of the current Run
  int d_, nc_;
  std::vector<Block> A_, B_;
  std::vector<internal::Rho> rho_;
  SparseMatrix J_, shifted_, normal_matrix_;
  std::unique_ptr<ncp::internal::LinearSolver> normal_solver_;
  bool normal_factorized_once_ = false;
  std::unique_ptr<ncp::internal::LinearSolver> linear_solver_;
  bool factorized_once_ = false;
  int symbolic_before_ = 0;
  double q_norm_ = 0.0;
  Vector best_r_;
  double best_error_ = 0.0;
  Vector gs_r_;  // best point of GaussSeidelTrial (when it did not converge)
  double gs_error_ = std::numeric_limits<double>::infinity();
  Vector u_, r_, phi_, trial_phi_, direction_, trial_, rhs_, Wd_;  // work vectors
  std::vector<double> recent_psi_;
  std::vector<int> coupled_, position_;    // SplitDecoupled
  Vector reduced_storage_;                 // ReducedDirection's system over coupled_
  Vector reduced_rhs_, reduced_solution_;  // (their first d |coupled_| entries)
  ncp::internal::DenseLU reduced_lu_;
  Clock::time_point start_;
};

}  // namespace internal

Solver::Solver(FrictionProblem problem) : problem_(std::move(problem)) {
  problem_.Validate();
  W0_ = problem_.W;
  newton_ = std::make_unique<internal::NewtonSolver>(problem_);
}

Solver::~Solver() = default;

void Solver::ScaleW(double scale) {
  if (!std::isfinite(scale))
    throw std::invalid_argument("ncp::fc::Solver::ScaleW: scale must be finite, got " +
                                std::to_string(scale));
  if (scale == scale_) return;  // (W already scale W0)
  if (!newton_->ScaleW(scale, W0_, &problem_.W))
    throw std::invalid_argument("ncp::fc::Solver::ScaleW: scale " +
                                std::to_string(scale) +
                                " times W has a non-finite entry");
  scale_ = scale;
}

void Solver::SetQ(const Vector& q) {
  if (q.size() != problem_.size())
    throw std::invalid_argument("ncp::fc::Solver::SetQ: q must have " +
                                std::to_string(problem_.size()) + " entries, got " +
                                std::to_string(q.size()));
  if (!q.allFinite())
    throw std::invalid_argument("ncp::fc::Solver::SetQ: q has a non-finite entry");
  problem_.q = q;
}

void Solver::Solve(const Options& options, Vector* r, Summary* summary) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("ncp::fc::Options: " + why);
  if (!r || !summary)
    throw std::invalid_argument("ncp::fc::Solve: r and summary must not be null");
  if (r->size() == 0) r->setZero(problem_.size());
  if (r->size() != problem_.size())
    throw std::invalid_argument("ncp::fc::Solve: start point must have " +
                                std::to_string(problem_.size()) + " entries, got " +
                                std::to_string(r->size()));
  if (!r->allFinite())
    throw std::invalid_argument("ncp::fc::Solve: start point not finite");
  internal::ResetSummary(options, problem_.num_contacts, summary);
  const auto start = Clock::now();
  newton_->Run(options, r, summary);
  summary->total_time_s = std::chrono::duration<double>(Clock::now() - start).count();
}

void Solve(const Options& options, const FrictionProblem& problem, Vector* r,
           Summary* summary) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("ncp::fc::Options: " + why);
  Solver solver(problem);
  solver.Solve(options, r, summary);
}

}  // namespace ncp::fc
