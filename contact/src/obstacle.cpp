#include "contact/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "text_format.hpp"

namespace contact {
namespace {

using internal::Format;

void RequireSpatialSize(const std::string& who, const std::string& what,
                        const Vector& v) {
  if (v.size() != 2 && v.size() != 3)
    throw std::invalid_argument(who + ": " + what + " must have size 2 or 3, got size " +
                                std::to_string(v.size()));
}

void RequireFinite(const std::string& who, const std::string& what, const Vector& v) {
  if (!v.allFinite())
    throw std::invalid_argument(who + ": " + what + " must be finite, got " + Format(v));
}

void RequireFinite(const std::string& who, const std::string& what, double value) {
  if (!std::isfinite(value))
    throw std::invalid_argument(who + ": " + what + " must be finite, got " +
                                Format(value));
}

void RequirePositiveRadius(const std::string& who, double radius) {
  if (!(std::isfinite(radius) && radius > 0))
    throw std::invalid_argument(
        who + ": radius must be finite and > 0, got radius = " + Format(radius));
}

/// Unit vector along v; throws if v is zero.
Vector NormalizedDirection(const std::string& who, const std::string& what,
                           const Vector& v) {
  const double length = v.norm();
  if (!(length > 0) || !std::isfinite(length))
    throw std::invalid_argument(who + ": " + what +
                                " must be a non-zero finite vector, got " + Format(v));
  return v / length;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// RigidObstacle

RigidObstacle::~RigidObstacle() = default;

ObstacleQuery RigidObstacle::Query(const Vector& x) const {
  if (x.size() != dimension())
    throw std::invalid_argument(
        "RigidObstacle::Query (" + Describe() + "): query point must have size " +
        std::to_string(dimension()) + ", got size " + std::to_string(x.size()));
  if (!x.allFinite()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    ObstacleQuery result;
    result.gap = nan;
    result.normal = Vector::Constant(dimension(), nan);
    result.closest_point = Vector::Constant(dimension(), nan);
    return result;
  }
  return QueryValidated(x);
}

// ---------------------------------------------------------------------------------------
// HalfSpace

HalfSpace::HalfSpace(const Vector& normal, double offset) : offset_(offset) {
  RequireSpatialSize("HalfSpace", "normal", normal);
  RequireFinite("HalfSpace", "normal", normal);
  RequireFinite("HalfSpace", "offset", offset);
  normal_ = NormalizedDirection("HalfSpace", "normal", normal);
}

namespace {
Vector AxisVector(const std::string& who, int dimension, int axis) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument(who + ": dimension must be 2 or 3, got " +
                                std::to_string(dimension));
  if (axis < 0 || axis >= dimension)
    throw std::invalid_argument(who + ": axis must be in [0, " +
                                std::to_string(dimension - 1) + "], got " +
                                std::to_string(axis));
  return Vector::Unit(dimension, axis);
}
}  // namespace

HalfSpace HalfSpace::ObstacleBelow(int dimension, int axis, double level) {
  return HalfSpace(AxisVector("HalfSpace::ObstacleBelow", dimension, axis), level);
}

HalfSpace HalfSpace::ObstacleAbove(int dimension, int axis, double level) {
  return HalfSpace(-AxisVector("HalfSpace::ObstacleAbove", dimension, axis), -level);
}

std::string HalfSpace::Describe() const {
  return "HalfSpace{obstacle n.y <= offset, n = " + Format(normal_) +
         ", offset = " + Format(offset_) + " m}";
}

ObstacleQuery HalfSpace::QueryValidated(const Vector& x) const {
  ObstacleQuery result;
  result.gap = normal_.dot(x) - offset_;
  result.normal = normal_;
  result.closest_point = x - result.gap * normal_;
  return result;
}

// ---------------------------------------------------------------------------------------
// ParabolaObstacle

ParabolaObstacle::ParabolaObstacle(int dimension, double vertex, double coefficient)
    : dimension_(dimension), vertex_(vertex), coefficient_(coefficient) {
  if (dimension != 2 && dimension != 3)
    throw std::invalid_argument("ParabolaObstacle: dimension must be 2 or 3, got " +
                                std::to_string(dimension));
  RequireFinite("ParabolaObstacle", "vertex", vertex);
  RequireFinite("ParabolaObstacle", "coefficient", coefficient);
  if (coefficient < 0)
    throw std::invalid_argument(
        "ParabolaObstacle: coefficient must be >= 0 (obstacle x >= vertex + coefficient "
        "|(y, z)|^2 convex), got coefficient = " +
        Format(coefficient));
}

ParabolaObstacle ParabolaObstacle::ThesisExample(int dimension) {
  return ParabolaObstacle(dimension, 5.0, 0.008);
}

std::string ParabolaObstacle::Describe() const {
  return std::string(dimension_ == 2
                         ? "ParabolaObstacle{obstacle x >= a + b y^2"
                         : "ParabolaObstacle{obstacle x >= a + b (y^2 + z^2)") +
         ", a = " + Format(vertex_) + " m, b = " + Format(coefficient_) + " 1/m}";
}

double ParabolaObstacle::ClosestParameter(double x, double rho) const {
  if (rho < 0)
    throw std::invalid_argument(
        "ParabolaObstacle::ClosestParameter: rho must be >= 0 (a distance), got rho = " +
        Format(rho));
  const double b = coefficient_;
  // Orthogonality (x - c(r)) . c'(r) = 0 for c(r) = (a + b r^2, r):
  //   g(r) = 2 b^2 r^3 + p r - rho = 0,  p = 1 - 2 b (x - a);
  // g is half the derivative of the squared distance |(x, rho) - c(r)|^2.
  const double p = 1.0 - 2.0 * b * (x - vertex_);
  if (b == 0.0) return rho;  // the plane x = a: p = 1, r = rho
  if (rho == 0.0) {
    // r = 0 is the minimizer while p >= 0 (up to the centre of curvature at the vertex,
    // x <= a + 1/(2b)); beyond it the minimizers are +-sqrt(-p / (2 b^2)).
    return p >= 0.0 ? 0.0 : std::sqrt(-p / 2.0) / b;
  }
  const auto g = [&](double r) { return r * (2.0 * b * b * r * r + p) - rho; };
  // Bracket [lo, hi] with g(lo) < 0 <= g(hi). g(0) = -rho < 0. For r >= sqrt(|p|)/b,
  // 2 b^2 r^3 + p r >= b^2 r^3, so r >= max(sqrt(|p|)/b, cbrt(rho/b^2)) gives g >= 0;
  // if p > 0, r = rho/p gives g = 2 b^2 (rho/p)^3 > 0 as well.
  double lo = 0.0;
  double hi = std::max(std::sqrt(std::abs(p)) / b, std::cbrt(rho / (b * b)));
  if (p > 0.0) hi = std::min(hi, rho / p);
  // g is convex on r >= 0 and g(0) < 0, so the positive root is unique, g' > 0 to its
  // right and Newton started at hi decreases monotonically onto it. The bracket guards
  // against rounding.
  double r = hi;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double value = g(r);
    if (value == 0.0) return r;
    if (value > 0.0)
      hi = r;
    else
      lo = r;
    const double slope = 6.0 * b * b * r * r + p;
    double next = slope > 0.0 ? r - value / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - r) <= 4.0 * std::numeric_limits<double>::epsilon() * r ||
        next == lo || next == hi)
      return next;
    r = next;
  }
  return r;
}

ObstacleQuery ParabolaObstacle::QueryValidated(const Vector& x) const {
  const double b = coefficient_;
  // Unit direction e of the transverse coordinates (y) or (y, z); tie-break +y on the
  // axis.
  Vector transverse = x.tail(dimension_ - 1);
  const double rho = transverse.norm();
  Vector direction = Vector::Unit(dimension_ - 1, 0);
  if (rho > 0.0) direction = transverse / rho;
  const double r = ClosestParameter(x[0], rho);

  ObstacleQuery result;
  result.closest_point.resize(dimension_);
  result.closest_point[0] = vertex_ + b * r * r;
  result.closest_point.tail(dimension_ - 1) = r * direction;
  // Normal of x = a + b r^2 towards -x: (-1, 2 b r e) / sqrt(1 + 4 b^2 r^2).
  result.normal.resize(dimension_);
  result.normal[0] = -1.0;
  result.normal.tail(dimension_ - 1) = 2.0 * b * r * direction;
  result.normal /= std::sqrt(1.0 + 4.0 * b * b * r * r);
  // x - c is parallel to the normal at the closest point; the projection is exact to
  // first order in the error of r and carries the sign.
  result.gap = result.normal.dot(x - result.closest_point);
  return result;
}

// ---------------------------------------------------------------------------------------
// SphereObstacle

SphereObstacle::SphereObstacle(const Vector& center, double radius)
    : center_(center), radius_(radius) {
  RequireSpatialSize("SphereObstacle", "center", center);
  RequireFinite("SphereObstacle", "center", center);
  RequirePositiveRadius("SphereObstacle", radius);
}

std::string SphereObstacle::Describe() const {
  return std::string(dimension() == 2 ? "SphereObstacle{disc" : "SphereObstacle{ball") +
         " |y - center| <= radius, center = " + Format(center_) +
         " m, radius = " + Format(radius_) + " m}";
}

ObstacleQuery SphereObstacle::QueryValidated(const Vector& x) const {
  const Vector offset = x - center_;
  const double distance = offset.norm();
  ObstacleQuery result;
  result.normal =
      distance > 0.0 ? Vector(offset / distance) : Vector::Unit(dimension(), 0);
  result.gap = distance - radius_;
  result.closest_point = center_ + radius_ * result.normal;
  return result;
}

// ---------------------------------------------------------------------------------------
// CylinderObstacle

CylinderObstacle::CylinderObstacle(const Vector& axis_point, const Vector& axis_direction,
                                   double radius)
    : axis_point_(axis_point), radius_(radius) {
  if (axis_point.size() != 3)
    throw std::invalid_argument(
        "CylinderObstacle: axis_point must have size 3, got size " +
        std::to_string(axis_point.size()));
  if (axis_direction.size() != 3)
    throw std::invalid_argument(
        "CylinderObstacle: axis_direction must have size 3, got size " +
        std::to_string(axis_direction.size()));
  RequireFinite("CylinderObstacle", "axis_point", axis_point);
  RequireFinite("CylinderObstacle", "axis_direction", axis_direction);
  RequirePositiveRadius("CylinderObstacle", radius);
  axis_direction_ =
      NormalizedDirection("CylinderObstacle", "axis_direction", axis_direction);
}

std::string CylinderObstacle::Describe() const {
  return "CylinderObstacle{dist(y, axis) <= radius, axis_point = " + Format(axis_point_) +
         " m, axis_direction = " + Format(axis_direction_) +
         ", radius = " + Format(radius_) + " m}";
}

ObstacleQuery CylinderObstacle::QueryValidated(const Vector& x) const {
  const Vector offset = x - axis_point_;
  Vector radial = offset - offset.dot(axis_direction_) * axis_direction_;
  // A second projection removes the rounding error of the first along d.
  radial -= radial.dot(axis_direction_) * axis_direction_;
  const double distance = radial.norm();
  ObstacleQuery result;
  // Below the rounding level of the projection the radial direction is noise: treat the
  // point as lying on the axis.
  if (distance > 8.0 * std::numeric_limits<double>::epsilon() * offset.norm()) {
    result.normal = radial / distance;
  } else {
    Eigen::Index least_aligned = 0;
    axis_direction_.cwiseAbs().minCoeff(&least_aligned);
    const Vector e = Vector::Unit(3, least_aligned);
    result.normal = (e - e.dot(axis_direction_) * axis_direction_).normalized();
  }
  result.gap = distance - radius_;
  result.closest_point = x - radial + radius_ * result.normal;
  return result;
}

}  // namespace contact
