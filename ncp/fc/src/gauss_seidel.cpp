#include "gauss_seidel.hpp"

#include <Eigen/LU>
#include <cmath>

#include "local_laws.hpp"
#include "ncp/fc/error.hpp"

namespace ncp::fc::internal {

namespace {

constexpr int kLocalNewtonSteps = 20;

/// |r - P_C(r - u_hat)| of one contact, u = W_aa r + v (the contact's part of
/// NaturalMapError).
double LocalResidual(int d, double mu, const Block& Waa, const Eigen::Vector3d& v,
                     const Eigen::Vector3d& r) {
  const Eigen::Vector3d u = Waa * r + v;
  const double ut = std::hypot(u[1], d == 3 ? u[2] : 0.0);
  Eigen::Vector3d z = r - u;
  z[0] -= mu * ut;
  ProjectOnCone(mu, d, z.data());
  double sum = 0.0;
  for (int i = 0; i < d; ++i) sum += (r[i] - z[i]) * (r[i] - z[i]);
  return std::sqrt(sum);
}

}  // namespace

void GaussSeidelSweep(const FrictionProblem& problem, const BlockDelassus& W,
                      const std::vector<Rho>& rho, Vector* r) {
  const int d = problem.dimension;
  for (int a = 0; a < problem.num_contacts; ++a) {
    const Block& Waa = W.Diagonal(a);
    Eigen::Vector3d ra = Eigen::Vector3d::Zero();
    ra.head(d) = r->segment(d * a, d);
    Eigen::Vector3d v = W.RowTimes(a, *r) - Waa * ra;  // sum_{b != a} W_ab r_b + q_a
    for (int i = 0; i < d; ++i) v[i] += problem.q[d * a + i];
    const double mu = problem.mu[a];
    const double before = LocalResidual(d, mu, Waa, v, ra);
    Eigen::Vector3d x = ra, phi = Eigen::Vector3d::Zero();
    Block A, B;
    for (int k = 0; k < kLocalNewtonSteps; ++k) {
      const Eigen::Vector3d u = Waa * x + v;
      AlartCurnierLaw(d, mu, rho[a].n, rho[a].t, x.data(), u.data(), phi.data(), &A, &B);
      Block J = A + B * Waa;
      for (int i = d; i < 3; ++i) J(i, i) = 1.0;  // the padding of d = 2
      const Eigen::FullPivLU<Block> lu(J);        // fixed size: no allocation
      if (!lu.isInvertible()) break;
      Eigen::Vector3d rhs = -phi;
      rhs.tail(3 - d).setZero();
      const Eigen::Vector3d step = lu.solve(rhs);
      if (!step.allFinite()) break;
      x += step;
      if (step.norm() <= 1e-14 * (1.0 + x.norm())) break;
    }
    if (x.allFinite() && LocalResidual(d, mu, Waa, v, x) < before)
      r->segment(d * a, d) = x.head(d);
  }
}

}  // namespace ncp::fc::internal
