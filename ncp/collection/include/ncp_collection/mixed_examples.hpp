/// \file mixed_examples.hpp
/// Small problems in the mixed form of ncp::MixedProblem (equations + pairs).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ncp/problem.hpp"
#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

/// A mixed problem with its starts and known solution(s).
struct MixedTestProblem {
  std::string name;
  std::string source;
  std::unique_ptr<MixedProblem> problem;
  std::vector<StartPoint> starts;
  std::vector<Vector> solutions;
  std::string notes;
};

/// Euclidean projection of a point a in R^k onto the unit simplex
/// {x >= 0, sum x = 1}, written as its KKT system with unknowns (y, x_1 .. x_k):
///     E(y, x)   = sum_j x_j - 1                   = 0        (1 equation, variable y)
///     A_j(y, x) = x_j >= 0,  B_j(y, x) = x_j - a_j - y >= 0,  A_j B_j = 0   (k pairs)
/// (y is the multiplier of the equality constraint). The solution is known in closed
/// form, x_j = max(a_j - tau, 0), y = -tau, with tau from sorting (Held, Wolfe and
/// Crowder 1974; Duchi et al. 2008, Fig. 1). Starts "zero" and "uniform" (x = 1/k).
MixedTestProblem SimplexProjection(const Vector& a);

}  // namespace ncp::collection
