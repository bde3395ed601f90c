#include "ncp/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ncp {

double BoxMcpResidual(SquareFunction& F, const Vector& lower, const Vector& upper,
                      const Vector& x) {
  Vector Fx = Vector::Zero(x.size());
  if (!F.Evaluate(x, &Fx) || !Fx.allFinite())
    return std::numeric_limits<double>::infinity();
  double r = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double projected = std::min(upper(i), std::max(lower(i), x(i) - Fx(i)));
    r = std::max(r, std::abs(x(i) - projected));
  }
  return r;
}

double MixedResidual(MixedProblem& problem, const Vector& x) {
  const int m = problem.NumEquations(), p = problem.NumVariables() - m;
  Vector E = Vector::Zero(m), A = Vector::Zero(p), B = Vector::Zero(p);
  if (!problem.Evaluate(x, &E, &A, &B) || !E.allFinite() || !A.allFinite() ||
      !B.allFinite())
    return std::numeric_limits<double>::infinity();
  double r = m > 0 ? E.lpNorm<Eigen::Infinity>() : 0.0;
  for (int j = 0; j < p; ++j) r = std::max(r, std::abs(std::min(A(j), B(j))));
  return r;
}

}  // namespace ncp
