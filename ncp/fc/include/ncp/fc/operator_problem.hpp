/// \file operator_problem.hpp
/// The frictional contact problem of problem.hpp with the Delassus operator W given by
/// its action r -> W r only (matrix-free), and its semismooth Newton solver.
///
/// For Delassus operators too large to form: W = G M^-1 G' of a finite-element body with
/// 10^4 contacts is a dense matrix of (3 10^4)^2 entries, while one product with it costs
/// one sparse solve with M. The solver (operator_solver.cpp) is the semismooth Newton of
/// solver.hpp with the same formulations and the same hybrid sequence of attempts,
/// Phi(r, W r + q) = 0 with J = A + B W, but the Newton equation (J + delta I) d = -Phi
/// is solved by GMRES, right preconditioned by the block-diagonal matrix of blocks A_a +
/// B_a D_a + delta I (D_a = diag(W_aa) as given by the caller), to the relative residual
///     eta_k = min(Options::newton_residual, max(||Phi_k|| / ||Phi_0||, 0.1 tol / e_k))
/// (inexact Newton with a forcing term that goes to zero with Phi: superlinear, Eisenstat
/// and Walker 1996; never finer than a tenth of the tolerance relative to the current
/// natural-map error e_k). ||J d + Phi|| <= eta_k ||Phi|| < ||Phi|| makes d a descent
/// direction of psi = ||Phi||^2 / 2; the nonmonotone Armijo search of solver.hpp follows,
/// with W (r + t d) = W r + t W d (one product per Newton step, none per backtrack).
/// Converged on the natural-map error of error.hpp (same measure and tolerance as the
/// matrix solvers), checked with u = W r + q recomputed, not updated.
/// Cost per Newton step: (GMRES iterations + 2) products with W.
///
/// Distributed (OperatorProblem::reduction set): the contacts are split among processes,
/// each holding the r, q, mu and diagonal of its own contacts and W acting on them
/// (apply_W collective: every part calls it at the same point). Every dot product, norm
/// and maximum of the Newton and of GMRES is the local one reduced over the parts; with
/// the same reduced value on every part, every branch (line search, GMRES restarts, the
/// hybrid's attempts, the time limit) is taken alike and the small GMRES work (Hessenberg
/// matrix, Givens rotations) is repeated identically on every part. Empty (the default):
/// one part, the serial solver, bit for bit.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "ncp/fc/solver.hpp"
#include "ncp/types.hpp"

namespace ncp::fc {

/// Sums and maxima over the parts of a distributed problem, in place on `count` values;
/// each must give the same bits on every part (e.g. every part's values gathered and
/// added in part order), so that every part takes the same decisions. Unset: one part.
struct Reduction {
  std::function<void(double* values, int count)> sum;
  std::function<void(double* values, int count)> max;

  bool distributed() const { return static_cast<bool>(sum); }
  /// The sum (maximum) over the parts of `local`; `local` itself with one part.
  double Sum(double local) const {
    if (sum) sum(&local, 1);
    return local;
  }
  double Max(double local) const {
    if (max) max(&local, 1);
    return local;
  }
};

struct OperatorProblem {
  int dimension = 3;     ///< 2 (normal + 1 tangent) or 3 (normal + 2 tangents)
  int num_contacts = 0;  ///< n_c; W acts on vectors of dimension n_c entries
  /// *Wr = W r (W symmetric positive semidefinite); *Wr is sized by the caller's first
  /// use and may be reused. Called once per GMRES iteration.
  std::function<void(const Vector& r, Vector* Wr)> apply_W;
  /// An approximation of diag(W) (> 0 where W acts), one entry per component: sets rho
  /// per contact (as Formulation::kAlartCurnier from the exact diagonal) and the
  /// preconditioner. Within a factor of a few of the true diagonal is enough.
  Vector diagonal;
  Vector q;          ///< free relative motion, size dimension n_c
  Vector mu;         ///< friction coefficient per contact, >= 0
  std::string name;  ///< for reports
  /// Distributed: this part's contacts only (dimension, num_contacts, q, mu, diagonal
  /// local; apply_W collective) and the reduction over the parts; unset: serial.
  Reduction reduction;

  int size() const { return dimension * num_contacts; }
  /// Throws std::invalid_argument (expected vs actual) unless the sizes agree, apply_W is
  /// set, every entry is finite, every mu >= 0 and every diagonal entry >= 0.
  void Validate() const;
};

/// Solves from *r (empty: r = 0) with semismooth Newton and GMRES (see the file comment).
/// Uses of `options`: formulation, tolerance, max_iterations, max_time_s, rho_scale,
/// armijo_beta, nonmonotone_window, max_backtracks, stall_window, newton_residual,
/// regularization, krylov_max_iterations, log_to_stderr (linear_solver and the
/// Gauss-Seidel settings do not apply). The best iterate is returned in *r; *summary
/// tells how it ended (Summary::krylov_iterations, operator_applications included).
/// Throws std::invalid_argument on invalid options, problem or start point.
void Solve(const Options& options, const OperatorProblem& problem, Vector* r,
           Summary* summary);

namespace internal {
class OperatorNewton;
}

/// Repeated solves of problems of one size (the steps of a time stepper, whose q,
/// diagonal and W change between solves): the Newton and GMRES workspaces - the Jacobian
/// and preconditioner blocks, the work vectors, the Krylov basis of size n x (restart +
/// 1)
/// - are kept, so that a solve of a problem of the previous one's size allocates nothing
/// (the Summary's message and trace reuse their storage; apply_W's own allocations are
/// the caller's). A problem of another size resizes them once. Solve(options, problem, r,
/// summary) above is one OperatorSolver used once; results are the same bit for bit.
class OperatorSolver {
 public:
  OperatorSolver();
  ~OperatorSolver();
  OperatorSolver(const OperatorSolver&) = delete;
  OperatorSolver& operator=(const OperatorSolver&) = delete;

  /// As Solve(options, problem, r, summary) above; `problem` is read during the call
  /// only.
  void Solve(const Options& options, const OperatorProblem& problem, Vector* r,
             Summary* summary);

 private:
  std::unique_ptr<internal::OperatorNewton> newton_;
};

}  // namespace ncp::fc
