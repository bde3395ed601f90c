/// \file types.hpp
/// Basic linear-algebra types and the enumerations shared by the ncp public API.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

namespace ncp {

using Vector = Eigen::VectorXd;
/// Column-major compressed sparse matrix; the format every Jacobian is exchanged in.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using DenseMatrix = Eigen::MatrixXd;

/// The NCP function phi(a, b) with phi(a, b) = 0  <=>  a >= 0, b >= 0, a b = 0.
enum class NcpFunction {
  /// phi(a, b) = sqrt(a^2 + b^2) - (a + b)            (thesis eq. 17; DFK 1996)
  kFischerBurmeister,
  /// phi(a, b) = min(a, b)                              (thesis eq. 16)
  kMin,
  /// phi(a, b) = lambda phi_FB(a, b) - (1 - lambda) max(a, 0) max(b, 0)
  /// (Chen, Chen and Kanzow 2000), lambda = Options::penalized_fb_lambda.
  kPenalizedFischerBurmeister,
};

/// Linear solver used for the Newton system J d = -Phi.
enum class LinearSolverType {
  kAuto,     ///< dense LU below Options::dense_threshold unknowns, else UMFPACK
  kDenseLU,  ///< dense LU of the densified Jacobian: Eigen::FullPivLU (rank-revealing) up
             ///< to 100 unknowns, Eigen::PartialPivLU above (singular: a pivot below n
             ///< eps the largest)
  kSparseLU,  ///< Eigen::SparseLU (supernodal, COLAMD ordering)
  kUmfpack,   ///< SuiteSparse UMFPACK through Eigen::UmfPackLU
  kKlu,       ///< SuiteSparse KLU through Eigen::KLU
  /// SuiteSparse CHOLMOD Cholesky of the Newton matrix made symmetric: rows that fix
  /// their variable alone (d_i = rhs_i / J_ii) are eliminated and the others scaled by
  /// s_i (one sign per connected block) with s_i J_ij = s_j J_ji (relative 1e-10). A box
  /// MCP with a symmetric positive definite F' and one-sided bounds (obstacle problems,
  /// convex bound-constrained minimization) gives S J = diag(da / db) + F' for the FB,
  /// min and penalized FB functions: positive definite, so about half the flops of an LU
  /// of the same fill and no pivoting (Davis, Direct Methods for Sparse Linear Systems,
  /// 2006; timings against UMFPACK: benchmarks/results/defaults/README.md). A Newton
  /// matrix that is not symmetrizable, or not positive definite, is factored by UMFPACK
  /// instead (Summary::cholesky_fallbacks).
  kCholmod,
};
/// The last enumerator of each enumeration (range checks, bindings).
constexpr NcpFunction kLastNcpFunction = NcpFunction::kPenalizedFischerBurmeister;
constexpr LinearSolverType kLastLinearSolverType = LinearSolverType::kCholmod;

/// Why a solve stopped. Only kConverged means the returned x solves the problem.
enum class TerminationType {
  kNotSolved,          ///< Solve() has not run yet (Summary default)
  kConverged,          ///< ||Phi(x)||_inf <= Options::tolerance
  kMaxIterations,      ///< Options::max_iterations reached
  kLineSearchFailure,  ///< no step of length >= Options::min_step satisfies Armijo
  kStationaryPoint,    ///< at (or stagnating near) a stationary point of psi that is not
                       ///< a solution: grad psi = 0, no Armijo decrease with a tiny
                       ///< gradient, or psi stalled (e.g. Billups from x0 = 0)
  kLinearSolverFailure,  ///< Newton system unsolvable and the gradient fallback is
                         ///< disabled
  kNonFiniteValues,      ///< NaN/Inf in the residual or Jacobian at the current iterate
  kEvaluationFailure,    ///< Evaluate()/Jacobian() returned false at the current iterate
  kUserAbort,            ///< the iteration callback asked to stop
  kTimeLimit,            ///< Options::max_seconds reached, or a factorization predicted
                         ///< to take longer than the time left was not started
  /// The problem has no solution, proven: a box MCP with an affine F
  /// (SquareFunction::IsAffine) whose stuck solve left a Farkas certificate y
  /// (Summary::infeasibility_certificate): no x in [l, u] has F(x) in the cone of the
  /// bounds (>= 0 on lower-bounded rows, <= 0 on upper-bounded, = 0 on free rows).
  kInfeasible,
  /// tolerance < ||Phi(x)||_inf, but every row within the tolerance plus its round-off
  /// floor (Options::roundoff_ulps): as accurate as double precision resolves at x, not
  /// the accuracy asked for. Usable (Summary::IsSolutionUsable); a caller that needs the
  /// tolerance itself asks for kConverged.
  kAtRoundoffFloor,
};
constexpr TerminationType kLastTerminationType = TerminationType::kAtRoundoffFloor;

const char* ToString(NcpFunction f);
const char* ToString(LinearSolverType t);
const char* ToString(TerminationType t);

}  // namespace ncp
