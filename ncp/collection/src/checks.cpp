#include "ncp_collection/checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ncp::collection {
namespace {

void CheckSize(const char* what, Eigen::Index actual, Eigen::Index expected) {
  if (actual != expected) {
    throw std::invalid_argument(std::string("NaturalResidual: ") + what + " has size " +
                                std::to_string(actual) + ", expected " +
                                std::to_string(expected));
  }
}

}  // namespace

Vector ProjectOntoBox(const Vector& lower, const Vector& upper, const Vector& y) {
  Vector p(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i)
    p(i) = std::max(lower(i), std::min(upper(i), y(i)));
  return p;
}

double NaturalResidualFromValues(const Vector& lower, const Vector& upper,
                                 const Vector& x, const Vector& Fx) {
  const Eigen::Index n = x.size();
  CheckSize("lower", lower.size(), n);
  CheckSize("upper", upper.size(), n);
  CheckSize("F(x)", Fx.size(), n);
  double r = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(x(i)) || !std::isfinite(Fx(i))) {
      return std::numeric_limits<double>::infinity();
    }
    // x_i - mid(l_i, u_i, x_i - F_i): zero iff (x_i = l_i, F_i >= 0) or
    // (x_i = u_i, F_i <= 0) or (l_i < x_i < u_i, F_i = 0), for x_i in [l_i, u_i].
    const double projected = std::max(lower(i), std::min(upper(i), x(i) - Fx(i)));
    r = std::max(r, std::abs(x(i) - projected));
  }
  return r;
}

double NaturalResidual(SquareFunction& F, const Vector& lower, const Vector& upper,
                       const Vector& x) {
  const int n = F.NumVariables();
  CheckSize("x", x.size(), n);
  Vector Fx(n);
  if (!F.Evaluate(x, &Fx)) return std::numeric_limits<double>::infinity();
  return NaturalResidualFromValues(lower, upper, x, Fx);
}

bool CentralDifferenceJacobian(SquareFunction& F, const Vector& x, double step,
                               DenseMatrix* J) {
  const int n = F.NumVariables();
  J->resize(n, n);
  Vector xp = x, xm = x, Fp(n), Fm(n);
  for (int j = 0; j < n; ++j) {
    const double h = step * std::max(1.0, std::abs(x(j)));
    xp(j) = x(j) + h;
    xm(j) = x(j) - h;
    if (!F.Evaluate(xp, &Fp) || !F.Evaluate(xm, &Fm)) return false;
    J->col(j) = (Fp - Fm) / (xp(j) - xm(j));
    xp(j) = x(j);
    xm(j) = x(j);
  }
  return true;
}

}  // namespace ncp::collection
