#include "ncp/fc/error.hpp"

#include <cmath>
#include <stdexcept>

namespace ncp::fc {

void ProjectOnCone(double mu, int dimension, double* z) {
  const double t = dimension == 3 ? std::hypot(z[1], z[2]) : std::abs(z[1]);
  if (z[0] >= 0.0 && t <= mu * z[0]) return;  // inside C_mu (z_N >= 0 matters for mu = 0)
  if (mu * t <= -z[0]) {                      // inside the polar cone -C*_mu
    for (int i = 0; i < dimension; ++i) z[i] = 0.0;
    return;
  }
  const double a = (z[0] + mu * t) / (1.0 + mu * mu);
  z[0] = a;
  for (int i = 1; i < dimension; ++i) z[i] = a * mu * z[i] / t;
}

double NaturalMapResidual(int dimension, const Vector& mu, const Vector& r,
                          const Vector& u) {
  return std::sqrt(NaturalMapSquaredResidual(dimension, mu, r, u));
}

double NaturalMapSquaredResidual(int dimension, const Vector& mu, const Vector& r,
                                 const Vector& u) {
  const int d = dimension;
  double sum = 0.0;
  for (Eigen::Index a = 0; a < mu.size(); ++a) {
    const double* ra = r.data() + d * a;
    const double* ua = u.data() + d * a;
    const double ut = d == 3 ? std::hypot(ua[1], ua[2]) : std::abs(ua[1]);
    double z[3];  // r - u_hat, u_hat = u + (mu |u_T|, 0, 0)
    z[0] = ra[0] - ua[0] - mu[a] * ut;
    for (int i = 1; i < d; ++i) z[i] = ra[i] - ua[i];
    ProjectOnCone(mu[a], d, z);
    for (int i = 0; i < d; ++i) sum += (ra[i] - z[i]) * (ra[i] - z[i]);
  }
  return sum;
}

double NaturalMapError(const FrictionProblem& problem, const Vector& r) {
  if (r.size() != problem.size())
    throw std::invalid_argument("NaturalMapError: r must have " +
                                std::to_string(problem.size()) + " entries, got " +
                                std::to_string(r.size()));
  const Vector u = problem.W * r + problem.q;
  return NaturalMapResidual(problem.dimension, problem.mu, r, u) /
         (1.0 + problem.q.norm());
}

}  // namespace ncp::fc
