/// \file checks.hpp
/// Checks computed from the problem data alone, independent of the ncp solver:
/// the natural residual of a box MCP and a finite-difference Jacobian.
#pragma once

#include "ncp/square_function.hpp"
#include "ncp/types.hpp"

namespace ncp::collection {

/// Componentwise median mid(l, u, y) = max(l, min(u, y)), the projection onto [l, u].
Vector ProjectOntoBox(const Vector& lower, const Vector& upper, const Vector& y);

/// Natural residual of the box MCP,  ||x - mid(l, u, x - F(x))||_inf.
/// It is zero exactly at solutions (Facchinei and Pang 2003, Prop. 1.5.8 with the
/// Euclidean projection onto the box). Returns +inf if F cannot be evaluated at x or
/// gives a non-finite value. Sizes must agree (throws std::invalid_argument).
double NaturalResidual(SquareFunction& F, const Vector& lower, const Vector& upper,
                       const Vector& x);

/// Same, from an already evaluated F(x).
double NaturalResidualFromValues(const Vector& lower, const Vector& upper,
                                 const Vector& x, const Vector& Fx);

/// dF/dx at x by central differences, column j = (F(x + h_j e_j) - F(x - h_j e_j)) / 2h_j
/// with h_j = step * max(1, |x_j|). Dense; meant for small n in tests. Returns false if
/// F cannot be evaluated at one of the perturbed points.
bool CentralDifferenceJacobian(SquareFunction& F, const Vector& x, double step,
                               DenseMatrix* J);

}  // namespace ncp::collection
