// Shared helpers of the ncp solver tests: run one (problem, start, function, backend)
// and recompute the residual from the problem data, never from the Summary.
#pragma once

#include <algorithm>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp/types.hpp"
#include "ncp_collection/checks.hpp"
#include "ncp_collection/test_problem.hpp"

namespace ncp::test {

struct Run {
  Vector x;
  Summary summary;
  double natural_residual = std::numeric_limits<double>::infinity();
};

/// Solves problem from x0 and recomputes ||x - mid(l, u, x - F(x))||_inf itself.
inline Run SolveFrom(collection::TestProblem& problem, const Vector& x0,
                     const Options& options) {
  Run run;
  run.x = x0;
  Solve(options, *problem.F, problem.lower, problem.upper, &run.x, &run.summary);
  run.natural_residual =
      collection::NaturalResidual(*problem.F, problem.lower, problem.upper, run.x);
  return run;
}

/// Tolerance for the finite-difference obstacle problems on a grid of width h. An iterate
/// u is stored to ulp(u) ~ 1.1e-16 (|u| <= 1/2), and F = h^-2 (differences of u) - f, so
/// ||F(u)|| cannot be made smaller than about h^-2 ulp(u) (5.5e-9 observed at h = 1e-4);
/// with a safety factor: max(1e-10, 20 eps h^-2).
inline double AttainableObstacleTolerance(double h) {
  return std::max(1e-10, 20 * std::numeric_limits<double>::epsilon() / (h * h));
}

inline Options MakeOptions(NcpFunction function, LinearSolverType backend) {
  Options options;
  options.ncp_function = function;
  options.linear_solver = backend;
  return options;
}

/// ||x - s||_inf to the nearest of the known solutions (+inf if none).
inline double DistanceToNearest(const Vector& x, const std::vector<Vector>& solutions) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vector& s : solutions)
    best = std::min(best, (x - s).lpNorm<Eigen::Infinity>());
  return best;
}

inline std::string Describe(const collection::TestProblem& problem,
                            const std::string& start, NcpFunction function,
                            LinearSolverType backend, const Run& run) {
  std::ostringstream out;
  out << problem.name << " from start " << start << " with " << ToString(function)
      << " / " << ToString(backend) << ": " << run.summary.BriefReport()
      << "; recomputed natural residual " << run.natural_residual
      << "; message: " << run.summary.message;
  return out.str();
}

}  // namespace ncp::test
