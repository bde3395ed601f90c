/// \file cops_bound_constrained.hpp
/// The bound-constrained grid problems 15-17 of COPS (E. D. Dolan and J. J. More,
/// "Benchmarking optimization software with COPS", Argonne MCS Division, 2000 (COPS 2.0);
/// COPS 3.0 by Dolan, More and Munson, 2004) in the form of the GAMS model library
/// (models of COPS 2.0): minimize f(v) over
/// the values v at the interior nodes of a uniform grid subject to l <= v <= u. Each
/// problem is the first-order (KKT) system of that minimization, the box MCP
///     l <= v <= u  perp  F(v) = grad f(v),
/// with the analytic gradient and Hessian (sparse). f is convex in all three, so the
/// MCP solutions are exactly the minimizers. The grid has interior_x x interior_y
/// unknowns (GAMS's --nx = interior_x + 1, --ny = interior_y + 1), numbered
/// (i - 1) + interior_x (j - 1) for the node (i, j), 1 <= i <= interior_x.
#pragma once

#include <vector>

#include "ncp/types.hpp"
#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// GAMS `jbearing` (SEQ=244), COPS #16: pressure in a journal bearing on (0, 2 pi) x
/// (0, 20), eccentricity 0.1; v >= 0. A convex QP: an LCP.
TestProblem JournalBearing(int interior_x = 25, int interior_y = 25);

/// GAMS `torsion` (SEQ=243), COPS #15: elastic-plastic torsion of a bar with square
/// cross-section (0, 1)^2, c = 5; |v| <= distance to the boundary. A convex QP with
/// two-sided bounds.
TestProblem Torsion(int interior_x = 25, int interior_y = 25);

/// GAMS `minsurf` (SEQ=245), COPS #17: minimal surface over (0, 1)^2 with the boundary
/// values 1 - (2x - 1)^2 on y = 0, 1 and 0 on x = 0, 1, above the obstacle v >= 1 on
/// the nodes of [1/4, 3/4]^2 (v >= 0 elsewhere). Nonlinear (the area of a piecewise
/// linear surface).
TestProblem MinimalSurface(int interior_x = 25, int interior_y = 25);

/// The objective f of each problem at the interior values v (size interior_x *
/// interior_y), as the .gms defines it (the test compares F with its differences, and
/// the optimal values with those published by COPS).
double JournalBearingObjective(int interior_x, int interior_y, const Vector& v);
double TorsionObjective(int interior_x, int interior_y, const Vector& v);
double MinimalSurfaceObjective(int interior_x, int interior_y, const Vector& v);

/// The three at their default size.
std::vector<TestProblem> CopsBoundConstrainedProblems();

}  // namespace ncp::collection
