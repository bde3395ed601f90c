/// \file test_problem.hpp
/// One problem of the collection: a box MCP  l <= x <= u  perp  F(x)  with its standard
/// starting points, its known solutions and the failures documented in the literature.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp::collection {

/// A labelled starting point, e.g. MCPLIB's start 3 of kojshin is {"3",
/// (100,100,100,100)}.
struct StartPoint {
  std::string label;  ///< the label used in the source (MCPLIB number, "zero", ...)
  Vector x;           ///< the point itself (size n)
};

/// A start point from which the method is documented to stop without a solution.
struct ExpectedFailure {
  std::string start_label;  ///< StartPoint::label this applies to
  /// NCP functions it applies to; empty means every function.
  std::vector<NcpFunction> functions;
  std::string reason;  ///< why (e.g. "local minimum of psi that is not a solution")

  bool AppliesTo(const std::string& label, NcpFunction function) const;
};

/// A box-constrained MCP  l <= x <= u  perp  F(x) (standard NCP: l = 0, u = +inf).
struct TestProblem {
  std::string name;    ///< short name, MCPLIB's where the problem is in MCPLIB
  std::string source;  ///< where the formulas come from
  std::unique_ptr<SquareFunction> F;
  Vector lower;  ///< l (entries may be -inf)
  Vector upper;  ///< u (entries may be +inf)
  std::vector<StartPoint> starts;
  /// Known solutions. If isolated_solutions is false they are sample points of a
  /// continuum of solutions, and a computed point must be judged by its residual only.
  std::vector<Vector> solutions;
  bool isolated_solutions = true;
  std::vector<ExpectedFailure> expected_failures;
  std::string notes;

  int NumVariables() const { return F ? F->NumVariables() : 0; }
  /// True when l = 0 and u = +inf componentwise (a standard NCP).
  bool IsStandardNcp() const;
  /// The documented failure for (start, function), or nullptr if none is documented.
  const ExpectedFailure* FindExpectedFailure(const std::string& start_label,
                                             NcpFunction function) const;
};

}  // namespace ncp::collection
