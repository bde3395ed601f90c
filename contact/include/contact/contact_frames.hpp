/// \file contact_frames.hpp
/// Contact nodes of a body against a rigid obstacle: for each node of Gamma_c its normal,
/// tangents, initial gap and dofs, i.e. the rotation R and the restriction maps X, Y, Z
/// of the thesis (eq. 55): Y picks the normal component of every contact node, Z the
/// tangential ones, X all other dofs.
///
/// Small-displacement limitation (as in the thesis, section 5): gaps and normals are
/// computed once in the reference configuration. The non-penetration condition is the
/// linearization  gap_c - n_c . u_c >= 0, exact for a flat obstacle whose normal is used,
/// first order otherwise; large sliding along a curved obstacle is not represented.
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
ContactFrames MakeContactFrames(const Mesh& mesh, const ContactBoundary& boundary,
                                const DofMap& dofs, const RigidObstacle& obstacle,
                                NormalSource source,
                                double allowed_initial_penetration = -1.0);

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

}  // namespace contact
