#include "contact/contact_frames.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace contact {

// The default allowed initial penetration relative to the mesh's size: coordinates written
// with 9 or more significant digits put a node touching the obstacle within this of it.
constexpr double kRoundoffPenetration = 1e-9;

const char* ToString(NormalSource s) {
  return s == NormalSource::kObstacle ? "obstacle" : "body";
}

ContactFrames MakeContactFrames(const Mesh& mesh, const ContactBoundary& boundary,
                                const DofMap& dofs, const RigidObstacle& obstacle,
                                NormalSource source, double allowed_initial_penetration) {
  const int dim = mesh.dim;
  if (obstacle.dimension() != dim)
    throw std::invalid_argument("the obstacle is " +
                                std::to_string(obstacle.dimension()) + "D but the mesh is " +
                                std::to_string(dim) + "D");
  if (allowed_initial_penetration < 0.0 && mesh.nodes.cols() > 0)
    allowed_initial_penetration =
        kRoundoffPenetration *
        (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).norm();
  ContactFrames out;
  for (int k = 0; k < boundary.NumNodes(); ++k) {
    const int node = boundary.nodes[static_cast<size_t>(k)];
    int num_constrained = 0;
    for (int a = 0; a < dim; ++a) num_constrained += dofs.IsConstrained(dim * node + a) ? 1 : 0;
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
          << " m: the body must start outside or touching it - move the obstacle (or the body) "
             "by at least this distance along the obstacle's normal";
      throw std::invalid_argument(msg.str());
    }
    ContactNode c;
    c.node = node;
    for (int a = 0; a < dim; ++a) c.dofs[a] = dofs.FreeIndex(dim * node + a);
    const Eigen::Vector3d towards_obstacle =
        -Eigen::Vector3d(q.normal(0), q.normal(1), dim == 3 ? q.normal(2) : 0.0);
    if (source == NormalSource::kObstacle) {
      c.normal = towards_obstacle;
      c.gap = q.gap;
    } else {
      const Eigen::Matrix<double, Eigen::Dynamic, 1> nb = boundary.normals.col(k);
      c.normal = Eigen::Vector3d(nb(0), nb(1), dim == 3 ? nb(2) : 0.0);
      const double cosine = c.normal.dot(towards_obstacle);
      if (!(cosine > 0.0)) {
        std::ostringstream msg;
        msg << "at contact node " << node << " (" << X.transpose()
            << ") the body normal (" << c.normal.head(dim).transpose()
            << ") points away from the obstacle; use the obstacle normal or check the 'contact' group";
        throw std::invalid_argument(msg.str());
      }
      c.gap = q.gap / cosine;
    }
    // A constrained component must be orthogonal to the normal (symmetry planes, plane-strain
    // faces); round-off is projected out, anything else leaves the node out of the contact set.
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
