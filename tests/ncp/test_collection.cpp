// Tests of the problem collection itself (no solver): analytic Jacobians against central
// differences, known solutions against the natural residual, the planted random LCPs.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "ncp_collection/collection.hpp"

using ncp::DenseMatrix;
using ncp::SparseMatrix;
using ncp::Vector;
using namespace ncp::collection;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Deterministic points for the Jacobian checks (a simple LCG; values in [-1, 1)).
class PointSampler {
 public:
  explicit PointSampler(std::uint64_t seed) : state_(seed) {}
  double Next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) * 0x1.0p-53 * 2.0 - 1.0;
  }
  Vector Around(const Vector& base, double relative) {
    Vector x = base;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      x(i) += relative * (1.0 + std::abs(base(i))) * Next();
    return x;
  }
  // x_i = base_i (1 + relative u_i): keeps every sign (and zeros).
  Vector Scaled(const Vector& base, double relative) {
    Vector x = base;
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) *= 1.0 + relative * Next();
    return x;
  }

 private:
  std::uint64_t state_;
};

// max_ij |J_ij - Jfd_ij| / max(1, max_ij |J_ij|). Jfd is the Richardson extrapolation
// (4 D(h/2) - D(h))/3 of the central differences D with steps h_j = 1e-6 max(1, |x_j|)
// and h_j/2: the O(h^2) truncation error cancels, which matters where a variable's scale
// is far below h_j (prices ~1e-3 in vonthmcp and mr5mcp, where D(h) alone is off by
// ~1e-5 relative at the solution).
double RelativeJacobianError(ncp::SquareFunction& F, const Vector& x, std::string* why) {
  SparseMatrix J;
  if (!F.Jacobian(x, &J)) {
    *why = "Jacobian() returned false";
    return kInf;
  }
  DenseMatrix Jh, Jhalf;
  if (!CentralDifferenceJacobian(F, x, 1e-6, &Jh) ||
      !CentralDifferenceJacobian(F, x, 0.5e-6, &Jhalf)) {
    *why = "F not evaluable next to x";
    return kInf;
  }
  const DenseMatrix Jfd = (4.0 * Jhalf - Jh) / 3.0;
  const DenseMatrix Jd(J);
  const double scale = std::max(1.0, Jd.lpNorm<Eigen::Infinity>());
  return (Jd - Jfd).lpNorm<Eigen::Infinity>() / scale;
}

// Points at which to check a problem's Jacobian: its starts, its known solutions and
// random perturbations of both (1e-3, 10% and 50% relative), kept where F is evaluable.
// A perturbation that leaves the domain of F (a price of order 1e-3 pushed below 0) is
// replaced by one that keeps the signs, x_i = base_i (1 + relative u_i).
std::vector<Vector> JacobianCheckPoints(TestProblem& p, PointSampler* sampler) {
  std::vector<Vector> bases;
  for (const StartPoint& s : p.starts) bases.push_back(s.x);
  for (const Vector& s : p.solutions) bases.push_back(s);
  std::vector<Vector> points;
  Vector Fx(p.NumVariables());
  for (const Vector& base : bases) {
    for (double relative : {0.0, 1e-3, 0.1, 0.5}) {
      Vector x = sampler->Around(base, relative);
      if (!p.F->Evaluate(x, &Fx)) x = sampler->Scaled(base, relative);
      if (p.F->Evaluate(x, &Fx)) points.push_back(x);
    }
  }
  return points;
}

}  // namespace

TEST_CASE("every collection Jacobian matches central differences", "[collection]") {
  PointSampler sampler(12345);
  std::vector<TestProblem> problems = StandardCollection();
  for (TestProblem& p : problems) {
    const std::vector<Vector> points = JacobianCheckPoints(p, &sampler);
    INFO(p.name);
    CHECK(points.size() >= 4);
    for (const Vector& x : points) {
      std::string why;
      const double error = RelativeJacobianError(*p.F, x, &why);
      INFO("at x = " << x.transpose().head(std::min<Eigen::Index>(6, x.size())) << " ... "
                     << why);
      CHECK(error <= 1e-6);
    }
  }
}

TEST_CASE("Jacobians near domain boundaries match central differences", "[collection]") {
  // Nash-Cournot: f_i'' = q_i^(1/beta_i - 1)/beta_i L^(1/beta_i) is steep near q_i = 0.
  TestProblem nash = NashCournot5();
  Vector q(5);
  q << 1e-2, 0.5, 3.0, 1e-2, 1e-3;
  std::string why;
  CHECK(RelativeJacobianError(*nash.F, q, &why) <= 1e-5);
  // Mathiesen near its poles x2 = -1, x3 = -1.
  TestProblem mathiesen = ModifiedMathiesen();
  Vector x(4);
  x << 0.7, -0.9, -0.8, 2.0;
  CHECK(RelativeJacobianError(*mathiesen.F, x, &why) <= 1e-6);
}

TEST_CASE("problems outside their domain report evaluation failure", "[collection]") {
  Vector F4(4), F5(5);
  TestProblem mathiesen = ModifiedMathiesen();
  Vector x(4);
  x << 1, -1, 0, 0;  // pole x2 = -1
  CHECK_FALSE(mathiesen.F->Evaluate(x, &F4));
  TestProblem nash = NashCournot5();
  CHECK_FALSE(nash.F->Evaluate(Vector::Zero(5), &F5));  // Q = 0
  Vector q = Vector::Constant(5, 1.0);
  q(2) = -0.5;
  CHECK_FALSE(nash.F->Evaluate(q, &F5));
  // beta_1 = 1.2 > 1: f_1'' = +inf at q_1 = 0, so no Jacobian there.
  q(2) = 1.0;
  q(0) = 0.0;
  CHECK(nash.F->Evaluate(q, &F5));
  SparseMatrix J;
  CHECK_FALSE(nash.F->Jacobian(q, &J));
}

TEST_CASE("Jacobian sparsity patterns stay fixed", "[collection]") {
  PointSampler sampler(777);
  std::vector<TestProblem> problems = StandardCollection();
  for (TestProblem& p : problems) {
    INFO(p.name);
    const std::vector<Vector> points = JacobianCheckPoints(p, &sampler);
    REQUIRE(points.size() >= 2);
    SparseMatrix J1, J2;
    REQUIRE(p.F->Jacobian(points.front(), &J1));
    REQUIRE(p.F->Jacobian(points.back(), &J2));
    REQUIRE(J1.nonZeros() == J2.nonZeros());
    CHECK(std::equal(J1.innerIndexPtr(), J1.innerIndexPtr() + J1.nonZeros(),
                     J2.innerIndexPtr()));
    CHECK(std::equal(J1.outerIndexPtr(), J1.outerIndexPtr() + J1.cols() + 1,
                     J2.outerIndexPtr()));
  }
}

TEST_CASE("collection entries are well formed", "[collection]") {
  std::vector<TestProblem> problems = StandardCollection();
  CHECK(problems.size() == 29);
  for (const TestProblem& p : problems) {
    INFO(p.name);
    const int n = p.NumVariables();
    CHECK(n >= 1);
    CHECK(!p.source.empty());
    CHECK(p.lower.size() == n);
    CHECK(p.upper.size() == n);
    CHECK((p.lower.array() <= p.upper.array()).all());
    CHECK(!p.starts.empty());
    for (const StartPoint& s : p.starts) CHECK(s.x.size() == n);
    for (const Vector& s : p.solutions) CHECK(s.size() == n);
  }
  TestProblem kojshin = KojimaShindo();
  CHECK(kojshin.starts.size() == 8);  // all 8 MCPLIB starting points
  CHECK(kojshin.IsStandardNcp());
  CHECK_FALSE(Obstacle1D(10, ObstacleKind::kTwoSidedBand).IsStandardNcp());
  const TestProblem billups = Billups();
  CHECK(billups.FindExpectedFailure("0", ncp::NcpFunction::kFischerBurmeister) !=
        nullptr);
  CHECK(billups.FindExpectedFailure("0", ncp::NcpFunction::kMin) != nullptr);
  CHECK(billups.FindExpectedFailure("3", ncp::NcpFunction::kFischerBurmeister) ==
        nullptr);
}

TEST_CASE("natural residual on hand-computed points", "[collection]") {
  // F(x) = 0 x + q, so F(x) = q at every x.
  SparseMatrix zero(3, 3);
  Vector q(3);
  q << 0.0, 3.0, -1.0;
  AffineFunction F(zero, q);
  const Vector l = Vector::Zero(3), u = Vector::Constant(3, kInf);
  Vector x(3);
  x << 1.0, 0.0, 2.0;
  // |1 - max(0, 1 - 0)| = 0, |0 - max(0, -3)| = 0, |2 - max(0, 2 + 1)| = 1.
  CHECK(NaturalResidual(F, l, u, x) == Approx(1.0));
  x(2) = 0.0;  // x3 = 0 with F3 = -1 < 0: |0 - max(0, 1)| = 1
  CHECK(NaturalResidual(F, l, u, x) == Approx(1.0));
  q(2) = 0.0;
  AffineFunction G(zero, q);
  CHECK(NaturalResidual(G, l, u, x) == 0.0);
  // Box [-1, 1], x = 0.5, F = 2: mid(-1, 1, -1.5) = -1, residual 1.5.
  SparseMatrix zero1(1, 1);
  AffineFunction H(zero1, Vector::Constant(1, 2.0));
  CHECK(NaturalResidual(H, Vector::Constant(1, -1.0), Vector::Constant(1, 1.0),
                        Vector::Constant(1, 0.5)) == Approx(1.5));
  // At the upper bound with F <= 0 it is a solution.
  AffineFunction K(zero1, Vector::Constant(1, -2.0));
  CHECK(NaturalResidual(K, Vector::Constant(1, -1.0), Vector::Constant(1, 1.0),
                        Vector::Constant(1, 1.0)) == 0.0);
  // Not evaluable: +inf.
  TestProblem mathiesen = ModifiedMathiesen();
  Vector bad(4);
  bad << 0, -2, 0, 0;
  CHECK(std::isinf(NaturalResidual(*mathiesen.F, mathiesen.lower, mathiesen.upper, bad)));
  CHECK_THROWS_AS(NaturalResidual(F, l, u, Vector::Zero(2)), std::invalid_argument);
}

TEST_CASE("known solutions have zero natural residual", "[collection]") {
  std::vector<TestProblem> problems = StandardCollection();
  for (TestProblem& p : problems) {
    for (const Vector& s : p.solutions) {
      INFO(p.name << " at " << s.transpose().head(std::min<Eigen::Index>(6, s.size())));
      // nash5's reference solution is quoted to 4 decimals in the literature.
      const double tolerance = p.name == "nash5" ? 1e-3 : 1e-12;
      CHECK(NaturalResidual(*p.F, p.lower, p.upper, s) <= tolerance);
    }
  }
  // The kojshin solutions: (sqrt(6)/2, 0, 0, 1/2) degenerate in component 3 only.
  TestProblem kojshin = KojimaShindo();
  Vector F(4);
  REQUIRE(kojshin.F->Evaluate(kojshin.solutions[0], &F));
  CHECK(F(0) == Approx(0.0).margin(1e-14));
  CHECK(F(1) == Approx(2.0 + std::sqrt(6.0) / 2));
  CHECK(F(2) == Approx(0.0).margin(1e-14));  // x3 = F3 = 0: the degenerate pair
  CHECK(F(3) == Approx(0.0).margin(1e-14));
  REQUIRE(kojshin.F->Evaluate(kojshin.solutions[1], &F));
  CHECK(F(1) == Approx(31.0));
  CHECK(F(3) == Approx(4.0));
  // Billups: F(0) = -0.01, so 0 is not a solution.
  TestProblem billups = Billups();
  CHECK(NaturalResidual(*billups.F, billups.lower, billups.upper, Vector::Zero(1)) ==
        Approx(0.01));
}

TEST_CASE("random P-matrix LCPs are strictly diagonally dominant and reproducible",
          "[collection]") {
  RandomLcpOptions options;
  options.degenerate_fraction = 0.2;
  TestProblem a = RandomPLcp(300, options);
  TestProblem b = RandomPLcp(300, options);
  options.seed += 1;
  TestProblem c = RandomPLcp(300, options);
  const auto& Fa = dynamic_cast<const AffineFunction&>(*a.F);
  const auto& Fb = dynamic_cast<const AffineFunction&>(*b.F);
  const auto& Fc = dynamic_cast<const AffineFunction&>(*c.F);
  CHECK(Fa.q() == Fb.q());
  CHECK(a.solutions[0] == b.solutions[0]);
  CHECK(Fa.q() != Fc.q());
  const DenseMatrix M(Fa.M());
  for (int i = 0; i < M.rows(); ++i) {
    const double off = M.row(i).cwiseAbs().sum() - std::abs(M(i, i));
    CHECK(M(i, i) > off);
  }
  CHECK(Fa.M().nonZeros() == 300 * 5);  // 4 off-diagonal + 1 diagonal per row
  // Planted pair: complementary, and the mix of index types is as requested.
  Vector w(300);
  REQUIRE(a.F->Evaluate(a.solutions[0], &w));
  int degenerate = 0, active = 0;
  for (int i = 0; i < 300; ++i) {
    const double xi = a.solutions[0](i);
    CHECK(xi * w(i) == Approx(0.0).margin(1e-12));
    if (xi > 0) ++active;
    if (xi == 0 && std::abs(w(i)) < 1e-12) ++degenerate;
  }
  CHECK(degenerate > 30);  // about 20% of 300
  CHECK(degenerate < 90);
  CHECK(active > 60);
}

TEST_CASE("obstacle problems have the documented sizes and bounds", "[collection]") {
  TestProblem one = Obstacle1D(50);
  CHECK(one.NumVariables() == 50);
  TestProblem two = Obstacle2D(7, ObstacleKind::kTwoSidedBand);
  CHECK(two.NumVariables() == 49);
  CHECK(two.lower.maxCoeff() == -0.1);
  CHECK(two.upper.minCoeff() == 0.1);
  // 5-point stencil: 5 m^2 - 4 m nonzeros, diagonal 4/h^2 = 4 * 64.
  SparseMatrix A;
  REQUIRE(two.F->Jacobian(Vector::Zero(49), &A));
  CHECK(A.nonZeros() == 5 * 49 - 4 * 7);
  CHECK(A.coeff(24, 24) == Approx(256.0));
  CHECK(A.coeff(24, 25) == Approx(-64.0));
  CHECK(A.coeff(24, 31) == Approx(-64.0));
  // The stencil evaluation of F agrees with the assembled A u - f.
  Vector u = Vector::LinSpaced(49, -0.3, 0.7), F(49), F0(49);
  REQUIRE(two.F->Evaluate(u, &F));
  REQUIRE(two.F->Evaluate(Vector::Zero(49), &F0));  // F(0) = -f
  CHECK((F - (A * u + F0)).lpNorm<Eigen::Infinity>() <= 1e-12 * 256);
  // The exact 1D bump solution is C^1 at the free boundary a = 1/2 - (2 - sqrt 3)/4.
  const double a = 0.5 - (2.0 - std::sqrt(3.0)) / 4.0;
  CHECK(ExactLowerBump1D(a - 1e-9) == Approx(ExactLowerBump1D(a + 1e-9)).epsilon(1e-7));
  CHECK(ExactLowerBump1D(0.5) == Approx(0.5));
  CHECK(ExactLowerBump1D(0.0) == 0.0);
  CHECK_THROWS_AS(Obstacle2D(0), std::invalid_argument);
}

TEST_CASE("obstacle problems in the gap variable are the same problems shifted by l",
          "[collection]") {
  for (ObstacleKind kind : {ObstacleKind::kLowerBump, ObstacleKind::kTwoSidedBand}) {
    for (int dimension : {1, 2}) {
      TestProblem height = dimension == 1 ? Obstacle1D(40, kind) : Obstacle2D(6, kind);
      TestProblem gap = dimension == 1 ? Obstacle1D(40, kind, ObstacleVariable::kGap)
                                       : Obstacle2D(6, kind, ObstacleVariable::kGap);
      const int n = height.NumVariables();
      INFO(gap.name);
      REQUIRE(gap.NumVariables() == n);
      CHECK(gap.name == height.name + "-gap");
      CHECK(gap.lower == Vector::Zero(n));
      CHECK(gap.upper == height.upper - height.lower);
      REQUIRE(gap.starts.size() == height.starts.size());
      for (size_t s = 0; s < gap.starts.size(); ++s)
        CHECK(gap.starts[s].x == height.starts[s].x - height.lower);
      // G(w) = F(w + l) at sample points, to the round-off of F (h^-2 ~ 1700 or 49).
      Vector w = Vector::LinSpaced(n, 0.0, 0.3), G(n), F(n);
      REQUIRE(gap.F->Evaluate(w, &G));
      REQUIRE(height.F->Evaluate(w + height.lower, &F));
      CHECK((G - F).lpNorm<Eigen::Infinity>() <= 1e-11);
      SparseMatrix JG, JF;
      REQUIRE(gap.F->Jacobian(w, &JG));
      REQUIRE(height.F->Jacobian(w + height.lower, &JF));
      CHECK((JG - JF).norm() == 0.0);
    }
  }
}

TEST_CASE("COPS grid problems: F is the gradient of the objective of the .gms",
          "[collection]") {
  // A small grid with interior_x != interior_y, so that swapped indices would show.
  const int mx = 6, my = 4;
  struct Case {
    TestProblem problem;
    double (*objective)(int, int, const Vector&);
  };
  Case cases[] = {{JournalBearing(mx, my), &JournalBearingObjective},
                  {Torsion(mx, my), &TorsionObjective},
                  {MinimalSurface(mx, my), &MinimalSurfaceObjective}};
  PointSampler sampler(2024);
  for (Case& c : cases) {
    TestProblem& p = c.problem;
    INFO(p.name);
    REQUIRE(p.NumVariables() == mx * my);
    for (double relative : {0.0, 0.1, 0.5}) {
      const Vector v = sampler.Around(p.starts[0].x, relative);
      Vector F(mx * my);
      REQUIRE(p.F->Evaluate(v, &F));
      // Central differences of f, step 1e-5: exact for the quadratics up to rounding,
      // O(1e-10) truncation error for minsurf.
      Vector gradient(mx * my);
      for (int k = 0; k < mx * my; ++k) {
        Vector plus = v, minus = v;
        plus(k) += 1e-5;
        minus(k) -= 1e-5;
        gradient(k) = (c.objective(mx, my, plus) - c.objective(mx, my, minus)) / 2e-5;
      }
      CHECK((F - gradient).lpNorm<Eigen::Infinity>() <=
            1e-7 * std::max(1.0, F.lpNorm<Eigen::Infinity>()));
    }
    CHECK_THROWS_AS(c.objective(mx, my, Vector::Zero(3)), std::invalid_argument);
  }
  // The quadratics vanish at v = 0 (zero boundary values); F(0) is the linear term.
  CHECK(JournalBearingObjective(mx, my, Vector::Zero(mx * my)) == 0.0);
  CHECK(TorsionObjective(mx, my, Vector::Zero(mx * my)) == 0.0);
  // Torsion: the bounds are the distance to the boundary, 1/7 .. at most 2/7 here.
  const TestProblem torsion = Torsion(mx, my);
  CHECK(torsion.upper(0) == Approx(1.0 / 7));
  CHECK((torsion.lower + torsion.upper).cwiseAbs().maxCoeff() == 0.0);
  // minsurf: the obstacle v >= 1 covers nodes floor(0.25 nx)..ceil(0.75 nx) in each
  // direction: i = 1..6 of nx = 7 and j = 1..4 of ny = 5, i.e. every node here.
  CHECK(MinimalSurface(mx, my).lower.minCoeff() == 1.0);
  CHECK_THROWS_AS(MinimalSurface(0, 3), std::invalid_argument);
}

TEST_CASE("mr5mcp: the .gms start is the calibrated production benchmark",
          "[collection]") {
  // At the start y = qref y0, k = qref k0, w = pref, rk = rk0 pref, so W = R = 1 and
  // labor and capital demand equal the supplies l = l0 qref and k: mkt_l = mkt_k = 0
  // for every region and period; prf_y = log(pref(t,r) / p(t)) = 0 for usa (p = pref
  // of usa). Layout: y, inv, k (55 each), p (11), ptc (5), w, pk, rk (55 each), i (4).
  TestProblem p = Mr5Mcp();
  REQUIRE(p.NumVariables() == 350);
  Vector F(350);
  REQUIRE(p.F->Evaluate(p.starts[0].x, &F));
  const int w = 3 * 55 + 11 + 5, rk = w + 2 * 55;
  CHECK(F.segment(w, 55).lpNorm<Eigen::Infinity>() <= 1e-12);
  CHECK(F.segment(rk, 55).lpNorm<Eigen::Infinity>() <= 1e-12);
  CHECK(F.head(11).lpNorm<Eigen::Infinity>() <= 1e-12);  // prf_y of usa
}

TEST_CASE("simplex projection: the closed-form point solves the mixed system",
          "[collection]") {
  Vector a(4);
  a << 0.8, 0.6, -0.2, 0.1;  // tau = 0.2: x = (0.6, 0.4, 0, 0), y = -0.2
  MixedTestProblem p = SimplexProjection(a);
  REQUIRE(p.solutions.size() == 1);
  const Vector& z = p.solutions[0];
  CHECK(z(0) == Approx(-0.2));
  CHECK(z(1) == Approx(0.6));
  CHECK(z(2) == Approx(0.4));
  CHECK(z(3) == 0.0);
  CHECK(z(4) == 0.0);
  Vector E(1), A(4), B(4);
  REQUIRE(p.problem->Evaluate(z, &E, &A, &B));
  CHECK(std::abs(E(0)) < 1e-15);
  for (int j = 0; j < 4; ++j) CHECK(std::min(A(j), B(j)) == Approx(0.0).margin(1e-15));
  // Jacobian blocks against differences of E, A, B (they are affine, so exact).
  SparseMatrix JE, JA, JB;
  REQUIRE(p.problem->Jacobian(z, &JE, &JA, &JB));
  Vector dz = Vector::LinSpaced(5, 0.1, 0.5), E2(1), A2(4), B2(4);
  REQUIRE(p.problem->Evaluate(z + dz, &E2, &A2, &B2));
  CHECK((JE * dz - (E2 - E)).norm() < 1e-14);
  CHECK((JA * dz - (A2 - A)).norm() < 1e-14);
  CHECK((JB * dz - (B2 - B)).norm() < 1e-14);
}
