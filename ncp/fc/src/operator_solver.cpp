// Alart-Curnier semismooth Newton with GMRES for OperatorProblem (operator_problem.hpp).
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "local_laws.hpp"
#include "ncp/fc/error.hpp"
#include "ncp/fc/operator_problem.hpp"

namespace ncp::fc {

void OperatorProblem::Validate() const {
  // The message is built only when a check fails (Validate runs once per solve).
  auto fail = [this](const std::string& what) {
    throw std::invalid_argument("ncp::fc::OperatorProblem" +
                                (name.empty() ? "" : " '" + name + "'") + ": " + what);
  };
  if (dimension != 2 && dimension != 3)
    fail("dimension must be 2 or 3, got " + std::to_string(dimension));
  if (num_contacts < 0) fail("num_contacts must be >= 0");
  if (!apply_W) fail("apply_W is not set");
  auto check = [&](const Vector& v, Eigen::Index expected, const char* what) {
    if (v.size() != expected)
      fail(what + (" must have " + std::to_string(expected) + " entries, got " +
                   std::to_string(v.size())));
    if (!v.allFinite()) fail(what + std::string(" has non-finite entries"));
  };
  check(q, size(), "q");
  check(diagonal, size(), "diagonal");
  check(mu, num_contacts, "mu");
  if ((mu.array() < 0.0).any()) fail("mu must be >= 0");
  if ((diagonal.array() < 0.0).any()) fail("diagonal must be >= 0");
}

using Clock = std::chrono::steady_clock;

namespace internal {

/// GMRES iterations between restarts.
constexpr int kRestart = 50;

/// The Newton-GMRES solver, kept between solves (OperatorSolver): every vector and block
/// of a solve is a member, sized by the first solve of a problem size and reused after.
/// Run() shares its state between the attempts of the hybrid.
class OperatorNewton {
 public:
  /// From *r through the attempts of options.formulation (kHybrid: AC, then FB, NM and
  /// other rho when one stalls, as solver.hpp), each from the best iterate so far; the
  /// best iterate is returned in *r.
  void Run(const Options& options, const OperatorProblem& problem, Vector* r,
           Summary* summary) {
    options_ = &options;
    problem_ = &problem;
    summary_ = summary;
    start_ = Clock::now();
    Resize(problem.dimension, problem.num_contacts);
    q_norm_ = Norm(problem.q);
    ComputeRho();
    MultiplyW(*r, &u_);
    u_ += problem.q;
    double error = Error(*r, u_);
    summary_->initial_error = error;
    Termination status =
        std::isfinite(error) ? Termination::kConverged : Termination::kNonFiniteValues;
    for (const auto& [formulation, rho_factor] :
         internal::AttemptSequence(options.formulation)) {
      if (status == Termination::kNonFiniteValues || error <= options.tolerance) break;
      if (summary_->attempts++ > 0) {  // restart on u = W r + q of the best iterate
        MultiplyW(*r, &u_);
        u_ += problem.q;
      }
      summary_->formulation_final = formulation;
      status = Iterate(formulation, rho_factor, r, &error);
      if (status == Termination::kConverged || status == Termination::kMaxIterations ||
          status == Termination::kTimeLimit)
        break;
    }
    summary_->final_error = error;
    if (error <= options.tolerance) status = Termination::kConverged;
    status = internal::RoundoffFloorStatus(options, status, error);
    summary_->termination = status;
    internal::ErrorReport(options, internal::Usable(status), error, &summary_->message);
    char counts[160];
    std::snprintf(counts, sizeof counts,
                  " after %d Newton steps, %d GMRES iterations, %d attempts",
                  summary_->iterations, summary_->krylov_iterations, summary_->attempts);
    summary_->message += counts;
    if (!internal::Usable(status))
      (summary_->message += "; last ended: ") += ToString(status);
  }

 private:
  /// The blocks and the GMRES basis for d-dimensional contacts, nc of them, with the
  /// restart length of the options (nothing allocated when the sizes are unchanged).
  void Resize(int d, int nc) {
    d_ = d;
    nc_ = nc;
    A_.resize(static_cast<size_t>(nc));
    B_.resize(static_cast<size_t>(nc));
    P_inverse_.resize(static_cast<size_t>(nc));
    const int m = std::min(kRestart, options_->krylov_max_iterations);
    krylov_basis_.resize(static_cast<Eigen::Index>(d) * nc, m + 1);
    projection_.resize(m + 1);
  }

  /// rho per contact from the given diagonal (internal::RhoFromDiagonal).
  void ComputeRho() {
    const Vector& diagonal = problem_->diagonal;
    const double largest = Max(diagonal.size() ? diagonal.maxCoeff() : 0.0);
    rho_.resize(static_cast<size_t>(nc_));
    for (int a = 0; a < nc_; ++a)
      rho_[static_cast<size_t>(a)] = internal::RhoFromDiagonal(
          d_, diagonal.data() + d_ * a, largest > 0.0 ? 1.0 / largest : 1.0);
  }

  void MultiplyW(const Vector& r, Vector* Wr) {
    problem_->apply_W(r, Wr);
    ++summary_->operator_applications;
  }

  // Sums and maxima over the parts of a distributed problem (OperatorProblem::reduction;
  // the local value itself when serial: the serial bits, Eigen's norm() being
  // sqrt(squaredNorm())).
  double Sum(double local) const { return problem_->reduction.Sum(local); }
  double Max(double local) const { return problem_->reduction.Max(local); }
  template <typename A, typename B>
  double Dot(const A& a, const B& b) const {
    return Sum(a.dot(b));
  }
  template <typename A>
  double Norm(const A& a) const {
    return std::sqrt(Sum(a.squaredNorm()));
  }
  // True on every part if `local` holds on any.
  bool Any(bool local) const { return Max(local ? 1.0 : 0.0) > 0.0; }

  double Error(const Vector& r, const Vector& u) const {
    return std::sqrt(Sum(NaturalMapSquaredResidual(d_, problem_->mu, r, u))) /
           (1.0 + q_norm_);
  }

  /// Phi(r, u) of the attempt's formulation into *phi, with the blocks A_, B_; returns
  /// psi.
  double Evaluate(const Vector& r, const Vector& u, Vector* phi) {
    phi->resize(r.size());
    const double scale = options_->rho_scale * rho_factor_;
    for (int a = 0; a < nc_; ++a)
      internal::EvaluateLaw(formulation_, d_, problem_->mu(a), rho_[a], scale,
                            r.data() + d_ * a, u.data() + d_ * a, phi->data() + d_ * a,
                            &A_[a], &B_[a]);
    return 0.5 * Sum(phi->squaredNorm());
  }

  /// The shift delta = regularization max(1, max |J_aa|) of solver.cpp (J's diagonal
  /// taken as that of A + B D), and the inverse blocks of the preconditioner A_a + B_a
  /// D_a + delta I. (The blocks are formed in P_inverse_ and inverted in place.)
  void Precondition() {
    double largest = 1.0;
    for (int a = 0; a < nc_; ++a) {
      Block D = Block::Identity();
      for (int i = 0; i < d_; ++i) D(i, i) = problem_->diagonal(d_ * a + i);
      P_inverse_[a] = A_[a] + B_[a] * D;
      for (int i = 0; i < d_; ++i)
        largest = std::max(largest, std::abs(P_inverse_[a](i, i)));
    }
    delta_ = options_->regularization * Max(largest);
    for (int a = 0; a < nc_; ++a) {
      Block P = P_inverse_[a] + delta_ * Block::Identity();
      if (d_ == 2) P(2, 2) = 1.0;
      Eigen::FullPivLU<Block> lu(P);
      P_inverse_[a] = lu.isInvertible() ? Block(lu.inverse()) : Block(Block::Identity());
    }
  }

  /// y = P^-1 x (x a vector or a column of the Krylov basis).
  void ApplyPreconditioner(const Eigen::Ref<const Vector>& x, Vector* y) const {
    y->resize(x.size());
    for (int a = 0; a < nc_; ++a) {
      Eigen::Vector3d xa = Eigen::Vector3d::Zero();
      for (int i = 0; i < d_; ++i) xa(i) = x(d_ * a + i);
      const Eigen::Vector3d ya = P_inverse_[a] * xa;
      for (int i = 0; i < d_; ++i) (*y)(d_ * a + i) = ya(i);
    }
  }

  /// y = (J + delta I) x = A x + B (W x) + delta x.
  void ApplyJacobian(const Vector& x, Vector* y) {
    MultiplyW(x, &Wx_);
    y->resize(x.size());
    for (int a = 0; a < nc_; ++a) {
      Eigen::Vector3d xa = Eigen::Vector3d::Zero(), wa = Eigen::Vector3d::Zero();
      for (int i = 0; i < d_; ++i) {
        xa(i) = x(d_ * a + i);
        wa(i) = Wx_(d_ * a + i);
      }
      const Eigen::Vector3d ya = A_[a] * xa + B_[a] * wa + delta_ * xa;
      for (int i = 0; i < d_; ++i) (*y)(d_ * a + i) = ya(i);
    }
  }

  /// H(0..k, k) and w <- w minus its projection on the basis V(:, 0..k)
  /// (Options::krylov_classical_gram_schmidt: classical Gram-Schmidt twice, one reduction
  /// of the k + 1 dot products per pass; otherwise modified Gram-Schmidt).
  void Orthogonalize(int k, Vector* w) {
    Eigen::MatrixXd& V = krylov_basis_;
    Eigen::MatrixXd& H = hessenberg_;
    if (!options_->krylov_classical_gram_schmidt) {
      for (int i = 0; i <= k; ++i) {
        H(i, k) = Dot(V.col(i), *w);
        *w -= H(i, k) * V.col(i);
      }
      return;
    }
    H.col(k).head(k + 1).setZero();
    auto h = projection_.head(k + 1);  // (sized in Resize: no allocation)
    for (int pass = 0; pass < 2; ++pass) {
      h.noalias() = V.leftCols(k + 1).transpose() * *w;
      if (problem_->reduction.sum)
        problem_->reduction.sum(h.data(), static_cast<int>(k + 1));
      w->noalias() -= V.leftCols(k + 1) * h;
      H.col(k).head(k + 1) += h;
    }
  }

  /// Right-preconditioned restarted GMRES (modified Gram-Schmidt, Givens rotations) for
  /// (J + delta I) d = b from d = 0, until ||b - (J + delta I) d|| <= eta ||b|| or
  /// krylov_max_iterations. Returns the relative residual reached.
  double Gmres(const Vector& b, double eta, Vector* d) {
    const Eigen::Index n = b.size();
    d->setZero(n);
    const double b_norm = Norm(b);
    if (b_norm == 0.0) return 0.0;
    Vector &residual = residual_, &w = w_, &z = z_;
    residual = b;
    double relative = 1.0;
    int used = 0;
    while (used < options_->krylov_max_iterations) {
      const int m = std::min(kRestart, options_->krylov_max_iterations - used);
      const double beta = Norm(residual);
      // The basis has the columns of a full cycle (Resize); the last cycle may use fewer.
      Eigen::MatrixXd& V = krylov_basis_;
      Eigen::MatrixXd& H = hessenberg_;
      H.setZero(m + 1, m);
      Vector &g = givens_rhs_, &cs = givens_cos_, &sn = givens_sin_;
      g.setZero(m + 1);
      cs.resize(m);
      sn.resize(m);
      V.col(0) = residual / beta;
      g(0) = beta;
      int k = 0;
      for (; k < m; ++k) {
        ApplyPreconditioner(V.col(k), &z);
        ApplyJacobian(z, &w);
        Orthogonalize(k, &w);
        H(k + 1, k) = Norm(w);
        if (H(k + 1, k) > 0.0) V.col(k + 1) = w / H(k + 1, k);
        for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
          const double t = cs(i) * H(i, k) + sn(i) * H(i + 1, k);
          H(i + 1, k) = -sn(i) * H(i, k) + cs(i) * H(i + 1, k);
          H(i, k) = t;
        }
        const double h = std::hypot(H(k, k), H(k + 1, k));
        cs(k) = h > 0.0 ? H(k, k) / h : 1.0;
        sn(k) = h > 0.0 ? H(k + 1, k) / h : 0.0;
        H(k, k) = h;
        H(k + 1, k) = 0.0;
        g(k + 1) = -sn(k) * g(k);
        g(k) *= cs(k);
        ++used;
        ++summary_->krylov_iterations;
        relative = std::abs(g(k + 1)) / b_norm;
        if (relative <= eta || H(k, k) == 0.0) {
          ++k;
          break;
        }
      }
      // d += P^-1 V_k y, H_k y = g_k (upper triangular).
      y_.resize(m + 1);
      auto y = y_.head(k);
      y = g.head(k);
      H.topLeftCorner(k, k).triangularView<Eigen::Upper>().solveInPlace(y);
      combination_.noalias() = V.leftCols(k) * y;
      ApplyPreconditioner(combination_, &z);
      *d += z;
      if (relative <= eta) break;
      ApplyJacobian(*d, &w);  // true residual for the restart
      residual = b - w;
      relative = Norm(residual) / b_norm;
      if (relative <= eta) break;
    }
    return relative;
  }

  /// Forcing term eta of the inexact Newton step ||J d + Phi|| <= eta ||Phi||:
  /// superlinear (||Phi|| / ||Phi_0||), but no finer than the error asks - a tenth of the
  /// tolerance relative to the current error (the last Newton steps of a solve to 1e-15
  /// otherwise took two thirds of all GMRES iterations).
  double ForcingTerm(double phi_norm, double phi0, double previous_error) const {
    const double needed =
        previous_error > 0.0 ? 0.1 * options_->tolerance / previous_error : 0.0;
    return std::min(options_->newton_residual,
                    std::max(phi0 > 0.0 ? phi_norm / phi0 : 1.0, needed));
  }

  /// Nonmonotone Armijo along direction_ from (r_, u_) with Wd_ = W d:
  /// psi(r + t d) <= max(recent psi) - 2 beta t psi(r), t = 2^-i, i <= max_backtracks.
  /// The accepted point in trial_r_, trial_u_, trial_phi_; false when no t passed.
  bool LineSearch(double psi, double* t, double* trial_psi) {
    const double reference = *std::max_element(recent_psi_.begin(), recent_psi_.end());
    *t = 1.0;
    for (int i = 0; i <= options_->max_backtracks; ++i, *t *= 0.5) {
      trial_r_ = r_ + *t * direction_;
      trial_u_ = u_ + *t * Wd_;
      *trial_psi = Evaluate(trial_r_, trial_u_, &trial_phi_);
      if (std::isfinite(*trial_psi) &&
          *trial_psi <= reference - 2.0 * options_->armijo_beta * *t * psi)
        return true;
      ++summary_->backtracks;
    }
    return false;
  }

  /// One attempt: the Newton loop from (r, u_ = W r + q) with error *error; keeps the
  /// best iterate in *r_best, *error_best.
  Termination Iterate(Formulation formulation, double rho_factor, Vector* r_best,
                      double* error_best) {
    formulation_ = formulation;
    rho_factor_ = rho_factor;
    Vector &r = r_, &u = u_, &phi = phi_, &direction = direction_, &Wd = Wd_;
    r = *r_best;
    double psi = Evaluate(r, u, &phi);
    const double phi0 = std::sqrt(2.0 * psi);
    // psi of the last Options::nonmonotone_window iterates, oldest first.
    recent_psi_.clear();
    recent_psi_.push_back(psi);
    internal::AttemptProgress progress(*options_, *error_best);
    while (true) {
      if (summary_->iterations >= options_->max_iterations)
        return Termination::kMaxIterations;
      // (Distributed: the time limit is reached when it is on any part.)
      if (options_->max_time_s > 0.0 &&
          Any(std::chrono::duration<double>(Clock::now() - start_).count() >
              options_->max_time_s))
        return Termination::kTimeLimit;
      Precondition();
      const double eta =
          ForcingTerm(std::sqrt(2.0 * psi), phi0, progress.previous_error());
      minus_phi_ = -phi;
      const double reached = Gmres(minus_phi_, eta, &direction);
      if (!(reached < 1.0) || Any(!direction.allFinite())) {
        ++summary_->linear_solver_failures;
        return Termination::kLinearSolverFailure;
      }
      MultiplyW(direction, &Wd);
      double t = 1.0, trial_psi = 0.0;
      if (!LineSearch(psi, &t, &trial_psi)) return Termination::kLineSearchFailure;
      r.swap(trial_r_);
      u.swap(trial_u_);
      phi.swap(trial_phi_);
      psi = trial_psi;
      recent_psi_.push_back(psi);
      if (static_cast<int>(recent_psi_.size()) > options_->nonmonotone_window)
        recent_psi_.erase(recent_psi_.begin());
      ++summary_->iterations;
      double error = Error(r, u);
      if (internal::Converged(*options_, error,
                              progress.previous_error())) {  // confirm on u = W r + q
        MultiplyW(r, &u);
        u += problem_->q;
        error = Error(r, u);
        psi = Evaluate(r, u, &phi);
      }
      if (!std::isfinite(error)) return Termination::kNonFiniteValues;
      if (options_->log_to_stderr)
        std::fprintf(stderr,
                     "fc-op %4d %-13s error %.3e psi %.3e step %.3g eta %.2g GMRES %.2e "
                     "(%d iterations in all)\n",
                     summary_->iterations, ToString(formulation_), error, psi, t, eta,
                     reached, summary_->krylov_iterations);
      const Termination status = progress.Update(error, r, error_best, r_best);
      if (status != Termination::kNotSolved) return status;
    }
  }

  // Of the current Run.
  const Options* options_ = nullptr;
  const OperatorProblem* problem_ = nullptr;
  Summary* summary_ = nullptr;
  Clock::time_point start_;
  int d_ = 3, nc_ = 0;
  std::vector<Block> A_, B_, P_inverse_;
  std::vector<internal::Rho> rho_;
  Formulation formulation_ = Formulation::kAlartCurnier;
  double rho_factor_ = 1.0;
  double delta_ = 0.0;
  double q_norm_ = 0.0;  // ||q||_2 (over all parts)
  // Newton: iterate, motion u = W r + q, Phi, direction, trial point, psi window.
  Vector r_, u_, phi_, minus_phi_, direction_, Wd_, trial_r_, trial_u_, trial_phi_;
  std::vector<double> recent_psi_;
  // GMRES: basis, Hessenberg matrix, Givens rotations and right side, work vectors.
  Eigen::MatrixXd krylov_basis_, hessenberg_;
  Vector givens_rhs_, givens_cos_, givens_sin_, y_, combination_, residual_, w_, z_, Wx_,
      projection_;
};

}  // namespace internal

OperatorSolver::OperatorSolver()
    : newton_(std::make_unique<internal::OperatorNewton>()) {}
OperatorSolver::~OperatorSolver() = default;

void OperatorSolver::Solve(const Options& options, const OperatorProblem& problem,
                           Vector* r, Summary* summary) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("ncp::fc::Options: " + why);
  // Distributed: the parts check their own contacts and all throw if one fails (no part
  // may go on into the collective products alone).
  try {
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
    why.clear();
  } catch (const std::invalid_argument& e) {
    why = e.what();
  }
  if (problem.reduction.Max(why.empty() ? 0.0 : 1.0) > 0.0)
    throw std::invalid_argument(
        why.empty() ? "ncp::fc::Solve: the problem is invalid on another part" : why);
  internal::ResetSummary(
      options, static_cast<int>(problem.reduction.Sum(problem.num_contacts)), summary);
  summary->formulation_final = options.formulation;
  summary->symbolic_factorizations = summary->krylov_iterations =
      summary->operator_applications = 0;
  const auto start = Clock::now();
  newton_->Run(options, problem, r, summary);
  summary->total_time_s = std::chrono::duration<double>(Clock::now() - start).count();
}

void Solve(const Options& options, const OperatorProblem& problem, Vector* r,
           Summary* summary) {
  OperatorSolver().Solve(options, problem, r, summary);
}

}  // namespace ncp::fc
