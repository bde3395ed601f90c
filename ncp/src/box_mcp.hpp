#pragma once

#include "ncp/solver.hpp"

namespace ncp::internal {

/// Box MCP l <= x <= u perp F(x), solved as a mixed problem (see box_mcp.cpp).
void SolveBoxMcp(Solver& solver, SquareFunction& F, const Vector& lower, const Vector& upper,
                 Vector* x, Summary* summary);

}  // namespace ncp::internal
