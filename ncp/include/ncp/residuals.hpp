/// \file residuals.hpp
/// Independent checks of a claimed solution, computed from the problem alone.
#pragma once

#include "ncp/problem.hpp"
#include "ncp/square_function.hpp"

namespace ncp {

/// Natural residual of the box MCP, ||x - mid(l, u, x - F(x))||_inf: zero exactly at
/// solutions, independent of the NCP function used by the solver. Returns +inf if F
/// cannot be evaluated at x.
double BoxMcpResidual(SquareFunction& F, const Vector& lower, const Vector& upper,
                      const Vector& x);

/// Mixed problem: max(||E||_inf, max_j |min(A_j, B_j)|). +inf if not evaluable.
double MixedResidual(MixedProblem& problem, const Vector& x);

}  // namespace ncp
