/// \file convex_qp.hpp
/// Reference solver for inequality-constrained convex quadratic programs
///
///     minimize    1/2 x' P x + q' x
///     subject to  G x <= h,
///
/// P (n x n) sparse symmetric positive semidefinite, G (m x n) sparse. It runs the
/// interior-point method Ipopt (Waechter and Biegler 2006) through its TNLP interface
/// with the linear solver Ipopt was built with (MUMPS on Debian). It serves as an
/// independent check of the complementarity formulations (frictionless contact, one
/// friction fixed-point step), not as the production solver.
///
/// The KKT conditions of the problem, which the returned (x, z) satisfy approximately:
///     P x + q + G' z = 0                (stationarity)
///     G x <= h,  z >= 0                 (primal and dual feasibility)
///     z_i (h - G x)_i = 0  for every i  (complementarity).
///
/// Misuse (size mismatch, non-finite data, non-symmetric P, invalid options) throws
/// std::invalid_argument. Numerical trouble (Ipopt not converging, infeasibility) never
/// throws: it is a ConvexQpStatus and a message in the result.
///
/// Accuracy: Ipopt stops when its SCALED optimality error is below ConvexQpOptions::
/// tolerance. The unscaled KKT residuals above are recomputed from the problem data after
/// the solve and returned in ConvexQpResult, so callers can check what was achieved.
/// Measured with the defaults (tolerance 1e-10, Debian Ipopt 3.11.9 + MUMPS) on random
/// 200-variable strictly convex QPs with 150 constraints, 10 seeds each:
///  - stationarity ||P x + q + G' z||_inf ~1e-15 relative to its terms; G x <= h exactly
///    (bound_relax_factor 0); z >= 0; max z_i (h - G x)_i <= 1e-10 relative.
///  - planted strictly complementary solution (active z*_i and inactive slacks >= 0.1):
///    ||x - x*||_inf <= 2e-10, ||z - z*||_inf / ||z*||_inf <= 5e-10 (5e-11 with P, z
///    scaled by 1e6); with tolerance 1e-8 only ~1e-7.
///  - planted solution with z*_i and slacks uniform in [0, 1] (nearly degenerate):
///    ||x - x*||_inf up to 2e-8.
///  - a weakly active constraint (z* = 0 on an active row) is resolved only to ~sqrt(mu):
///    x off by 4e-6 while every KKT residual is <= 1e-10 (interior-point behaviour).
#pragma once

#include <string>

#include "contact/types.hpp"

namespace contact {

struct ConvexQpOptions {
  /// Ipopt option tol: converged when Ipopt's scaled optimality error E_0 <= tolerance
  /// (Waechter and Biegler 2006, section 2.1: the max of dual infeasibility / s_d,
  /// constraint violation and complementarity / s_c, where s_d, s_c >= 1 grow with the
  /// mean multiplier size beyond 100), after Ipopt's gradient-based scaling of objective
  /// and constraints. So it is neither a purely absolute nor a purely relative test.
  double tolerance = 1e-10;
  /// Additional unscaled tests Ipopt makes before reporting success (defaults are
  /// Ipopt's; tighten them to force an absolute accuracy, at the risk of
  /// kAcceptable/kMaxIterations): Ipopt option constr_viol_tol: max_i (G x - h)_i^+ <=
  /// this.
  double constraint_violation_tolerance = 1e-4;
  /// Ipopt option dual_inf_tol: ||P x + q + G' z||_inf <= this.
  double dual_infeasibility_tolerance = 1.0;
  /// Ipopt option compl_inf_tol: max_i z_i (h - G x)_i <= this.
  double complementarity_tolerance = 1e-4;
  /// Ipopt option max_iter: stop with kMaxIterations after this many interior-point
  /// steps.
  int max_iterations = 3000;
  /// Ipopt option max_cpu_time [s]: stop with kMaxTime after this much CPU time.
  double max_cpu_seconds = 1e6;
  /// Ipopt option print_level, 0 (silent) ... 12; output goes to stdout.
  int print_level = 0;
  /// Ipopt option mehrotra_algorithm: Mehrotra's predictor-corrector for LPs and convex
  /// QPs (also switches to Ipopt's least-squares primal initialization). Off by default:
  /// it saves a few iterations but, measured on x <= -1, -x <= -1, it ends with
  /// kUnbounded (diverging iterates) where the default algorithm reports kInfeasible.
  bool mehrotra = false;
  /// Ipopt option bound_relax_factor: Ipopt relaxes every bound h_i by
  /// bound_relax_factor * max(1, |h_i|) before solving. 0 (here the default) keeps
  /// G x <= h exact; Ipopt's own default 1e-8 limits the accuracy of x and z to ~1e-8.
  double bound_relax_factor = 0.0;

  /// Rejects settings outside their ranges (tolerances > 0 and finite, max_iterations >=
  /// 0, max_cpu_seconds > 0, print_level in [0, 12], bound_relax_factor >= 0); *error
  /// says which and why.
  bool IsValid(std::string* error) const;
};

/// Why a solve stopped. Only kSolved means Ipopt met all of ConvexQpOptions' tolerances.
enum class ConvexQpStatus {
  kNotSolved,      ///< SolveConvexQpIpopt has not run (ConvexQpResult default)
  kSolved,         ///< Ipopt: Solve_Succeeded
  kAcceptable,     ///< Ipopt: Solved_To_Acceptable_Level (its looser acceptable_tol)
  kMaxIterations,  ///< Ipopt: Maximum_Iterations_Exceeded
  kMaxTime,        ///< Ipopt: Maximum_CpuTime_Exceeded
  kInfeasible,     ///< Ipopt: Infeasible_Problem_Detected (G x <= h looks infeasible)
  kUnbounded,      ///< Ipopt: Diverging_Iterates (objective unbounded below?)
  kSmallSearchDirection,  ///< Ipopt: Search_Direction_Becomes_Too_Small (often at a
                          ///< solution that cannot be resolved further: check residuals)
  kFailed,                ///< any other Ipopt return status (restoration failure, errors)
};

const char* ToString(ConvexQpStatus status);

struct ConvexQpResult {
  ConvexQpStatus status = ConvexQpStatus::kNotSolved;
  std::string message = "not solved yet";  ///< Ipopt's return status name and value

  Vector x;            ///< last primal iterate (n)
  Vector multipliers;  ///< z (m): KKT multipliers of G x <= h, P x + q + G' z = 0, z >= 0
  int iterations = -1;     ///< Ipopt interior-point iterations
  double seconds = -1.0;   ///< wall time of the whole call [s]
  double objective = 0.0;  ///< 1/2 x' P x + q' x at the returned x

  /// KKT residuals recomputed from the problem data at the returned (x, z), unscaled:
  double stationarity = -1.0;          ///< ||P x + q + G' z||_inf
  double constraint_violation = -1.0;  ///< max(0, max_i (G x - h)_i)
  double dual_infeasibility = -1.0;    ///< max(0, max_i -z_i)
  double complementarity = -1.0;       ///< max_i |z_i (h - G x)_i|

  /// One line: status, iterations, objective, residuals, time.
  std::string BriefReport() const;
  /// True only for kSolved.
  bool IsSolutionUsable() const { return status == ConvexQpStatus::kSolved; }
};

/// True when the library was built with Ipopt (CMake option NCP_WITH_IPOPT, default ON).
/// Without it SolveConvexQpIpopt returns kFailed with kWithoutIpopt as its message, and
/// the Ipopt step (StepMethod::kIpopt, compare_with_ipopt) is refused.
bool BuiltWithIpopt();
inline constexpr const char* kWithoutIpopt =
    "this build has no Ipopt (configured with -DNCP_WITH_IPOPT=OFF): reconfigure with "
    "-DNCP_WITH_IPOPT=ON (needs coinor-libipopt-dev) for the Ipopt reference solver";

/// Solves the QP above with Ipopt from the start point x0 (size n).
/// Throws std::invalid_argument if P is not n x n (n = q.size()), G is not m x n
/// (m = h.size()), x0.size() != n, n == 0, any entry of P, q, G, h, x0 is not finite,
/// P is not symmetric (|P_ij - P_ji| > 1e-12 max|P|), or the options are invalid.
/// Convexity (P positive semidefinite) is assumed, not checked. m = 0 is allowed.
ConvexQpResult SolveConvexQpIpopt(const SparseMatrix& P, const Vector& q,
                                  const SparseMatrix& G, const Vector& h,
                                  const Vector& x0,
                                  const ConvexQpOptions& options = ConvexQpOptions());

}  // namespace contact
