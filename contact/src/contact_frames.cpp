#include "contact/contact_frames.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace contact {

// The default allowed initial penetration relative to the mesh's size: coordinates
// written with 9 or more significant digits put a node touching the obstacle within this
// of it.
constexpr double kRoundoffPenetration = 1e-9;

const char* ToString(NormalSource s) {
  return s == NormalSource::kObstacle ? "obstacle" : "body";
}

namespace {

/// -(obstacle normal): the direction from the body towards the obstacle.
Eigen::Vector3d TowardsObstacle(int dim, const ObstacleQuery& q) {
  return -Eigen::Vector3d(q.normal(0), q.normal(1), dim == 3 ? q.normal(2) : 0.0);
}

/// The body normal n_b of boundary node k as a 3-vector.
Eigen::Vector3d BodyNormal(int dim, const ContactBoundary& boundary, int k) {
  const Eigen::Matrix<double, Eigen::Dynamic, 1> nb = boundary.normals.col(k);
  return Eigen::Vector3d(nb(0), nb(1), dim == 3 ? nb(2) : 0.0);
}

}  // namespace

Eigen::VectorXd ObstacleGaps(const Mesh& mesh, const ContactBoundary& boundary,
                             const ContactFrames& frames, const RigidObstacle& obstacle,
                             NormalSource source, const Vector& translation) {
  const int dim = mesh.dim;
  if (translation.size() != dim || !translation.allFinite())
    throw std::invalid_argument("the obstacle translation must be " +
                                std::to_string(dim) + " finite numbers [m], got " +
                                std::to_string(translation.size()) +
                                (translation.allFinite() ? "" : " with a NaN or inf"));
  Eigen::VectorXd gaps(static_cast<Eigen::Index>(frames.nodes.size()));
  for (size_t c = 0; c < frames.nodes.size(); ++c) {
    const int node = frames.nodes[c].node;
    const Vector X = mesh.nodes.col(node);
    const ObstacleQuery q = obstacle.Query(X - translation);  // the moved obstacle at X
    if (source == NormalSource::kObstacle) {
      gaps(static_cast<Eigen::Index>(c)) = q.gap;
      continue;
    }
    const double cosine =
        BodyNormal(dim, boundary, frames.boundary_index[c]).dot(TowardsObstacle(dim, q));
    if (!(cosine > 0.0))
      throw std::invalid_argument(
          "at contact node " + std::to_string(node) +
          " the body normal points away from the moved obstacle; use the "
          "obstacle normal (obstacle.normal_source = \"obstacle\")");
    gaps(static_cast<Eigen::Index>(c)) = q.gap / cosine;
  }
  return gaps;
}

ContactFrames MakeContactFrames(const Mesh& mesh, const ContactBoundary& boundary,
                                const DofMap& dofs, const RigidObstacle& obstacle,
                                NormalSource source, double allowed_initial_penetration) {
  const int dim = mesh.dim;
  if (obstacle.dimension() != dim)
    throw std::invalid_argument("the obstacle is " +
                                std::to_string(obstacle.dimension()) +
                                "D but the mesh is " + std::to_string(dim) + "D");
  if (allowed_initial_penetration < 0.0 && mesh.nodes.cols() > 0)
    allowed_initial_penetration =
        kRoundoffPenetration *
        (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).norm();
  ContactFrames out;
  for (int k = 0; k < boundary.NumNodes(); ++k) {
    const int node = boundary.nodes[static_cast<size_t>(k)];
    int num_constrained = 0;
    for (int a = 0; a < dim; ++a)
      num_constrained += dofs.IsConstrained(dim * node + a) ? 1 : 0;
    if (num_constrained == dim) {
      out.excluded_mesh_nodes.push_back(node);
      continue;
    }
    const Vector X = mesh.nodes.col(node);
    const ObstacleQuery q = obstacle.Query(X);
    if (q.gap < -allowed_initial_penetration) {
      std::ostringstream msg;
      msg << "contact node " << node << " at (" << X.transpose()
          << ") starts inside the obstacle (" << obstacle.Describe() << ") by " << -q.gap
          << " m: the body must start outside or touching it - move the obstacle (or the "
             "body) "
             "by at least this distance along the obstacle's normal";
      throw std::invalid_argument(msg.str());
    }
    ContactNode c;
    c.node = node;
    for (int a = 0; a < dim; ++a) c.dofs[a] = dofs.FreeIndex(dim * node + a);
    const Eigen::Vector3d towards_obstacle = TowardsObstacle(dim, q);
    if (source == NormalSource::kObstacle) {
      c.normal = towards_obstacle;
      c.gap = q.gap;
    } else {
      c.normal = BodyNormal(dim, boundary, k);
      const double cosine = c.normal.dot(towards_obstacle);
      if (!(cosine > 0.0)) {
        std::ostringstream msg;
        msg << "at contact node " << node << " (" << X.transpose()
            << ") the body normal (" << c.normal.head(dim).transpose()
            << ") points away from the obstacle; use the obstacle normal or check the "
               "'contact' group";
        throw std::invalid_argument(msg.str());
      }
      c.gap = q.gap / cosine;
    }
    // A constrained component must be orthogonal to the normal (symmetry planes,
    // plane-strain faces); round-off is projected out, anything else leaves the node out
    // of the contact set.
    bool compatible = true;
    for (int a = 0; a < dim; ++a) {
      if (c.dofs[a] >= 0) continue;
      compatible &= std::abs(c.normal(a)) <= 1e-8;
      c.normal(a) = 0.0;
    }
    if (!compatible) {
      out.excluded_mesh_nodes.push_back(node);
      continue;
    }
    c.normal.normalize();
    c.area = boundary.tributary_area(k);
    CompleteContactFrame(dim, &c);
    out.nodes.push_back(c);
    out.boundary_index.push_back(k);
  }
  return out;
}

}  // namespace contact
