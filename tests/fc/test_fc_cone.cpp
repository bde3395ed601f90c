// The Coulomb-cone projection (Moreau's characterization), Siconos' natural-map error at
// a published solution, and the generalized Jacobian blocks of both formulations against
// central finite differences at random points.
#include <catch2/catch.hpp>
#include <random>

#include "fc_support.hpp"
#include "local_laws.hpp"
#include "ncp/fc/error.hpp"

using namespace ncp::fc;
using Catch::Matchers::WithinAbs;

TEST_CASE("ProjectOnCone satisfies Moreau's decomposition", "[fc][cone]") {
  const int d = GENERATE(2, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-2.0, 2.0), friction(0.0, 1.5);
  for (int k = 0; k < 2000; ++k) {
    const double mu = k % 10 == 0 ? 0.0 : friction(rng);
    double z[3] = {value(rng), value(rng), d == 3 ? value(rng) : 0.0};
    double p[3] = {z[0], z[1], z[2]};
    ProjectOnCone(mu, d, p);
    const double pt = std::hypot(p[1], d == 3 ? p[2] : 0.0);
    double w[3] = {z[0] - p[0], z[1] - p[1], z[2] - p[2]};  // must lie in the polar cone
    const double wt = std::hypot(w[1], d == 3 ? w[2] : 0.0);
    CHECK(pt <= mu * p[0] + 1e-12);   // P(z) in C_mu
    CHECK(mu * wt <= -w[0] + 1e-12);  // z - P(z) in -C*_mu
    CHECK_THAT(p[0] * w[0] + p[1] * w[1] + p[2] * w[2],
               WithinAbs(0.0, 1e-12));  // orthogonal
  }
  // Frictionless (mu = 0) with no tangential part: C_0 is the half-line r_N >= 0, so a
  // negative normal component projects to 0 (a contact that separates carries no force).
  for (double mu : {0.0, 0.5}) {
    double z[3] = {-1.0, 0.0, 0.0};
    ProjectOnCone(mu, d, z);
    CHECK(z[0] == 0.0);
    double y[3] = {2.0, 0.0, 0.0};
    ProjectOnCone(mu, d, y);
    CHECK(y[0] == 2.0);
  }
}

TEST_CASE("NaturalMapError vanishes at the published solution only", "[fc][error]") {
  const FrictionProblem p = test::OneContactProblem();
  const Eigen::VectorXd solution = test::OneContactSolution();
  // The solution is given to 10 digits: its error is of that order, not of round-off.
  CHECK(NaturalMapError(p, solution) < 1e-9);
  CHECK(test::CoulombViolation(p, solution) < 1e-9);
  CHECK(NaturalMapError(p, Eigen::VectorXd::Zero(3)) > 0.1);
  Eigen::VectorXd perturbed = solution;
  perturbed[1] += 1e-3;
  CHECK(NaturalMapError(p, perturbed) > 1e-4);
  CHECK_THROWS_AS(NaturalMapError(p, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

namespace {

using internal::Block;
using Law = std::function<void(const double* r, const double* u, double* phi, Block* A,
                               Block* B)>;

/// Central differences of the law in r (which = 0) or u (which = 1).
Block FiniteDifference(const Law& law, int d, const double* r, const double* u,
                       int which) {
  const double h = 1e-7;
  Block D = Block::Zero();
  Block A, B;
  for (int j = 0; j < d; ++j) {
    double rp[3] = {r[0], r[1], r[2]}, up[3] = {u[0], u[1], u[2]};
    double rm[3] = {r[0], r[1], r[2]}, um[3] = {u[0], u[1], u[2]};
    (which == 0 ? rp : up)[j] += h;
    (which == 0 ? rm : um)[j] -= h;
    double fp[3] = {0, 0, 0}, fm[3] = {0, 0, 0};
    law(rp, up, fp, &A, &B);
    law(rm, um, fm, &A, &B);
    for (int i = 0; i < d; ++i) D(i, j) = (fp[i] - fm[i]) / (2 * h);
  }
  return D;
}

}  // namespace

TEST_CASE("Jacobian blocks of both formulations match finite differences",
          "[fc][jacobian]") {
  const int d = GENERATE(2, 3);
  const int law_index = GENERATE(0, 1, 2);  // Alart-Curnier, natural map, FB
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0), friction(0.05, 1.2),
      rho(0.2, 3.0);
  int checked = 0;
  for (int k = 0; k < 500; ++k) {
    const double mu = k % 10 == 0 ? 0.0 : friction(rng), rho_n = rho(rng),
                 rho_t = rho(rng);
    const double r[3] = {value(rng), value(rng), d == 3 ? value(rng) : 0.0};
    const double u[3] = {value(rng), value(rng), d == 3 ? value(rng) : 0.0};
    Law law = [&](const double* rr, const double* uu, double* phi, Block* A, Block* B) {
      if (law_index == 0)
        internal::AlartCurnierLaw(d, mu, rho_n, rho_t, rr, uu, phi, A, B);
      else if (law_index == 1)
        internal::NaturalMapLaw(d, mu, rho_n, rr, uu, phi, A, B);
      else
        internal::FischerBurmeisterLaw(d, mu, rr, uu, phi, A, B);
    };
    double phi[3];
    Block A, B;
    law(r, u, phi, &A, &B);
    const Block Ar = FiniteDifference(law, d, r, u, 0),
                Bu = FiniteDifference(law, d, r, u, 1);
    INFO("d " << d << " law " << law_index << " mu " << mu << "\nA\n"
              << A << "\nFD\n"
              << Ar << "\nB\n"
              << B << "\nFD\n"
              << Bu);
    CHECK((A - Ar).cwiseAbs().maxCoeff() < 1e-5);
    CHECK((B - Bu).cwiseAbs().maxCoeff() < 1e-5);
    ++checked;
  }
  CHECK(checked == 500);
}

TEST_CASE("Both formulations vanish at the published solution", "[fc][jacobian]") {
  const FrictionProblem p = test::OneContactProblem();
  const Eigen::Vector3d r = test::OneContactSolution();
  const Eigen::Vector3d u = p.W * r + p.q;
  double phi[3];
  Block A, B;
  internal::AlartCurnierLaw(3, 0.1, 1.0 / 15, 1.0 / 15, r.data(), u.data(), phi, &A, &B);
  CHECK(Eigen::Map<Eigen::Vector3d>(phi).norm() < 1e-9);
  internal::NaturalMapLaw(3, 0.1, 1.0 / 15, r.data(), u.data(), phi, &A, &B);
  CHECK(Eigen::Map<Eigen::Vector3d>(phi).norm() < 1e-9);
  internal::FischerBurmeisterLaw(3, 0.1, r.data(), u.data(), phi, &A, &B);
  CHECK(Eigen::Map<Eigen::Vector3d>(phi).norm() < 1e-8);
}
