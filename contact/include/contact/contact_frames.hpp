/// \file contact_frames.hpp
/// Contact nodes of a body against a rigid obstacle: for each node of Gamma_c its normal,
/// tangents, initial gap and dofs, i.e. the rotation R and the restriction maps X, Y, Z
/// of the thesis (eq. 55): Y picks the normal component of every contact node, Z the
/// tangential ones, X all other dofs.
///
/// Small strain (as in the thesis, section 5): gaps and normals are computed once in the
/// reference configuration. Under finite strain the integrator re-evaluates them every
/// step in the current configuration (CurrentContactGeometry). The non-penetration
/// condition is the linearization  gap_c - n_c . u_c >= 0, exact for a flat obstacle
/// whose normal is used, first order otherwise; large sliding along a curved obstacle is
/// not represented.
#pragma once

#include <string>
#include <vector>

#include "contact/contact_boundary.hpp"
#include "contact/contact_system.hpp"
#include "contact/dof_map.hpp"
#include "contact/obstacle.hpp"

namespace contact {

enum class NormalSource {
  kObstacle,  ///< n_c = -(obstacle normal at the closest point), s_c = obstacle gap
  kBody,      ///< n_c = outward normal of the body at the node (thesis section 5),
              ///< s_c = distance from the node to the obstacle along n_c (first order:
              ///< gap / (n_c . -obstacle normal), exact for flat obstacles)
};
const char* ToString(NormalSource s);

struct ContactFrames {
  std::vector<ContactNode> nodes;   ///< in the free-dof numbering of the DofMap
  std::vector<int> boundary_index;  ///< index k into ContactBoundary for each node
  /// Contact boundary nodes left out because Dirichlet conditions constrain all their
  /// components, or a component along which the normal points (a node with constrained
  /// components orthogonal to its normal stays, working in its free components).
  std::vector<int> excluded_mesh_nodes;
};

/// Throws std::invalid_argument if the obstacle's dimension differs from the mesh's, if
/// a node starts inside the obstacle by more than `allowed_initial_penetration` [m], or
/// if with kBody the body normal points away from the obstacle at a node (n_b . n_o >=
/// 0). A negative `allowed_initial_penetration` (the default) means 1e-9 of the diagonal
/// of the mesh's bounding box: round-off of the mesh coordinates, in the mesh's own
/// length unit.
/// `follow_body` (finite kinematics, CurrentContactGeometry): with kBody a node whose
/// body normal points away from the obstacle (the far side of a body that may turn) takes
/// the obstacle normal and gap instead of being refused.
ContactFrames MakeContactFrames(const Mesh& mesh, const ContactBoundary& boundary,
                                const DofMap& dofs, const RigidObstacle& obstacle,
                                NormalSource source,
                                double allowed_initial_penetration = -1.0,
                                bool follow_body = false);

/// The initial gaps s_c [m] of frames.nodes against `obstacle` translated rigidly by
/// `translation` [m] (size dim: every obstacle point y moves to y + translation),
/// computed as MakeContactFrames computes them with the same `boundary` and `source`; the
/// frames' normals and tangents are kept (the small-displacement setting above). A zero
/// translation gives the nodes' own gaps. A node may end up inside the obstacle (s_c < 0:
/// the next steps push it out). Throws std::invalid_argument for a wrong or non-finite
/// translation, or (kBody) a body normal that points away from the moved obstacle.
Eigen::VectorXd ObstacleGaps(const Mesh& mesh, const ContactBoundary& boundary,
                             const ContactFrames& frames, const RigidObstacle& obstacle,
                             NormalSource source, const Vector& translation);

/// The contact geometry of a body that moves and turns (finite kinematics): the frames of
/// `frames.nodes` re-evaluated in the current configuration x = X + u, with u the full
/// displacement [m] (`deformed` is the mesh with nodes x). For each node the normal n_c
/// is the source's (kBody: the outward normal of the deformed contact boundary at the
/// node, area-weighted as in ContactBoundary::normals; where it points away from the
/// obstacle, or kObstacle: -(obstacle normal at the closest point to x)), the tangents
/// follow it, and s_c is set so that the step's linearized condition
///   s_c - n_c . u_c >= 0   reads   g_c(x) - n_c . du_c >= 0
/// with g_c(x) the current distance to the obstacle (translated by `translation`) along
/// n_c: s_c = g_c(x) + n_c . u_c. Exact to first order in the step's increment du.
void CurrentContactGeometry(const Mesh& deformed, const ContactBoundary& boundary,
                            const ContactFrames& frames, const RigidObstacle& obstacle,
                            NormalSource source, const Vector& translation,
                            const Eigen::VectorXd& u_free,
                            std::vector<ContactNode>* nodes, Eigen::VectorXd* gaps);

}  // namespace contact
