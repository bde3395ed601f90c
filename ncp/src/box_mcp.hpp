#pragma once

#include <memory>

#include "ncp/solver.hpp"

namespace ncp::internal {

/// The box MCP in mixed form (box_mcp.cpp); kept by the Solver between solves.
class BoxMcpAsMixed;
struct BoxMcpDeleter {
  void operator()(BoxMcpAsMixed* p) const;
};
using BoxMcpCache = std::unique_ptr<BoxMcpAsMixed, BoxMcpDeleter>;

/// Box MCP l <= x <= u perp F(x), solved as a mixed problem (see box_mcp.cpp). *cache is
/// reused when it was built for the same F and bounds, else replaced.
void SolveBoxMcp(Solver& solver, BoxMcpCache* cache, SquareFunction& F, const Vector& lower,
                 const Vector& upper, Vector* x, Summary* summary);

}  // namespace ncp::internal
