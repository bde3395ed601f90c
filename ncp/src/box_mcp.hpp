// The box MCP l <= x <= u perp F(x) as a mixed problem (box_mcp.cpp). The dependency runs
// one way: ncp::Solver (solver.cpp) calls the two phases below around its own solve of
// the mixed problem; nothing here calls the Solver.
#pragma once

#include <memory>

#include "ncp/problem.hpp"
#include "ncp/solver.hpp"
#include "ncp/square_function.hpp"

namespace ncp::internal {

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
