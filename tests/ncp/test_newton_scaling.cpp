// Badly scaled and singular Newton systems: the equilibrated dense LU
// (Options::scale_newton_system) and the rank-revealing least-squares step
// (Options::minimum_norm_step). Every converged run is checked against data recomputed
// here: the solution of the same problem with unscaled rows, and the natural residual of
// the unscaled problem.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/affine_function.hpp"

using ncp::DenseMatrix;
using ncp::SparseMatrix;
using ncp::TerminationType;
using ncp::Vector;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A mixed LCP with a unique solution: M = 2 I + K + B B' / n (K skew-symmetric, so x'Mx
// >= 2 |x|^2), q normal; the first `free_rows` variables are free, the rest >= 0.
struct MixedLcp {
  DenseMatrix M;
  Vector q, lower, upper;
};

MixedLcp RandomMixedLcp(int n, int free_rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  DenseMatrix B(n, n), K(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = normal(rng), K(i, j) = normal(rng);
  MixedLcp p;
  p.M = 2.0 * DenseMatrix::Identity(n, n) + (K - K.transpose()) +
        B * B.transpose() / static_cast<double>(n);
  p.q.resize(n);
  for (int i = 0; i < n; ++i) p.q(i) = normal(rng);
  p.lower = Vector::Zero(n);
  p.lower.head(free_rows).setConstant(-kInf);
  p.upper = Vector::Constant(n, kInf);
  return p;
}

// Row i of M and q times s_i = 10^e_i, e spread evenly over [-8, 8] in a random order:
// the same solution (a free row is an equation, a pair's w_i >= 0 keeps its sign), a
// Newton matrix whose rows span 16 decades.
MixedLcp ScaleRows(MixedLcp p, unsigned seed) {
  const int n = static_cast<int>(p.q.size());
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  for (int i = 0; i < n; ++i) {
    const double s =
        std::pow(10.0, -8.0 + 16.0 * order[static_cast<size_t>(i)] / (n - 1));
    p.M.row(i) *= s;
    p.q(i) *= s;
  }
  return p;
}

struct Run {
  ncp::Summary summary;
  Vector x;
};

Run SolveLcp(const MixedLcp& p, const ncp::Options& options) {
  const SparseMatrix M = p.M.sparseView();
  ncp::collection::AffineFunction F(M, p.q);
  Run r;
  r.x = Vector::Zero(p.q.size());
  ncp::Solve(options, F, p.lower, p.upper, &r.x, &r.summary);
  return r;
}

// max_i |mid(l_i, u_i, x_i - w_i) - x_i| / (1 + (|M||x| + |q|)_i), w = M x + q.
double NaturalResidual(const MixedLcp& p, const Vector& x) {
  const Vector w = p.M * x + p.q;
  const Vector terms = p.M.cwiseAbs() * x.cwiseAbs() + p.q.cwiseAbs();
  double r = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double projected = std::min(p.upper(i), std::max(p.lower(i), x(i) - w(i)));
    r = std::max(r, std::abs(projected - x(i)) / (1.0 + terms(i)));
  }
  return r;
}

ncp::Options Plain() {
  ncp::Options o;
  o.hybrid = false;
  return o;
}

}  // namespace

TEST_CASE("rows scaled over 16 decades: the equilibrated LU solves as if unscaled") {
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const MixedLcp unscaled = RandomMixedLcp(24, 8, seed);
    const MixedLcp scaled = ScaleRows(unscaled, seed + 100);
    const Run reference = SolveLcp(unscaled, Plain());
    REQUIRE(reference.summary.termination == TerminationType::kConverged);
    REQUIRE(NaturalResidual(unscaled, reference.x) <= 1e-12);

    ncp::Options without = Plain();
    without.scale_newton_system = false;
    without.minimum_norm_step = false;
    const Run before = SolveLcp(scaled, without);
    const Run after = SolveLcp(scaled, Plain());
    INFO("seed " << seed << ": unscaled " << reference.summary.message
                 << "; scaled, no equilibration: " << before.summary.message
                 << ", failed Newton solves " << before.summary.linear_solver_failures
                 << "; equilibrated: " << after.summary.message
                 << ", failed Newton solves " << after.summary.linear_solver_failures);
    // The rank test of the LU calls the scaled matrix singular ...
    CHECK(before.summary.linear_solver_failures > 0);
    // ... the LU of the equilibrated matrix does not. (The iterations differ from the
    // unscaled problem's: FB of rows scaled by 1e-8 .. 1e8 is another merit function.)
    // Converged or at the round-off floor (rows over 16 decades): usable; x checked next.
    CHECK(after.summary.IsSolutionUsable());
    CHECK(after.summary.linear_solver_failures == 0);
    CHECK(after.summary.equilibrated_factorizations > 0);
    CHECK(after.summary.iterations < before.summary.iterations);
    CHECK((after.x - reference.x).lpNorm<Eigen::Infinity>() <=
          1e-8 * (1.0 + reference.x.lpNorm<Eigen::Infinity>()));
    CHECK(NaturalResidual(unscaled, after.x) <= 1e-8);
  }
}

TEST_CASE("well-scaled rows: no equilibration, the same iterates") {
  const MixedLcp p = RandomMixedLcp(24, 8, 7);
  ncp::Options off = Plain();
  off.scale_newton_system = false;
  const Run with = SolveLcp(p, Plain());
  const Run without = SolveLcp(p, off);
  CHECK(with.summary.equilibrated_factorizations == 0);
  CHECK(with.summary.iterations == without.summary.iterations);
  CHECK(with.x == without.x);
}

TEST_CASE("a rank-deficient free block: the minimum-norm step, not the gradient") {
  // x1 + x2 = 1 stated twice (rows 1 and 2 dependent: J singular everywhere), x3 >= 0
  // perp x3 + 1 >= 0. Solutions: x1 + x2 = 1, x3 = 0; the minimum-norm step from 0 lands
  // on the one of least norm, (1/2, 1/2, 0).
  MixedLcp p;
  p.M.resize(3, 3);
  p.M << 1, 1, 0, 2, 2, 0, 0, 0, 1;
  p.q = Vector(3);
  p.q << -1, -2, 1;
  p.lower = Vector(3);
  p.lower << -kInf, -kInf, 0;
  p.upper = Vector::Constant(3, kInf);
  for (const ncp::LinearSolverType backend :
       {ncp::LinearSolverType::kDenseLU, ncp::LinearSolverType::kUmfpack}) {
    ncp::Options options = Plain();
    options.linear_solver = backend;
    const Run r = SolveLcp(p, options);
    ncp::Options off = options;
    off.minimum_norm_step = false;
    const Run before = SolveLcp(p, off);
    INFO(ncp::ToString(backend) << ": " << r.summary.message
                                << "; without the step: " << before.summary.message);
    CHECK(r.summary.termination == TerminationType::kConverged);
    CHECK(r.summary.minimum_norm_steps > 0);
    CHECK(r.summary.gradient_steps == 0);
    CHECK(NaturalResidual(p, r.x) <= 1e-10);
    CHECK(before.summary.gradient_steps > 0);
    CHECK(r.summary.iterations < before.summary.iterations);
    if (backend == ncp::LinearSolverType::kDenseLU) {
      CHECK(std::abs(r.x(0) - 0.5) <= 1e-12);
      CHECK(std::abs(r.x(1) - 0.5) <= 1e-12);
    }
  }
}

TEST_CASE("scaled rows (diagnostic)", "[.scan]") {
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    const MixedLcp unscaled = RandomMixedLcp(24, 8, seed);
    const MixedLcp scaled = ScaleRows(unscaled, seed + 100);
    ncp::Options without = Plain();
    without.scale_newton_system = false;
    without.minimum_norm_step = false;
    const Run runs[3] = {SolveLcp(unscaled, Plain()), SolveLcp(scaled, without),
                         SolveLcp(scaled, Plain())};
    std::printf("seed %u:", seed);
    for (const Run& r : runs)
      std::printf("  %s %d it, %d failed Newton solves, %d gradient, ||Phi|| %.1e |",
                  ToString(r.summary.termination), r.summary.iterations,
                  r.summary.linear_solver_failures, r.summary.gradient_steps,
                  r.summary.final_phi_inf);
    std::printf("\n");
  }
}
