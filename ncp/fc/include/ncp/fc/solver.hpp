/// \file solver.hpp
/// Semismooth Newton solvers of the local frictional contact problem (problem.hpp).
///
/// Each formulation writes the Coulomb law of contact alpha as Phi_alpha(r_alpha,
/// u_alpha) = 0 with u = W r + q, so the generalized Jacobian is J = A + B W with A =
/// dPhi/dr and B = dPhi/du block diagonal (one d x d block per contact); J keeps the
/// block pattern of W (plus the diagonal blocks), so the sparse symbolic analysis is done
/// once per solve. The Newton loop is this module's own (ncp's Solver is an MCP solver):
/// J d = -Phi by ncp's internal linear solvers (dense LU or UMFPACK), then a nonmonotone
/// Armijo line search on psi = 1/2 ||Phi||^2 (Grippo, Lampariello, Lucidi 1986) along d,
/// which is a descent direction of psi since grad psi' d = Phi' J d = -||Phi||^2.
/// Convergence is tested on Siconos' natural-map error (error.hpp), not on ||Phi||.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ncp/fc/problem.hpp"
#include "ncp/types.hpp"

namespace ncp::fc {

enum class Formulation {
  /// Alart & Curnier 1991 (Christensen-Pang form), rho_N = rho_scale / W_NN,
  /// rho_T = rho_scale / mean(W_TT) per contact:
  ///   Phi_N = r_N - max(0, r_N - rho_N u_N),
  ///   Phi_T = r_T - P_{B(0, mu max(0, r_N - rho_N u_N))}(r_T - rho_T u_T).
  kAlartCurnier,
  /// Natural map of the De Saxce form, rho = rho_scale / mean(diag W_alpha,alpha):
  ///   Phi = r - P_{C_mu}(r - rho u_hat),  u_hat = u + (mu |u_T|, 0, 0).
  kNaturalMap,
  /// Fischer-Burmeister function of the second-order cone (Fukushima, Luo & Tseng 2001)
  /// on
  /// x = (mu r_N, r_T), y = (u_N + mu |u_T|, mu u_T): Phi = x + y - (x o x + y o
  /// y)^(1/2).
  /// No rho.
  kFischerBurmeister,
  /// Alart-Curnier first; when an attempt stalls (line-search or linear-solver failure,
  /// or
  /// no halving of the error in Options::stall_window iterations) the next attempt of
  /// (Fischer-Burmeister, natural map, AC with rho x10, natural map with rho/10, AC with
  /// rho/10, natural map with rho x10) restarts from the best iterate so far. After the
  /// first attempt, projected Gauss-Seidel sweeps are tried
  /// (Options::gauss_seidel_fallback_sweeps).
  kHybrid,
};

enum class Termination {
  kNotSolved,            ///< Solve() has not run (Summary default)
  kConverged,            ///< NaturalMapError(r) <= Options::tolerance
  kMaxIterations,        ///< Options::max_iterations Newton steps in total
  kTimeLimit,            ///< Options::max_time_s elapsed
  kLineSearchFailure,    ///< no step 2^-i, i <= max_backtracks, met the Armijo test (last
                         ///< attempt)
  kLinearSolverFailure,  ///< J + delta I and J'J + m I both failed (last attempt)
  kStalled,          ///< the error did not halve within stall_window steps (last attempt)
  kNonFiniteValues,  ///< NaN/Inf in Phi or the error
  /// Options::tolerance < NaturalMapError(r) <= Options::acceptable_tolerance, the error
  /// at the round-off of W r + q (a Newton step that did not halve it): as accurate as
  /// double precision allows here, but not the tolerance asked for. Usable
  /// (Summary::IsSolutionUsable).
  kAtRoundoffFloor,
};

const char* ToString(Formulation f);
const char* ToString(Termination t);
/// "ac", "nm", "fb", "hybrid" (as on fc-solve's command line); throws
/// std::invalid_argument.
Formulation ParseFormulation(const std::string& name);

struct Options {
  Formulation formulation = Formulation::kHybrid;
  /// Converged when NaturalMapError(r) = ||r - P_C(r - u_hat)||_2 / (1 + ||q||_2) <=
  /// tolerance.
  double tolerance = 1e-8;
  /// Round-off floor (0: off; else > tolerance): a Newton step that reaches an error at
  /// most acceptable_tolerance without halving the previous one ends the solve with
  /// kAtRoundoffFloor - the error has hit the round-off of W r + q and `tolerance` is out
  /// of reach. For callers that ask for more than they require (contact's step asks 1e-5
  /// of its tolerance and requires the tolerance).
  double acceptable_tolerance = 0.0;
  /// Newton steps in total, over all attempts of the hybrid.
  int max_iterations = 500;
  /// Wall-clock limit in seconds (0: none); checked once per iteration.
  double max_time_s = 0.0;
  /// Projected Gauss-Seidel sweeps (local Alart-Curnier Newton per contact, Jean-Moreau
  /// NSGS) from the start point before the first Newton step; stops early at tolerance.
  /// Off by default: on data/fc3d, 10 sweeps cut BoxesStack1 from 18 to 4
  /// Newton steps but left the hybrid unable to finish Capsules-i101-404 (error 5.9e-6).
  int gauss_seidel_sweeps = 0;
  /// Fallback of the hybrid: when its first attempt (Alart-Curnier) stalls, at most this
  /// many projected Gauss-Seidel sweeps from the best iterate, stopping at tolerance or
  /// when the error no longer halves within 200 sweeps; if they do not converge, the next
  /// Newton attempts go on from the Newton iterate (and the Gauss-Seidel point is
  /// returned only if nothing came closer). Gauss-Seidel needs no factorization of W and
  /// copes with redundant contacts (W rank-deficient with many stuck contacts: Kapla
  /// towers), where the Newton direction is ill-determined. 0 turns it off.
  int gauss_seidel_fallback_sweeps = 2000;
  /// Multiplies the per-contact rho of the formulations (see Formulation).
  double rho_scale = 1.0;
  /// Armijo constant beta in (0, 1/2): accept psi(r + t d) <= max(recent psi) - 2 beta t
  /// psi(r).
  double armijo_beta = 1e-4;
  /// The max is taken over the last nonmonotone_window values of psi (1 = monotone).
  int nonmonotone_window = 5;
  /// Largest i tried for the step t = 2^-i.
  int max_backtracks = 40;
  /// An attempt stalls when its best error has not halved over this many steps. 15: on
  /// data/fc3d, Capsules-i101-404 (AC stalls from r = 0, FB then solves it)
  /// took 41 / 26 / 21 steps with 30 / 15 / 10, and 10 also switched OneObject-i1028-138
  /// away from an AC run that converges.
  int stall_window = 15;
  /// Newton step from (J + delta I) d = -Phi, delta = s max(1, max |J_ii|) with the
  /// relative shift s = max(regularization, min(shift_error_cap, e)), e the natural-map
  /// error of the iterate, kept when ||J d + Phi|| <= newton_residual ||Phi|| (< 1: then
  /// a descent direction of psi); otherwise the Levenberg-Marquardt direction
  /// (J'J + m I) d = -J' Phi, m = max(||Phi||, regularization).
  double newton_residual = 0.1;
  double regularization = 1e-10;
  /// Upper bound of the residual-proportional part of the shift above (0: the shift is
  /// `regularization` alone). A shift proportional to the residual (regularized Newton:
  /// Li, Fukushima, Qi & Yamashita 2003; Yamashita & Fukushima 2001 for LM) bounds the
  /// step along W's near-null directions - redundant contacts, or a W stored with 6
  /// significant digits that has turned slightly indefinite - where the step of J +
  /// 1e-10 I jumps across the kinks of the law, and it vanishes with e, so the local
  /// convergence stays superlinear. The matrix-free solver (operator_problem.hpp) does
  /// not use it.
  double shift_error_cap = 1e-6;
  LinearSolverType linear_solver = LinearSolverType::kAuto;
  /// kAuto: dense LU for dimension n_c <= dense_threshold, UMFPACK above.
  int dense_threshold = 150;
  /// GMRES iterations per Newton step at most (operator_problem.hpp only; restarted every
  /// 50). A Newton step whose GMRES stops short of the forcing term is still taken when
  /// it reduces ||J d + Phi|| below ||Phi|| (then still a descent direction).
  int krylov_max_iterations = 200;
  /// GMRES's orthogonalization of each new Krylov vector against the basis
  /// (operator_problem.hpp only): false, modified Gram-Schmidt (k + 1 dot products in
  /// sequence at iteration k); true, classical Gram-Schmidt applied twice (the k + 1 dot
  /// products at once, two passes: as orthogonal as modified Gram-Schmidt, Giraud,
  /// Langou and Rozloznik 2005). On a distributed problem each sequence of dot products
  /// is one reduction over the parts: 2 instead of k + 1 per iteration.
  bool krylov_classical_gram_schmidt = false;
  /// One line per iteration on stderr.
  bool log_to_stderr = false;

  /// Rejects settings outside their ranges; *error says which and why.
  bool IsValid(std::string* error) const;
};

struct IterationRecord {
  int iteration = 0;  ///< k over all attempts (0 = start point)
  Formulation formulation = Formulation::kAlartCurnier;
  double error = 0.0;        ///< NaturalMapError(r^k)
  double psi = 0.0;          ///< 1/2 ||Phi(r^k)||^2 of the current formulation
  double step_length = 0.0;  ///< t of the step that reached r^k
  double time_s = 0.0;       ///< since the solve started
};

struct Summary {
  Termination termination = Termination::kNotSolved;
  std::string message = "not solved yet";
  Formulation formulation_requested = Formulation::kHybrid;
  Formulation formulation_final = Formulation::kHybrid;  ///< of the last attempt
  LinearSolverType linear_solver_used = LinearSolverType::kAuto;

  int num_contacts = -1;
  int iterations = -1;              ///< Newton steps, all attempts
  int gauss_seidel_sweeps = -1;     ///< sweeps done before the Newton steps
  int fallback_sweeps = -1;         ///< Gauss-Seidel sweeps of the fallback (Options)
  int attempts = -1;                ///< 1 + formulation switches of the hybrid
  int backtracks = -1;              ///< halvings in the line searches
  int linear_solver_failures = -1;  ///< Newton solves failed or failing the residual test
  int levenberg_marquardt_steps = -1;  ///< directions from (J'J + m I) d = -J' Phi
  int symbolic_factorizations = -1;
  int krylov_iterations =
      -1;  ///< GMRES iterations, all Newton steps (operator_problem.hpp)
  int operator_applications = -1;  ///< products with W (operator_problem.hpp)

  double initial_error = -1.0;  ///< NaturalMapError at the start point
  double final_error = -1.0;    ///< NaturalMapError at the returned r (recomputed)
  double total_time_s = -1.0;

  std::vector<IterationRecord> trace;

  /// One line: status, formulation, iterations, error, time.
  std::string BriefReport() const;
  bool IsSolutionUsable() const {
    return termination == Termination::kConverged ||
           termination == Termination::kAtRoundoffFloor;
  }
};

/// Solves the problem from *r (resized to problem.size() and zeroed if empty) and returns
/// in *r the iterate with the smallest error met. Throws std::invalid_argument for
/// invalid options, an invalid problem or a start point of the wrong size or not finite;
/// numerical trouble ends with a Termination instead.
void Solve(const Options& options, const FrictionProblem& problem, Vector* r,
           Summary* summary);

namespace internal {
class NewtonSolver;
}

/// Repeated solves of one problem whose q and scale of W change between solves but not
/// its structure (the steps of a time stepper): the problem is validated once, and W's
/// block form, rho per contact, the Jacobian's pattern, the linear solver's symbolic
/// analysis and the work vectors are kept, so that a solve allocates nothing in its
/// Newton iterations (dense LU) and only the Summary's trace and message grow.
/// Solve(options, problem, r, summary) above is one Solver used once.
class Solver {
 public:
  /// Throws std::invalid_argument as FrictionProblem::Validate.
  explicit Solver(FrictionProblem problem);
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  /// W = scale W0, W0 the W given to the constructor (a change of units of r or u).
  /// Throws std::invalid_argument when scale or an entry of scale W0 is not finite.
  void ScaleW(double scale);
  /// New q (size dimension n_c, finite; else std::invalid_argument).
  void SetQ(const Vector& q);
  const FrictionProblem& problem() const { return problem_; }
  /// As Solve(options, problem(), r, summary); *summary's trace and message storage is
  /// reused.
  void Solve(const Options& options, Vector* r, Summary* summary);

 private:
  FrictionProblem problem_;
  SparseMatrix W0_;
  double scale_ = 1.0;  // W = scale_ W0_
  std::unique_ptr<internal::NewtonSolver> newton_;
};

}  // namespace ncp::fc
