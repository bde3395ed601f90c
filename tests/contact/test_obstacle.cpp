// Tests of the rigid obstacles: gaps, normals and closest points against hand-computed
// values, the closest-point conditions recomputed here, grad gap = normal by finite
// differences, and the messages of every rejected input.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include "contact/obstacle.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using contact::CylinderObstacle;
using contact::HalfSpace;
using contact::ObstacleQuery;
using contact::ParabolaObstacle;
using contact::RigidObstacle;
using contact::SphereObstacle;
using contact::Vector;

namespace {

Vector V(double x, double y) { return (Vector(2) << x, y).finished(); }
Vector V(double x, double y, double z) { return (Vector(3) << x, y, z).finished(); }

/// Central-difference gradient of the gap; step h [m].
Vector GapGradientByDifferences(const RigidObstacle& obstacle, const Vector& x,
                                double h) {
  Vector gradient(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Vector forward = x, backward = x;
    forward[i] += h;
    backward[i] -= h;
    gradient[i] = (obstacle.Gap(forward) - obstacle.Gap(backward)) / (2 * h);
  }
  return gradient;
}

/// Checks the properties every obstacle shares at x: unit normal, x = c + gap n, the
/// closest point lies on the surface, Gap/Normal agree with Query, grad gap = normal.
void CheckCommonProperties(const RigidObstacle& obstacle, const Vector& x) {
  INFO(obstacle.Describe() << " at x = " << x.transpose());
  const ObstacleQuery query = obstacle.Query(x);
  const double scale = std::max(1.0, x.norm());
  CHECK_THAT(query.normal.norm(), WithinAbs(1.0, 1e-14));
  CHECK((x - query.closest_point - query.gap * query.normal).norm() <= 1e-12 * scale);
  CHECK_THAT(obstacle.Gap(query.closest_point), WithinAbs(0.0, 1e-12 * scale));
  CHECK(obstacle.Gap(x) == query.gap);
  CHECK(obstacle.Normal(x) == query.normal);
  const Vector gradient = GapGradientByDifferences(obstacle, x, 1e-6 * scale);
  CHECK((gradient - query.normal).norm() <= 1e-7);
}

}  // namespace

// ---------------------------------------------------------------------------------------

TEST_CASE("HalfSpace: gap n.x - offset, normal n, normalized on construction",
          "[obstacle]") {
  const HalfSpace floor(V(0, 2), 1.0);  // y >= 1 is the body side
  CHECK(floor.dimension() == 2);
  CHECK(floor.normal() == V(0, 1));
  const ObstacleQuery q = floor.Query(V(3, 4));
  CHECK_THAT(q.gap, WithinAbs(3.0, 1e-15));
  CHECK(q.normal == V(0, 1));
  CHECK_THAT((q.closest_point - V(3, 1)).norm(), WithinAbs(0.0, 1e-15));
  CHECK_THAT(floor.Gap(V(-7, 0.25)), WithinAbs(-0.75, 1e-15));  // inside: penetration

  // Oblique plane in 3D: n = (1, 1, 1)/sqrt(3), offset 2/sqrt(3) (the plane x + y + z =
  // 2).
  const HalfSpace oblique(V(1, 1, 1), 2.0 / std::sqrt(3.0));
  CHECK_THAT(oblique.Gap(V(1, 2, 3)), WithinRel(4.0 / std::sqrt(3.0), 1e-15));
  CHECK_THAT(oblique.Gap(V(0, 0, 0)), WithinRel(-2.0 / std::sqrt(3.0), 1e-15));
  const Vector c = oblique.Query(V(1, 2, 3)).closest_point;
  CHECK_THAT(c.sum(), WithinAbs(2.0, 1e-14));

  CheckCommonProperties(floor, V(0.3, -2.0));
  CheckCommonProperties(oblique, V(-1, 0.5, 4));
}

TEST_CASE("HalfSpace: ObstacleBelow and ObstacleAbove", "[obstacle]") {
  // Floor 0.5 m below a body whose lowest point has y = 0.
  const HalfSpace floor = HalfSpace::ObstacleBelow(2, 1, 0.0 - 0.5);
  CHECK_THAT(floor.Gap(V(10, 0)), WithinAbs(0.5, 1e-15));
  CHECK(floor.Normal(V(10, 0)) == V(0, 1));
  // Flat analogue of the thesis' obstacle: a wall at x = 5, body at x < 5.
  const HalfSpace wall = HalfSpace::ObstacleAbove(3, 0, 5.0);
  CHECK_THAT(wall.Gap(V(4, 1, 2)), WithinAbs(1.0, 1e-15));
  CHECK_THAT(wall.Gap(V(5.25, 1, 2)), WithinAbs(-0.25, 1e-15));
  CHECK(wall.Normal(V(4, 1, 2)) == V(-1, 0, 0));
  CHECK_THAT(wall.Describe(), Contains("HalfSpace") && Contains("offset = -5"));
}

TEST_CASE("HalfSpace: rejected input", "[obstacle]") {
  CHECK_THROWS_WITH(HalfSpace(V(0, 0), 1.0),
                    Contains("normal must be a non-zero finite vector, got (0, 0)"));
  CHECK_THROWS_WITH(HalfSpace(Vector::Ones(4), 1.0),
                    Contains("normal must have size 2 or 3, got size 4"));
  CHECK_THROWS_WITH(HalfSpace(V(0, 1), std::nan("")),
                    Contains("offset must be finite, got nan"));
  CHECK_THROWS_WITH(HalfSpace(V(0, INFINITY), 0.0), Contains("normal must be finite"));
  CHECK_THROWS_WITH(HalfSpace::ObstacleBelow(2, 2, 0.0),
                    Contains("axis must be in [0, 1], got 2"));
  CHECK_THROWS_WITH(HalfSpace::ObstacleAbove(4, 0, 0.0),
                    Contains("dimension must be 2 or 3, got 4"));
  const HalfSpace floor(V(0, 1), 0.0);
  CHECK_THROWS_AS(floor.Gap(V(1, 2, 3)), std::invalid_argument);
  CHECK_THROWS_WITH(floor.Query(V(1, 2, 3)),
                    Contains("query point must have size 2, got size 3"));
}

TEST_CASE("Obstacles: a non-finite query point gives NaN, not an exception",
          "[obstacle]") {
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const ObstacleQuery q = parabola.Query(V(std::nan(""), 1.0));
  CHECK(std::isnan(q.gap));
  CHECK(q.normal.size() == 2);
  CHECK(std::isnan(q.normal[0]));
  CHECK(std::isnan(q.closest_point[1]));
  CHECK(std::isnan(SphereObstacle(V(0, 0, 0), 1.0).Gap(V(INFINITY, 0, 0))));
}

// ---------------------------------------------------------------------------------------
// The thesis' parabola x = 5 + 0.008 y^2 (body at x < 5 + 0.008 y^2).

TEST_CASE("ParabolaObstacle: points on the axis", "[obstacle][parabola]") {
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  CHECK(parabola.vertex() == 5.0);
  CHECK(parabola.coefficient() == 0.008);

  SECTION("body side: the vertex is closest") {
    const ObstacleQuery q = parabola.Query(V(3, 0));
    CHECK_THAT(q.gap, WithinAbs(2.0, 1e-15));
    CHECK(q.normal == V(-1, 0));
    CHECK(q.closest_point == V(5, 0));
  }
  SECTION("inside, before the centre of curvature x = 5 + 1/(2 b) = 67.5") {
    const ObstacleQuery q = parabola.Query(V(10, 0));
    CHECK_THAT(q.gap, WithinAbs(-5.0, 1e-14));
    CHECK(q.closest_point == V(5, 0));
    CHECK_THAT(parabola.Gap(V(67.5, 0)), WithinAbs(-62.5, 1e-12));
  }
  SECTION("inside, beyond the centre of curvature: two closest points, +y chosen") {
    // x = 100: r^2 = -(1 - 2 b (x - a)) / (2 b^2) = 0.52 / 1.28e-4 = 4062.5,
    // c = (5 + 0.008 * 4062.5, sqrt(4062.5)) = (37.5, 63.7377...),
    // |x - c|^2 = 62.5^2 + 4062.5 = 7968.75, shorter than the axial distance 95.
    const ObstacleQuery q = parabola.Query(V(100, 0));
    CHECK_THAT(q.gap, WithinRel(-std::sqrt(7968.75), 1e-14));
    CHECK_THAT(q.closest_point[0], WithinRel(37.5, 1e-14));
    CHECK_THAT(q.closest_point[1], WithinRel(std::sqrt(4062.5), 1e-14));
    CHECK(q.normal[1] > 0);
  }
}

TEST_CASE("ParabolaObstacle: points placed along the normal of a known curve point",
          "[obstacle][parabola]") {
  // x = c(r0) + d n(r0) with c(r0) = (5 + 0.008 r0^2, r0), n(r0) = (-1, 0.016 r0) / |.|.
  // The closest point is c(r0) and the gap d for d > 0 (convex obstacle) and for
  // 0 > d > -(radius of curvature) = -(1 + 4 b^2 r0^2)^{3/2} / (2 b) (>= 62.5 here).
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const double b = 0.008;
  const double r0 = GENERATE(-40.0, -10.0, -0.5, 0.0, 1e-9, 3.0, 25.0, 400.0);
  const double d = GENERATE(1e-12, 0.75, 2.0, 30.0, -1e-12, -0.5, -10.0);
  const Vector c = V(5 + b * r0 * r0, r0);
  const Vector n = V(-1, 2 * b * r0).normalized();
  const Vector x = c + d * n;
  INFO("r0 = " << r0 << ", d = " << d);
  const ObstacleQuery q = parabola.Query(x);
  const double scale = std::max(1.0, x.norm());
  CHECK_THAT(q.gap, WithinAbs(d, 1e-13 * scale));
  CHECK((q.closest_point - c).norm() <= 1e-12 * scale);
  CHECK((q.normal - n).norm() <= 1e-13);
  CHECK_THAT(parabola.ClosestParameter(x[0], std::abs(x[1])),
             WithinAbs(std::abs(r0), 1e-12 * scale));
}

TEST_CASE("ParabolaObstacle: the gap is the global minimum distance to the curve",
          "[obstacle][parabola]") {
  // Recomputes min_r |x - c(r)| by dense sampling of r and golden-section refinement,
  // independently of the cubic, and checks the orthogonality (x - c) || n, |x - c| =
  // |gap|.
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const auto distance = [](const Vector& x, double r) {
    return std::hypot(x[0] - (5 + 0.008 * r * r), x[1] - r);
  };
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> axial(-50.0, 150.0), transverse(-120.0, 120.0);
  for (int trial = 0; trial < 200; ++trial) {
    Vector x = V(axial(rng), transverse(rng));
    if (trial < 5) x[1] = 1e-3 * trial;  // on and near the axis, also beyond the centre
    INFO("x = " << x.transpose());
    // Dense sampling of r in [-400, 400]: the closest point is no farther than the
    // vertex, so |r - y| <= |x - (5, 0)| < 200 and |r| < 320 here.
    double best_r = 0;
    for (double r = -400.0; r <= 400.0; r += 0.01)
      if (distance(x, r) < distance(x, best_r)) best_r = r;
    // Golden-section refinement on [best_r - 0.01, best_r + 0.01].
    double lo = best_r - 0.01, hi = best_r + 0.01;
    for (int k = 0; k < 100; ++k) {
      const double left = lo + 0.382 * (hi - lo), right = hi - 0.382 * (hi - lo);
      if (distance(x, left) < distance(x, right))
        hi = right;
      else
        lo = left;
    }
    const double best = distance(x, 0.5 * (lo + hi));

    const ObstacleQuery q = parabola.Query(x);
    CHECK_THAT(std::abs(q.gap), WithinAbs(best, 1e-11 * std::max(1.0, best)));
    CHECK((q.gap > 0) == (x[0] < 5 + 0.008 * x[1] * x[1]));
    // Closest point on the curve, orthogonality, |x - c| = |gap|.
    CHECK_THAT(q.closest_point[0],
               WithinAbs(5 + 0.008 * q.closest_point[1] * q.closest_point[1],
                         1e-12 * std::max(1.0, q.closest_point[0])));
    const Vector offset = x - q.closest_point;
    const double cross = offset[0] * q.normal[1] - offset[1] * q.normal[0];
    CHECK_THAT(cross, WithinAbs(0.0, 1e-12 * std::max(1.0, x.norm())));
    CHECK_THAT(offset.norm(),
               WithinAbs(std::abs(q.gap), 1e-12 * std::max(1.0, x.norm())));
    CHECK(q.normal[0] < 0);  // normal points towards the body side (-x)
  }
}

TEST_CASE("ParabolaObstacle: grad gap = normal, closest point on the surface",
          "[obstacle][parabola]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const ParabolaObstacle paraboloid = ParabolaObstacle::ThesisExample(3);
  const ParabolaObstacle steep(2, -1.0, 3.0);  // x = -1 + 3 y^2: strong curvature
  for (int trial = 0; trial < 50; ++trial) {
    // Outside, and inside up to 50 m deep (< 62.5 m radius of curvature at the vertex),
    // away from the axis beyond the centre of curvature where the normal jumps.
    CheckCommonProperties(parabola, V(5 + 50 * unit(rng), 60 * unit(rng)));
    CheckCommonProperties(paraboloid,
                          V(5 + 50 * unit(rng), 60 * unit(rng), 60 * unit(rng)));
    CheckCommonProperties(steep,
                          V(-1.1 - 2 * std::abs(unit(rng)), 2 * unit(rng)));  // outside
  }
}

TEST_CASE("ParabolaObstacle: the 3D paraboloid is the 2D parabola rotated about x",
          "[obstacle][parabola]") {
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const ParabolaObstacle paraboloid = ParabolaObstacle::ThesisExample(3);
  const double angle = 0.7;
  for (const Vector& x2 : {V(2, 30), V(40, 70), V(5.1, -3), V(100, 0.5)}) {
    const double rho = x2[1];
    const Vector x3 = V(x2[0], rho * std::cos(angle), rho * std::sin(angle));
    const ObstacleQuery q2 = parabola.Query(x2);
    const ObstacleQuery q3 = paraboloid.Query(x3);
    INFO("x2 = " << x2.transpose());
    CHECK_THAT(q3.gap, WithinAbs(q2.gap, 1e-13 * x2.norm()));
    CHECK_THAT(q3.normal[0], WithinAbs(q2.normal[0], 1e-14));
    CHECK_THAT(q3.normal[1], WithinAbs(q2.normal[1] * std::cos(angle), 1e-14));
    CHECK_THAT(q3.normal[2], WithinAbs(q2.normal[1] * std::sin(angle), 1e-14));
    CHECK_THAT(q3.closest_point[0], WithinAbs(q2.closest_point[0], 1e-12 * x2.norm()));
  }
  // On the axis beyond the centre of curvature: a circle of closest points; +y chosen.
  const ObstacleQuery q = paraboloid.Query(V(100, 0, 0));
  CHECK_THAT(q.gap, WithinRel(-std::sqrt(7968.75), 1e-14));
  CHECK(q.closest_point[1] > 0);
  CHECK(q.closest_point[2] == 0);
}

TEST_CASE("ParabolaObstacle: coefficient 0 is the plane x = vertex",
          "[obstacle][parabola]") {
  const ParabolaObstacle flat(2, 5.0, 0.0);
  const ObstacleQuery q = flat.Query(V(3.5, 100));
  CHECK_THAT(q.gap, WithinAbs(1.5, 1e-15));
  CHECK(q.normal == V(-1, 0));
  CHECK(q.closest_point == V(5, 100));
}

TEST_CASE("ParabolaObstacle: far points and nearly flat parabolas",
          "[obstacle][parabola]") {
  // b = 1e-9: the closest point to (0, 1000) is (a + b r^2, r) with r ~= 1000 and gap
  // ~= a + b 1000^2 = 5.001 (to O(b^2 r^2)): the bracket must not lose r for tiny b.
  const ParabolaObstacle nearly_flat(2, 5.0, 1e-9);
  CHECK_THAT(nearly_flat.Gap(V(0, 1000)), WithinAbs(5.001, 1e-9));
  CheckCommonProperties(nearly_flat, V(0, 1000));
  // Far from the thesis' parabola: x = (-1e4, 1e4).
  const ParabolaObstacle parabola = ParabolaObstacle::ThesisExample(2);
  const Vector far = V(-1e4, 1e4);
  const ObstacleQuery q = parabola.Query(far);
  const double r = q.closest_point[1];
  const double b = 0.008;
  // Orthogonality cubic 2 b^2 r^3 + (1 - 2 b (x - a)) r - y = 0 at the returned r.
  CHECK_THAT(2 * b * b * r * r * r + (1 - 2 * b * (far[0] - 5)) * r - far[1],
             WithinAbs(0.0, 1e-10 * far[1]));
  CheckCommonProperties(parabola, far);
}

TEST_CASE("ParabolaObstacle: rejected input", "[obstacle][parabola]") {
  CHECK_THROWS_WITH(ParabolaObstacle(4, 5.0, 0.008),
                    Contains("dimension must be 2 or 3, got 4"));
  CHECK_THROWS_WITH(
      ParabolaObstacle(2, 5.0, -0.008),
      Contains("coefficient must be >= 0") && Contains("got coefficient = -0.008"));
  CHECK_THROWS_WITH(ParabolaObstacle(2, std::nan(""), 0.008),
                    Contains("vertex must be finite, got nan"));
  CHECK_THROWS_WITH(ParabolaObstacle(3, 5.0, INFINITY),
                    Contains("coefficient must be finite, got inf"));
  CHECK_THROWS_WITH(ParabolaObstacle::ThesisExample(2).ClosestParameter(1.0, -2.0),
                    Contains("rho must be >= 0 (a distance), got rho = -2"));
  CHECK_THROWS_WITH(ParabolaObstacle::ThesisExample(3).Gap(V(1, 2)),
                    Contains("query point must have size 3, got size 2"));
  CHECK_THAT(
      ParabolaObstacle::ThesisExample(2).Describe(),
      Contains("ParabolaObstacle") && Contains("a = 5 m") && Contains("b = 0.008"));
}

// ---------------------------------------------------------------------------------------

TEST_CASE("SphereObstacle: disc and ball", "[obstacle]") {
  const SphereObstacle disc(V(1, 2), 0.5);
  CHECK(disc.dimension() == 2);
  // x - center = (3, 4): distance 5.
  const ObstacleQuery q = disc.Query(V(4, 6));
  CHECK_THAT(q.gap, WithinAbs(4.5, 1e-15));
  CHECK_THAT((q.normal - V(0.6, 0.8)).norm(), WithinAbs(0.0, 1e-15));
  CHECK_THAT((q.closest_point - V(1.3, 2.4)).norm(), WithinAbs(0.0, 1e-15));
  CHECK_THAT(disc.Gap(V(1.3, 2)), WithinAbs(-0.2, 1e-15));
  CHECK(disc.Normal(V(1.3, 2)) == V(1, 0));
  // Tie-break at the centre.
  CHECK_THAT(disc.Gap(V(1, 2)), WithinAbs(-0.5, 1e-15));
  CHECK(disc.Normal(V(1, 2)) == V(1, 0));

  const SphereObstacle ball(V(0, 0, -2), 1.5);
  CHECK_THAT(ball.Gap(V(2, 3, 4)), WithinAbs(7.0 - 1.5, 1e-14));  // |(2, 3, 6)| = 7
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    CheckCommonProperties(disc, V(1 + 3 * unit(rng), 2 + 3 * unit(rng)));
    CheckCommonProperties(ball, V(3 * unit(rng), 3 * unit(rng), -2 + 3 * unit(rng)));
  }
}

TEST_CASE("SphereObstacle: rejected input", "[obstacle]") {
  CHECK_THROWS_WITH(SphereObstacle(V(0, 0), 0.0),
                    Contains("radius must be finite and > 0, got radius = 0"));
  CHECK_THROWS_WITH(SphereObstacle(V(0, 0), -1.0), Contains("got radius = -1"));
  CHECK_THROWS_WITH(SphereObstacle(V(0, 0), std::nan("")), Contains("got radius = nan"));
  CHECK_THROWS_WITH(SphereObstacle(Vector::Zero(1), 1.0),
                    Contains("center must have size 2 or 3, got size 1"));
  CHECK_THROWS_WITH(SphereObstacle(V(0, NAN), 1.0), Contains("center must be finite"));
  CHECK_THROWS_WITH(SphereObstacle(V(0, 0), 1.0).Query(V(1, 2, 3)),
                    Contains("query point must have size 2, got size 3"));
}

TEST_CASE("CylinderObstacle: axis-aligned and oblique", "[obstacle]") {
  const CylinderObstacle vertical(V(0, 0, 0), V(0, 0, 2), 1.0);
  CHECK(vertical.axis_direction() == V(0, 0, 1));
  const ObstacleQuery q = vertical.Query(V(3, 4, 7));
  CHECK_THAT(q.gap, WithinAbs(4.0, 1e-15));
  CHECK_THAT((q.normal - V(0.6, 0.8, 0)).norm(), WithinAbs(0.0, 1e-15));
  CHECK_THAT((q.closest_point - V(0.6, 0.8, 7)).norm(), WithinAbs(0.0, 1e-15));
  // On the axis: gap = -radius, normal perpendicular to the axis (least aligned: e_x).
  CHECK_THAT(vertical.Gap(V(0, 0, -3)), WithinAbs(-1.0, 1e-15));
  CHECK(vertical.Normal(V(0, 0, -3)) == V(1, 0, 0));

  // Axis through (1, 0, 0) along (1, 1, 0)/sqrt(2); x = p + 3 d + 2 e_z is 2 m from it.
  const CylinderObstacle oblique(V(1, 0, 0), V(1, 1, 0), 0.5);
  const Vector d = V(1, 1, 0).normalized();
  const ObstacleQuery qo = oblique.Query(V(1, 0, 0) + 3 * d + 2 * V(0, 0, 1));
  CHECK_THAT(qo.gap, WithinAbs(1.5, 1e-14));
  CHECK_THAT((qo.normal - V(0, 0, 1)).norm(), WithinAbs(0.0, 1e-14));
  const Vector on_axis_normal = oblique.Normal(V(1, 0, 0) + 5 * d);
  CHECK_THAT(on_axis_normal.norm(), WithinAbs(1.0, 1e-15));
  CHECK_THAT(on_axis_normal.dot(d), WithinAbs(0.0, 1e-15));

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial)
    CheckCommonProperties(oblique, V(1 + 3 * unit(rng), 3 * unit(rng), 3 * unit(rng)));
}

TEST_CASE("CylinderObstacle: rejected input", "[obstacle]") {
  CHECK_THROWS_WITH(CylinderObstacle(V(0, 0), V(0, 0, 1), 1.0),
                    Contains("axis_point must have size 3, got size 2"));
  CHECK_THROWS_WITH(CylinderObstacle(V(0, 0, 0), V(0, 1), 1.0),
                    Contains("axis_direction must have size 3, got size 2"));
  CHECK_THROWS_WITH(
      CylinderObstacle(V(0, 0, 0), V(0, 0, 0), 1.0),
      Contains("axis_direction must be a non-zero finite vector, got (0, 0, 0)"));
  CHECK_THROWS_WITH(CylinderObstacle(V(0, 0, 0), V(0, 0, 1), -2.0),
                    Contains("radius must be finite and > 0, got radius = -2"));
  CHECK_THROWS_WITH(CylinderObstacle(V(0, INFINITY, 0), V(0, 0, 1), 1.0),
                    Contains("axis_point must be finite"));
  CHECK_THROWS_WITH(CylinderObstacle(V(0, 0, 0), V(0, 0, 1), 1.0).Gap(V(1, 2)),
                    Contains("query point must have size 3, got size 2"));
}

TEST_CASE("Obstacles through the RigidObstacle interface", "[obstacle]") {
  std::vector<std::unique_ptr<RigidObstacle>> obstacles;
  obstacles.push_back(std::make_unique<HalfSpace>(HalfSpace::ObstacleBelow(3, 2, -1.0)));
  obstacles.push_back(
      std::make_unique<ParabolaObstacle>(ParabolaObstacle::ThesisExample(3)));
  obstacles.push_back(std::make_unique<SphereObstacle>(V(0, 0, 0), 2.0));
  obstacles.push_back(std::make_unique<CylinderObstacle>(V(0, 0, 0), V(1, 0, 0), 2.0));
  for (const auto& obstacle : obstacles) {
    CHECK(obstacle->dimension() == 3);
    CHECK_FALSE(obstacle->Describe().empty());
    CheckCommonProperties(*obstacle, V(0.3, -2.7, 3.1));
  }
}
