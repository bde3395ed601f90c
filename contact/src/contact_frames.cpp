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

/// Projects the constrained components out of c->normal (round-off of a normal orthogonal
/// to them); false if one was more than round-off.
bool ProjectConstrained(int dim, ContactNode* c) {
  bool compatible = true;
  for (int a = 0; a < dim; ++a) {
    if (c->dofs[a] >= 0) continue;
    compatible &= std::abs(c->normal(a)) <= 1e-8;
    c->normal(a) = 0.0;
  }
  return compatible;
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
    const Eigen::Vector3d nb = BodyNormal(dim, boundary, frames.boundary_index[c]);
    const double cosine = nb.dot(TowardsObstacle(dim, q));
    if (!(cosine > 0.0) && frames.nodes[c].normal.dot(nb) <= 0.0) {
      gaps(static_cast<Eigen::Index>(c)) = q.gap;  // (follow_body: the obstacle normal)
      continue;
    }
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
                                NormalSource source, double allowed_initial_penetration,
                                bool follow_body) {
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
    const bool away = BodyNormal(dim, boundary, k).dot(towards_obstacle) <= 0.0;
    if (source == NormalSource::kObstacle || (follow_body && away)) {
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
    if (!ProjectConstrained(dim, &c)) {
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

void CurrentContactGeometry(const Mesh& deformed, const ContactBoundary& boundary,
                            const ContactFrames& frames, const RigidObstacle& obstacle,
                            NormalSource source, const Vector& translation,
                            const Eigen::VectorXd& u_free,
                            std::vector<ContactNode>* nodes, Eigen::VectorXd* gaps) {
  const int dim = deformed.dim;
  Eigen::MatrixXd body_normals;
  if (source == NormalSource::kBody)
    body_normals = OutwardNodalNormals(deformed, boundary.group);
  *nodes = frames.nodes;
  gaps->resize(static_cast<Eigen::Index>(frames.nodes.size()));
  for (size_t i = 0; i < frames.nodes.size(); ++i) {
    ContactNode& c = (*nodes)[i];
    const ObstacleQuery q = obstacle.Query(deformed.nodes.col(c.node) - translation);
    const Eigen::Vector3d towards_obstacle = TowardsObstacle(dim, q);
    double gap = q.gap;  // g_c(x) along the obstacle normal [m]
    c.normal = towards_obstacle;
    if (source == NormalSource::kBody) {
      const Eigen::VectorXd nb = body_normals.col(frames.boundary_index[i]);
      const Eigen::Vector3d n(nb(0), nb(1), dim == 3 ? nb(2) : 0.0);
      const double cosine = n.dot(towards_obstacle);
      if (cosine > 0.0) {  // else the far side of the body: the obstacle normal
        c.normal = n;
        gap = q.gap / cosine;
      }
    }
    // A normal along a constrained component cannot turn there (the set-up kept only
    // nodes whose normal was orthogonal to it): the obstacle normal is used then.
    if (!ProjectConstrained(dim, &c)) {
      c.normal = towards_obstacle;
      gap = q.gap;
      ProjectConstrained(dim, &c);
    }
    c.normal.normalize();
    CompleteContactFrame(dim, &c);
    double un = 0.0;  // n_c . u_c [m]
    for (int a = 0; a < dim; ++a)
      if (c.dofs[a] >= 0) un += c.normal(a) * u_free(c.dofs[a]);
    c.gap = gap + un;
    (*gaps)(static_cast<Eigen::Index>(i)) = c.gap;
  }
}

}  // namespace contact
