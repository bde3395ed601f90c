// The box MCP l <= x <= u perp F(x) as a mixed problem (box_mcp.cpp). The dependency runs
// one way: ncp::Solver (solver.cpp) calls the two phases below around its own solve of
// the mixed problem; nothing here calls the Solver.
#pragma once

#include <memory>

#include "ncp/problem.hpp"
#include "ncp/solver.hpp"
#include "ncp/square_function.hpp"

namespace ncp::internal {

/// The Jacobian of Phi = [E; phi(A, B)] written straight into a dense matrix from the
/// problem's own derivative, without the matrices JE, JA, JB of MixedProblem::Jacobian
/// (the dense path of small box MCPs: every row of Phi is a row of F' times +-1 or
/// constant entries). The results are those of MixedProblem::Jacobian followed by the
/// solver's assembly (Solver::Workspace::FillDenseJacobian), to the bit: the same
/// products, summed in the same order.
class DenseMixedJacobian {
 public:
  virtual ~DenseMixedJacobian() = default;
  /// The derivative at the unknowns y; false when it cannot be evaluated there (as
  /// MixedProblem::Jacobian). Throws std::invalid_argument on a wrong size.
  virtual bool EvaluateDerivative(const Vector& y) = 0;
  /// za = JA z and zb = JB z with the last derivative (the z-vector rule, DFK eq. 27).
  virtual void MultiplyPairJacobians(const Vector& z, Vector* za, Vector* zb) const = 0;
  /// Jd = [JE; diag(da) JA + diag(db) JB] with the last derivative and sensitivity_i =
  /// sum over the terms of row i of |term| |y_col| (the round-off floor's r); false when
  /// an entry the rows use is not finite (then Jd is incomplete).
  virtual bool Fill(const Vector& da, const Vector& db, const Vector& y, DenseMatrix* Jd,
                    Vector* sensitivity) const = 0;
};

/// The box MCP in mixed form (box_mcp.cpp); kept by the Solver between solves.
class BoxMcpAsMixed;
struct BoxMcpDeleter {
  void operator()(BoxMcpAsMixed* p) const;
};
using BoxMcpCache = std::unique_ptr<BoxMcpAsMixed, BoxMcpDeleter>;

/// One solve of a box MCP, before and after the solve of its mixed form:
///
///   BoxMcpSolve box(options, &cache, F, lower, upper, x);  // mixed form, start
///   if (box.ready()) Solve(box.problem(), &box.unknowns(), summary);
///   box.Finish(summary);  // x, certificate, projection onto [l, u]
class BoxMcpSolve {
 public:
  /// Checks sizes, bounds and the start point (std::invalid_argument), takes the mixed
  /// form from *cache when it was built for the same F and bounds (else builds it there),
  /// projects *x onto [l, u] (Options::project_start_point) and starts the slacks at the
  /// positive and negative parts of F(x0).
  BoxMcpSolve(const Options& options, BoxMcpCache* cache, SquareFunction& F,
              const Vector& lower, const Vector& upper, Vector* x);
  /// False when F cannot be evaluated (or is not finite) at the start point: there is
  /// nothing to solve, and Finish reports kEvaluationFailure.
  bool ready() const { return ready_; }
  /// The mixed problem and its unknowns [x; slacks] (the start point on entry to the
  /// solve).
  MixedProblem& problem();
  Vector& unknowns();
  /// The same problem's Jacobian written dense (DenseMixedJacobian).
  DenseMixedJacobian& dense_jacobian();
  /// After the solve of problem() into summary: *x from the unknowns, a Farkas
  /// certificate when an affine F got stuck (kInfeasible), and *x projected onto [l, u],
  /// with the start and final projections counted and stated in the summary.
  void Finish(Summary* summary);

 private:
  const Options& options_;
  SquareFunction& F_;
  BoxMcpAsMixed& mixed_;
  Vector& x_;
  int projected_start_ = 0;
  bool ready_ = false;
};

}  // namespace ncp::internal
