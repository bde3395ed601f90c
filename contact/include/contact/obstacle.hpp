/// \file obstacle.hpp
/// Rigid obstacles for the contact problem: the signed distance (normal gap) from a point
/// to the obstacle surface, the obstacle's outward unit normal and the closest surface
/// point.
///
/// Conventions shared by every obstacle (all lengths in metres):
///  - A query point x is a point of the body in the current or reference configuration,
///    an Eigen vector of size dimension() (2 or 3). Coordinates are (x, y) or (x, y, z).
///  - gap(x) is the exact signed Euclidean distance to the obstacle surface:
///    gap > 0 outside the obstacle (on the body side), gap = 0 on the surface,
///    gap < 0 inside the obstacle (penetration depth -gap).
///  - normal(x) is the unit normal of the OBSTACLE surface at the closest point, pointing
///  out
///    of the obstacle (towards the body). Wherever the closest point is unique,
///        x = closest_point + gap * normal   and   grad gap(x) = normal.
///    So non-penetration of a node at X with displacement u, gap(X + u) >= 0, linearizes
///    to gap(X) + normal . u >= 0.
///  - Where the closest point is not unique (the centre of a sphere, the axis of a
///  cylinder,
///    points deep inside a parabola on its axis), gap is still exact but the normal is
///    not differentiable there; each class documents the tie-break it uses.
///  - A query point of the wrong size throws std::invalid_argument. Non-finite
///  coordinates do
///    not throw (they may come from a diverging solver iteration): the result is NaN, so
///    the caller's own non-finite check reports it.
#pragma once

#include <string>

#include "contact/types.hpp"

namespace contact {

/// Result of one closest-point query.
struct ObstacleQuery {
  double gap = 0.0;      ///< signed distance [m]: > 0 outside, < 0 inside the obstacle
  Vector normal;         ///< outward unit normal of the obstacle at closest_point
  Vector closest_point;  ///< point of the obstacle surface nearest to x [m]
};

/// A rigid, fixed obstacle. Implementations override dimension(), QueryValidated() and
/// Describe(); the size check of the query point is done once here.
class RigidObstacle {
 public:
  virtual ~RigidObstacle();

  /// Spatial dimension of the query points, 2 or 3.
  virtual int dimension() const = 0;

  /// Gap, normal and closest point for x. Throws std::invalid_argument if
  /// x.size() != dimension(); NaN/Inf coordinates give NaN in every field.
  ObstacleQuery Query(const Vector& x) const;
  /// Signed distance from x to the obstacle surface [m]: >= 0 outside, < 0 inside.
  double Gap(const Vector& x) const { return Query(x).gap; }
  /// Outward unit normal of the obstacle at the point closest to x (= grad Gap(x)).
  Vector Normal(const Vector& x) const { return Query(x).normal; }

  /// One line naming the shape and its parameters, e.g. for logs and output files.
  virtual std::string Describe() const = 0;

 protected:
  /// Query for a point already checked to have size dimension().
  virtual ObstacleQuery QueryValidated(const Vector& x) const = 0;
};

/// Half-space obstacle {y : n . y <= offset} bounded by a line (2D) or plane (3D).
/// The body lies on the side n . x >= offset, so
///     gap(x) = n . x - offset,   normal = n,   closest point = x - gap(x) n.
class HalfSpace : public RigidObstacle {
 public:
  /// normal: any non-zero finite vector of size 2 or 3, normalized here; the surface is
  /// {n . y = offset} with n the normalized vector, so offset is the signed distance of
  /// the surface from the origin along n [m]. Throws std::invalid_argument for a zero,
  /// non-finite or wrongly sized normal, or a non-finite offset.
  HalfSpace(const Vector& normal, double offset);

  /// Obstacle filling x_axis <= level (a floor under the body): n = +e_axis, offset =
  /// level. E.g. a floor a distance s below a body whose lowest point has y = y0:
  /// ObstacleBelow(2, 1, y0 - s).
  static HalfSpace ObstacleBelow(int dimension, int axis, double level);
  /// Obstacle filling x_axis >= level (a wall the body approaches with increasing
  /// x_axis): n = -e_axis, offset = -level.
  static HalfSpace ObstacleAbove(int dimension, int axis, double level);

  int dimension() const override { return static_cast<int>(normal_.size()); }
  std::string Describe() const override;

  const Vector& normal() const { return normal_; }  ///< unit normal n
  double offset() const { return offset_; }         ///< offset [m]

 protected:
  ObstacleQuery QueryValidated(const Vector& x) const override;

 private:
  Vector normal_;
  double offset_;
};

/// The curved obstacle of the thesis: in 2D the parabola given parametrically by
/// [vertex + coefficient r^2, r], r in R, i.e. the curve x = vertex + coefficient y^2; in
/// 3D the paraboloid of revolution about the x axis, x = vertex + coefficient (y^2 +
/// z^2). The obstacle fills x >= vertex + coefficient (y^2 + z^2) (a convex region for
/// coefficient >= 0) and the body lies at x < vertex + coefficient (y^2 + z^2); the
/// thesis uses vertex = 5 m, coefficient = 0.008 1/m.
///
/// gap is the exact signed Euclidean distance to the curve / surface. With rho = |(y, z)|
/// the closest point is (vertex + b r^2, r (y, z) / rho), b = coefficient, where r >= 0
/// is the root of the orthogonality condition (x - c(r)) . c'(r) = 0, the cubic
///     2 b^2 r^3 + (1 - 2 b (x - vertex)) r - rho = 0,
/// which has exactly one root in r > 0 for rho > 0 (it is convex on r >= 0 and negative
/// at r = 0); it is found by safeguarded Newton from an upper bracket. The normal,
/// (-1, 2 b r (y, z) / rho) / sqrt(1 + 4 b^2 r^2), points towards -x (the body side).
/// Tie-breaks on the axis (rho = 0): beyond the centre of curvature at the vertex,
/// x > vertex + 1 / (2b), the closest points form a circle (3D) or a pair (2D); the one
/// with +y is returned.
class ParabolaObstacle : public RigidObstacle {
 public:
  /// dimension 2 (parabola) or 3 (paraboloid); vertex [m] and coefficient [1/m] finite,
  /// coefficient >= 0 (0 gives the plane x = vertex). Throws std::invalid_argument.
  ParabolaObstacle(int dimension, double vertex, double coefficient);

  /// The obstacle of the thesis' dynamic examples: x = 5 + 0.008 y^2 (+ 0.008 z^2 in 3D).
  static ParabolaObstacle ThesisExample(int dimension);

  int dimension() const override { return dimension_; }
  std::string Describe() const override;

  double vertex() const {
    return vertex_;
  }  ///< a [m]: the surface meets the x axis at x = a
  double coefficient() const { return coefficient_; }  ///< b [1/m]

  /// r >= 0 of the closest point for a point at axial coordinate x and distance rho >= 0
  /// from the axis (see the class comment). Exposed for tests. Throws
  /// std::invalid_argument if rho < 0.
  double ClosestParameter(double x, double rho) const;

 protected:
  ObstacleQuery QueryValidated(const Vector& x) const override;

 private:
  int dimension_;
  double vertex_;
  double coefficient_;
};

/// A ball: the disc (2D) or solid sphere (3D) {y : |y - center| <= radius}; the body lies
/// outside. gap = |x - center| - radius, normal = (x - center) / |x - center|.
/// Tie-break at x = center: normal = +e_x.
class SphereObstacle : public RigidObstacle {
 public:
  /// center of size 2 or 3 with finite entries, radius finite and > 0 [m].
  /// Throws std::invalid_argument.
  SphereObstacle(const Vector& center, double radius);

  int dimension() const override { return static_cast<int>(center_.size()); }
  std::string Describe() const override;

  const Vector& center() const { return center_; }
  double radius() const { return radius_; }

 protected:
  ObstacleQuery QueryValidated(const Vector& x) const override;

 private:
  Vector center_;
  double radius_;
};

/// An infinite solid circular cylinder in 3D, {y : dist(y, axis) <= radius}, with the
/// axis through axis_point along axis_direction; the body lies outside. With v = x -
/// axis_point, d the unit axis direction and w = v - (v . d) d the radial part:
///     gap = |w| - radius,   normal = w / |w|.
/// Tie-break on the axis (w = 0): normal = the unit vector perpendicular to d obtained by
/// normalizing e_k - (e_k . d) d, with e_k the coordinate axis least aligned with d.
class CylinderObstacle : public RigidObstacle {
 public:
  /// axis_point and axis_direction of size 3 with finite entries, direction non-zero
  /// (normalized here), radius finite and > 0 [m]. Throws std::invalid_argument.
  CylinderObstacle(const Vector& axis_point, const Vector& axis_direction, double radius);

  int dimension() const override { return 3; }
  std::string Describe() const override;

  const Vector& axis_point() const { return axis_point_; }
  const Vector& axis_direction() const { return axis_direction_; }  ///< unit vector
  double radius() const { return radius_; }

 protected:
  ObstacleQuery QueryValidated(const Vector& x) const override;

 private:
  Vector axis_point_;
  Vector axis_direction_;
  double radius_;
};

}  // namespace contact
