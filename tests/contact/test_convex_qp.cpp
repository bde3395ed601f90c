// Tests of the Ipopt reference QP solver. Every solve is checked against the KKT
// conditions
//     P x + q + G' z = 0,  G x <= h,  z >= 0,  z_i (h - G x)_i = 0
// recomputed here from the problem data (not trusting ConvexQpResult's residuals), and
// against known solutions where the problem was built around one.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/convex_qp.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using contact::ConvexQpOptions;
using contact::ConvexQpResult;
using contact::ConvexQpStatus;
using contact::SolveConvexQpIpopt;
using contact::SparseMatrix;
using contact::Vector;

namespace {

SparseMatrix Sparse(const Eigen::MatrixXd& dense) { return dense.sparseView(); }

/// KKT residuals recomputed from the data, each relative to the size of its terms.
struct Kkt {
  double stationarity;  ///< ||P x + q + G' z||_inf / max(||q||, ||P x||, ||G' z||, 1)
  double primal_infeasibility;  ///< max(0, max (G x - h)) / max(1, ||h||_inf)
  double min_multiplier;        ///< min z (>= 0 wanted)
  double complementarity;  ///< max |z_i (h - G x)_i| / (max(1, ||z||) max(1, ||h - Gx||))
};

Kkt RecomputeKkt(const SparseMatrix& P, const Vector& q, const SparseMatrix& G,
                 const Vector& h, const Vector& x, const Vector& z) {
  REQUIRE(x.size() == q.size());
  REQUIRE(z.size() == h.size());
  const Vector Px = P * x;
  const Vector Gtz = G.transpose() * z;
  const double gradient_scale =
      std::max({1.0, q.lpNorm<Eigen::Infinity>(), Px.lpNorm<Eigen::Infinity>(),
                Gtz.lpNorm<Eigen::Infinity>()});
  Kkt kkt;
  kkt.stationarity = (Px + q + Gtz).lpNorm<Eigen::Infinity>() / gradient_scale;
  if (h.size() == 0) {
    kkt.primal_infeasibility = 0;
    kkt.min_multiplier = 0;
    kkt.complementarity = 0;
    return kkt;
  }
  const Vector slack = h - G * x;
  kkt.primal_infeasibility =
      std::max(0.0, -slack.minCoeff()) / std::max(1.0, h.lpNorm<Eigen::Infinity>());
  kkt.min_multiplier = z.minCoeff();
  kkt.complementarity = z.cwiseProduct(slack).lpNorm<Eigen::Infinity>() /
                        (std::max(1.0, z.lpNorm<Eigen::Infinity>()) *
                         std::max(1.0, slack.lpNorm<Eigen::Infinity>()));
  return kkt;
}

void CheckKkt(const SparseMatrix& P, const Vector& q, const SparseMatrix& G,
              const Vector& h, const ConvexQpResult& result, double tolerance) {
  const Kkt kkt = RecomputeKkt(P, q, G, h, result.x, result.multipliers);
  INFO(result.BriefReport());
  CHECK(kkt.stationarity <= tolerance);
  CHECK(kkt.primal_infeasibility <= tolerance);
  CHECK(kkt.min_multiplier >= 0.0);
  CHECK(kkt.complementarity <= tolerance);
}

/// A random strictly convex QP built around a known KKT point (x*, z*):
/// P = scale (A' A + 0.1 I) with A sparse random, G sparse random; half the constraints
/// active with z*_i in [0.1, 1] scale, the others inactive with slack in [0.1, 1]
/// (strict complementarity); q = -P x* - G' z*, h = G x* + slack.
struct PlantedQp {
  SparseMatrix P, G;
  Vector q, h, x, z;
};

PlantedQp RandomPlantedQp(int n, int m, double density, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> symmetric(-1.0, 1.0), bounded_away(0.1, 1.0),
      unit(0.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (unit(rng) < density) entries.emplace_back(i, j, symmetric(rng));
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  SparseMatrix identity(n, n);
  identity.setIdentity();
  PlantedQp qp;
  qp.P = scale * (SparseMatrix(A.transpose() * A) + 0.1 * identity);
  entries.clear();
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j)
      if (unit(rng) < density) entries.emplace_back(i, j, symmetric(rng));
  qp.G.resize(m, n);
  qp.G.setFromTriplets(entries.begin(), entries.end());
  qp.x = Vector::NullaryExpr(n, [&] { return symmetric(rng); });
  qp.z = Vector::Zero(m);
  Vector slack = Vector::Zero(m);
  for (int i = 0; i < m; ++i) {
    if (i % 2 == 0)
      qp.z[i] = scale * bounded_away(rng);
    else
      slack[i] = bounded_away(rng);
  }
  qp.q = -(qp.P * qp.x) - qp.G.transpose() * qp.z;
  qp.h = qp.G * qp.x + slack;
  return qp;
}

ConvexQpOptions OptionsWithMehrotra(bool mehrotra) {
  ConvexQpOptions options;
  options.mehrotra = mehrotra;
  return options;
}

}  // namespace

TEST_CASE("ConvexQp: two variables, one active constraint, known solution",
          "[convex_qp]") {
  // min (x - 1)^2 + (y - 2.5)^2 = 1/2 x' (2 I) x + (-2, -5) x + const
  // s.t. x + 2 y <= 3, x >= 0, y >= 0.
  // Projection of (1, 2.5) onto x + 2 y = 3: (1, 2.5) - 0.6 (1, 2) = (0.4, 1.3);
  // 2 ((0.4, 1.3) - (1, 2.5)) + z (1, 2) = 0 gives z = 1.2; objective
  // 0.4^2 + 1.3^2 - 2 0.4 - 5 1.3 = -5.45.
  const bool mehrotra = GENERATE(false, true);
  INFO("mehrotra = " << mehrotra);
  Eigen::MatrixXd P(2, 2), G(3, 2);
  P << 2, 0, 0, 2;
  G << 1, 2, -1, 0, 0, -1;
  const Vector q = (Vector(2) << -2, -5).finished();
  const Vector h = (Vector(3) << 3, 0, 0).finished();
  const ConvexQpResult result = SolveConvexQpIpopt(
      Sparse(P), q, Sparse(G), h, Vector::Zero(2), OptionsWithMehrotra(mehrotra));
  INFO(result.BriefReport());
  REQUIRE(result.status == ConvexQpStatus::kSolved);
  CHECK(result.IsSolutionUsable());
  CHECK_THAT(result.message, Contains("Solve_Succeeded"));
  CHECK(result.iterations > 0);
  CHECK(result.iterations < 30);
  CHECK(result.seconds >= 0);
  // Measured: errors ~1e-11 with the default tolerance 1e-10.
  CHECK_THAT(result.x[0], WithinAbs(0.4, 1e-9));
  CHECK_THAT(result.x[1], WithinAbs(1.3, 1e-9));
  CHECK_THAT(result.multipliers[0], WithinAbs(1.2, 1e-9));
  CHECK_THAT(result.multipliers[1], WithinAbs(0.0, 1e-9));
  CHECK_THAT(result.multipliers[2], WithinAbs(0.0, 1e-9));
  CHECK_THAT(result.objective, WithinAbs(-5.45, 1e-9));
  CheckKkt(Sparse(P), q, Sparse(G), h, result, 1e-10);
  // The result's own residuals agree with the recomputed ones.
  CHECK(result.stationarity <= 1e-12);
  CHECK(result.constraint_violation <= 1e-12);
  CHECK(result.dual_infeasibility == 0.0);
  CHECK(result.complementarity <= 1e-10);
}

TEST_CASE("ConvexQp: multipliers carry the sign P x + q + G' z = 0, z >= 0",
          "[convex_qp]") {
  // min 1/2 x^2 - 3 x s.t. x <= 1 (z = 2) and, written the other way round, -x >= -1.
  const SparseMatrix P = Sparse(Eigen::MatrixXd::Constant(1, 1, 1.0));
  const Vector q = Vector::Constant(1, -3.0);
  const SparseMatrix G = Sparse(Eigen::MatrixXd::Constant(1, 1, 1.0));
  const ConvexQpResult result =
      SolveConvexQpIpopt(P, q, G, Vector::Constant(1, 1.0), Vector::Zero(1), {});
  REQUIRE(result.IsSolutionUsable());
  CHECK_THAT(result.x[0], WithinAbs(1.0, 1e-10));
  CHECK_THAT(result.multipliers[0], WithinAbs(2.0, 1e-10));
  // Lower bound x >= 2 written as -x <= -2: stationarity x - 3 - z = 0, z = 1 > 0.
  const SparseMatrix minus_G = Sparse(Eigen::MatrixXd::Constant(1, 1, -1.0));
  const ConvexQpResult lower =
      SolveConvexQpIpopt(P, Vector::Constant(1, -1.0), minus_G, Vector::Constant(1, -2.0),
                         Vector::Zero(1), {});
  REQUIRE(lower.IsSolutionUsable());
  CHECK_THAT(lower.x[0], WithinAbs(2.0, 1e-10));
  CHECK_THAT(lower.multipliers[0], WithinAbs(1.0, 1e-10));
}

TEST_CASE("ConvexQp: 200 variables, planted strictly complementary solution",
          "[convex_qp]") {
  const bool mehrotra = GENERATE(false, true);
  const double scale = GENERATE(1.0, 1e6);  // 1e6: stiffness-like magnitudes of P and z
  INFO("mehrotra = " << mehrotra << ", scale = " << scale);
  const PlantedQp qp = RandomPlantedQp(200, 150, 0.05, scale, 11);
  const ConvexQpResult result = SolveConvexQpIpopt(
      qp.P, qp.q, qp.G, qp.h, Vector::Zero(200), OptionsWithMehrotra(mehrotra));
  INFO(result.BriefReport());
  REQUIRE(result.status == ConvexQpStatus::kSolved);
  // Measured with tolerance 1e-10 (seeds 1..10): ||x - x*||_inf <= 2e-10, relative
  // multiplier error <= 5e-10; complementarity z_i s_i <= 1e-10 relative.
  CHECK((result.x - qp.x).lpNorm<Eigen::Infinity>() <= 1e-8);
  CHECK((result.multipliers - qp.z).lpNorm<Eigen::Infinity>() <=
        1e-8 * qp.z.lpNorm<Eigen::Infinity>());
  CheckKkt(qp.P, qp.q, qp.G, qp.h, result, 1e-10);
  const double optimal_objective = 0.5 * qp.x.dot(qp.P * qp.x) + qp.q.dot(qp.x);
  CHECK_THAT(
      result.objective,
      WithinAbs(optimal_objective, 1e-10 * std::max(1.0, std::abs(optimal_objective))));
}

TEST_CASE("ConvexQp: 200 variables, random data, KKT recomputed", "[convex_qp]") {
  // No planted solution: q random, h in [0, 1] (x = 0 feasible), so the active set and
  // its degeneracy are whatever the data give.
  const unsigned seed = GENERATE(1u, 2u, 3u);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> symmetric(-1.0, 1.0), unit(0.0, 1.0);
  PlantedQp qp = RandomPlantedQp(200, 300, 0.05, 1.0, seed);
  qp.q = 3.0 * Vector::NullaryExpr(200, [&] { return symmetric(rng); });
  qp.h = Vector::NullaryExpr(300, [&] { return unit(rng); });
  const ConvexQpResult result =
      SolveConvexQpIpopt(qp.P, qp.q, qp.G, qp.h, Vector::Zero(200), {});
  INFO(result.BriefReport());
  REQUIRE(result.status == ConvexQpStatus::kSolved);
  // Measured: stationarity ~1e-15, no violation, relative complementarity ~1e-12.
  CheckKkt(qp.P, qp.q, qp.G, qp.h, result, 1e-10);
  // Optimality against a feasible competitor: any feasible point has objective >= ours.
  CHECK(result.objective <= 0.0 + 1e-12);  // x = 0 is feasible with objective 0
}

TEST_CASE("ConvexQp: duplicated constraint rows (non-unique multipliers)",
          "[convex_qp]") {
  Eigen::MatrixXd P(2, 2), G(2, 2);
  P << 2, 0, 0, 2;
  G << 1, 2, 1, 2;
  const Vector q = (Vector(2) << -2, -5).finished();
  const Vector h = (Vector(2) << 3, 3).finished();
  const ConvexQpResult result =
      SolveConvexQpIpopt(Sparse(P), q, Sparse(G), h, Vector::Zero(2), {});
  REQUIRE(result.IsSolutionUsable());
  CHECK_THAT(result.x[0], WithinAbs(0.4, 1e-9));
  CHECK_THAT(result.x[1], WithinAbs(1.3, 1e-9));
  CHECK_THAT(result.multipliers.sum(), WithinAbs(1.2, 1e-9));
  CheckKkt(Sparse(P), q, Sparse(G), h, result, 1e-10);
}

TEST_CASE("ConvexQp: weakly active constraint (no strict complementarity)",
          "[convex_qp]") {
  // min (x - 1)^2 + (y - 2.5)^2 s.t. x <= 1: the unconstrained minimizer (1, 2.5) lies on
  // the constraint, z* = 0. Interior-point iterates approach it like sqrt(mu): this
  // documents the accuracy actually obtained, which is much worse in x than in the KKT
  // residuals. Measured: |x - 1| = 4e-6, z = 8e-6, objective error 2e-11.
  Eigen::MatrixXd P(2, 2), G(1, 2);
  P << 2, 0, 0, 2;
  G << 1, 0;
  const Vector q = (Vector(2) << -2, -5).finished();
  const Vector h = Vector::Constant(1, 1.0);
  const ConvexQpResult result =
      SolveConvexQpIpopt(Sparse(P), q, Sparse(G), h, Vector::Zero(2), {});
  INFO(result.BriefReport());
  REQUIRE(result.IsSolutionUsable());
  CheckKkt(Sparse(P), q, Sparse(G), h, result, 1e-10);
  CHECK_THAT(result.x[0], WithinAbs(1.0, 1e-4));
  CHECK(result.x[0] <= 1.0);
  CHECK_THAT(result.x[1], WithinAbs(2.5, 1e-12));
  CHECK_THAT(result.multipliers[0], WithinAbs(0.0, 1e-4));
  CHECK_THAT(result.objective, WithinAbs(-7.25, 1e-9));
}

TEST_CASE("ConvexQp: linear program (P = 0) with a vertex solution", "[convex_qp]") {
  // min -0.5 x - y s.t. x + y <= 1, x >= 0, y >= 0: vertex (0, 1), z = (1, 0.5, 0).
  const SparseMatrix P(2, 2);
  Eigen::MatrixXd G(3, 2);
  G << 1, 1, -1, 0, 0, -1;
  const Vector q = (Vector(2) << -0.5, -1).finished();
  const Vector h = (Vector(3) << 1, 0, 0).finished();
  const ConvexQpResult result =
      SolveConvexQpIpopt(P, q, Sparse(G), h, Vector::Zero(2), {});
  REQUIRE(result.IsSolutionUsable());
  CHECK_THAT(result.x[0], WithinAbs(0.0, 1e-9));
  CHECK_THAT(result.x[1], WithinAbs(1.0, 1e-9));
  CHECK_THAT(result.multipliers[0], WithinAbs(1.0, 1e-9));
  CHECK_THAT(result.multipliers[1], WithinAbs(0.5, 1e-9));
  CHECK_THAT(result.multipliers[2], WithinAbs(0.0, 1e-9));
  CHECK_THAT(result.objective, WithinAbs(-1.0, 1e-9));
}

TEST_CASE("ConvexQp: no constraints (m = 0) solves P x = -q", "[convex_qp]") {
  Eigen::MatrixXd P(2, 2);
  P << 4, 1, 1, 3;  // q = -P x* makes x* = (0.25, -2) the minimizer
  const Vector expected = (Vector(2) << 0.25, -2.0).finished();
  const Vector q = -P * expected;
  const ConvexQpResult result = SolveConvexQpIpopt(Sparse(P), q, SparseMatrix(0, 2),
                                                   Vector(0), Vector::Zero(2), {});
  REQUIRE(result.IsSolutionUsable());
  CHECK(result.multipliers.size() == 0);
  CHECK_THAT(result.x[0], WithinAbs(0.25, 1e-12));
  CHECK_THAT(result.x[1], WithinAbs(-2.0, 1e-12));
  CHECK(result.complementarity == 0.0);
}

TEST_CASE("ConvexQp: infeasible, unbounded and iteration-limited problems give a status",
          "[convex_qp]") {
  Eigen::MatrixXd P(2, 2);
  P << 2, 0, 0, 2;
  const Vector q = (Vector(2) << -2, -5).finished();
  SECTION("x <= -1 and -x <= -1: infeasible") {
    Eigen::MatrixXd G(2, 2);
    G << 1, 0, -1, 0;
    const ConvexQpResult result = SolveConvexQpIpopt(
        Sparse(P), q, Sparse(G), Vector::Constant(2, -1.0), Vector::Zero(2), {});
    CHECK(result.status == ConvexQpStatus::kInfeasible);
    CHECK_THAT(result.message, Contains("Infeasible_Problem_Detected"));
    CHECK_FALSE(result.IsSolutionUsable());
    CHECK(result.x.size() == 2);
    CHECK(result.constraint_violation > 0.5);  // recomputed residual exposes it
  }
  SECTION("LP min -x - y s.t. x <= 1: unbounded below") {
    Eigen::MatrixXd G(1, 2);
    G << 1, 0;
    const ConvexQpResult result =
        SolveConvexQpIpopt(SparseMatrix(2, 2), Vector::Constant(2, -1.0), Sparse(G),
                           Vector::Constant(1, 1.0), Vector::Zero(2), {});
    CHECK(result.status == ConvexQpStatus::kUnbounded);
    CHECK_THAT(result.message, Contains("Diverging_Iterates"));
    CHECK(result.objective < -1e10);
  }
  SECTION("max_iterations = 1") {
    const PlantedQp qp = RandomPlantedQp(50, 40, 0.1, 1.0, 3);
    ConvexQpOptions options;
    options.max_iterations = 1;
    const ConvexQpResult result =
        SolveConvexQpIpopt(qp.P, qp.q, qp.G, qp.h, Vector::Zero(50), options);
    CHECK(result.status == ConvexQpStatus::kMaxIterations);
    CHECK_THAT(result.message, Contains("Maximum_Iterations_Exceeded"));
    CHECK(result.iterations == 1);
    CHECK(result.x.size() == 50);
    CHECK(result.multipliers.size() == 40);
  }
}

TEST_CASE("ConvexQp: rejected input names expected and actual sizes", "[convex_qp]") {
  const SparseMatrix P2 = Sparse(Eigen::MatrixXd::Identity(2, 2));
  const SparseMatrix G32 = Sparse(Eigen::MatrixXd::Ones(3, 2));
  const Vector q2 = Vector::Zero(2), h3 = Vector::Ones(3), x2 = Vector::Zero(2);
  const ConvexQpOptions options;
  CHECK_THROWS_WITH(SolveConvexQpIpopt(Sparse(Eigen::MatrixXd::Identity(3, 3)), q2, G32,
                                       h3, x2, options),
                    Contains("P must be n x n = 2 x 2 (n = q.size()), got 3 x 3"));
  CHECK_THROWS_WITH(
      SolveConvexQpIpopt(P2, q2, Sparse(Eigen::MatrixXd::Ones(3, 4)), h3, x2, options),
      Contains("G must be m x n = 3 x 2 (m = h.size(), n = q.size()), got 3 x 4"));
  CHECK_THROWS_WITH(SolveConvexQpIpopt(P2, q2, G32, Vector::Ones(2), x2, options),
                    Contains("G must be m x n = 2 x 2") && Contains("got 3 x 2"));
  CHECK_THROWS_WITH(SolveConvexQpIpopt(P2, q2, G32, h3, Vector::Zero(5), options),
                    Contains("x0 must have size n = 2, got 5"));
  CHECK_THROWS_WITH(SolveConvexQpIpopt(SparseMatrix(0, 0), Vector(0), SparseMatrix(0, 0),
                                       Vector(0), Vector(0), options),
                    Contains("q must have at least 1 entry, got 0"));
  Vector bad = x2;
  bad[1] = std::nan("");
  CHECK_THROWS_WITH(SolveConvexQpIpopt(P2, q2, G32, h3, bad, options),
                    Contains("x0 has a non-finite entry"));
  CHECK_THROWS_WITH(SolveConvexQpIpopt(P2, bad, G32, h3, x2, options),
                    Contains("q has a non-finite entry"));
  Eigen::MatrixXd asymmetric(2, 2);
  asymmetric << 2, 1, 0, 2;
  CHECK_THROWS_WITH(SolveConvexQpIpopt(Sparse(asymmetric), q2, G32, h3, x2, options),
                    Contains("P must be symmetric") && Contains("got 1"));
  Eigen::MatrixXd infinite_G = Eigen::MatrixXd::Ones(3, 2);
  infinite_G(2, 1) = INFINITY;
  CHECK_THROWS_WITH(SolveConvexQpIpopt(P2, q2, Sparse(infinite_G), h3, x2, options),
                    Contains("G has a non-finite entry"));
}

TEST_CASE("ConvexQpOptions: IsValid and rejected settings", "[convex_qp]") {
  std::string error;
  CHECK(ConvexQpOptions().IsValid(&error));
  ConvexQpOptions options;
  options.tolerance = 0.0;
  CHECK_FALSE(options.IsValid(&error));
  CHECK_THAT(error, Contains("tolerance must be finite and > 0, got 0"));
  options = ConvexQpOptions();
  options.max_iterations = -3;
  CHECK_FALSE(options.IsValid(&error));
  CHECK_THAT(error, Contains("max_iterations must be >= 0, got -3"));
  options = ConvexQpOptions();
  options.print_level = 13;
  CHECK_FALSE(options.IsValid(&error));
  CHECK_THAT(error, Contains("print_level must be in [0, 12], got 13"));
  options = ConvexQpOptions();
  options.bound_relax_factor = -1e-8;
  CHECK_FALSE(options.IsValid(&error));
  CHECK_THAT(error, Contains("bound_relax_factor must be finite and >= 0"));
  CHECK_THROWS_WITH(
      SolveConvexQpIpopt(Sparse(Eigen::MatrixXd::Identity(1, 1)), Vector::Zero(1),
                         SparseMatrix(0, 1), Vector(0), Vector::Zero(1), options),
      Contains("SolveConvexQpIpopt: ConvexQpOptions: bound_relax_factor"));
}

TEST_CASE("ConvexQpResult: defaults cannot be mistaken for a result, status names",
          "[convex_qp]") {
  const ConvexQpResult result;
  CHECK(result.status == ConvexQpStatus::kNotSolved);
  CHECK(result.message == "not solved yet");
  CHECK(result.iterations == -1);
  CHECK(result.stationarity == -1.0);
  CHECK_FALSE(result.IsSolutionUsable());
  std::set<std::string> names;
  for (ConvexQpStatus status :
       {ConvexQpStatus::kNotSolved, ConvexQpStatus::kSolved, ConvexQpStatus::kAcceptable,
        ConvexQpStatus::kMaxIterations, ConvexQpStatus::kMaxTime,
        ConvexQpStatus::kInfeasible, ConvexQpStatus::kUnbounded,
        ConvexQpStatus::kSmallSearchDirection, ConvexQpStatus::kFailed})
    names.insert(contact::ToString(status));
  CHECK(names.size() == 9);
}
