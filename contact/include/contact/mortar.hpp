/// \file mortar.hpp
/// Mortar (segment-to-segment) contact constraints between bodies with non-matching
/// meshes, with dual Lagrange multipliers (Wohlmuth 2000; Popp, Gee, Wall 2009): on the
/// slave surface the multiplier is interpolated with the dual basis Phi_j, biorthogonal
/// to the slave shape functions, int Phi_j N_k dS = delta_jk D_jj, so the mortar matrix D
/// is diagonal and every constraint stays attached to one slave node j:
///     D_jj = h int_(Gamma_s) N_j dS,      M_jk = h int_(Gamma_s) Phi_j (N_k^m o pi) dS,
/// with pi the projection of the slave surface onto the master surface along the slave
/// segment normal, h the thickness in 2D. The normal gap of slave node j, in metres,
///     g_j = n_j . ( sum_k M_jk / D_jj x_k^m - x_j^s ),   x = X + u,
/// with n_j the outward unit normal of the slave body at node j (area-weighted facet
/// normals), is linear in the displacements: g = g0 + B u. The contact force lambda_j >=
/// 0 [N] conjugate to g_j acts on the slave node as -lambda_j n_j and on master node k as
/// (M_jk / D_jj) lambda_j n_j (the columns of B'), and the contact pressure is
/// p_j = lambda_j / D_jj [Pa]. Because the Phi_j sum to one, a uniform pressure produces
/// consistent nodal forces on both sides: the contact patch test is passed exactly.
///
/// Reference configuration (small sliding): the segments are paired once, in the
/// undeformed geometry. Linear segments (Line2: 2D, triangles and quadrilaterals).
#pragma once

#include <string>
#include <vector>

#include "contact/bodies.hpp"
#include "contact/types.hpp"

namespace contact {

/// One contact pair: a boundary group of a slave body against one of a master body.
struct MortarInterface {
  int slave_body = -1;
  std::string slave_group;
  int master_body = -1;
  std::string master_group;
  /// Master segments farther than this from a slave segment along its normal are not
  /// paired [m]; <= 0: the length of the longer of the two segments.
  double search_distance = 0.0;
  /// Coulomb friction coefficient mu >= 0 of the pair: |tau_j| <= mu lambda_j.
  double friction = 0.0;
};

/// The constraints g = initial_gap + B u of all interfaces, one row per slave node that
/// some master segment covers, and the tangential slip s = T u of the same rows,
///     s_j = t_j . ( sum_k M_jk / D_jj u_k^m - u_j^s ),   t_j = (-n_j,y, n_j,x),
/// the displacement of the mortar-weighted master point relative to slave node j along
/// its tangent [m]; the friction force tau_j [N] acts as T' tau.
struct MortarConstraints {
  SparseMatrix B;      ///< rows x global dofs (BodySystem numbering) [1]
  SparseMatrix T;      ///< rows x global dofs: the tangential slip rows [1]
  Vector friction;     ///< mu_j of the interface of row j
  Vector initial_gap;  ///< g0_j in the reference configuration [m]
  Vector weight;       ///< D_jj [m^2] (2D: length times thickness); p_j = lambda_j / D_jj
  std::vector<int> interface;   ///< interface index of row j
  std::vector<int> slave_body;  ///< body of slave node j
  std::vector<int> slave_node;  ///< mesh node of slave node j in its body
  Eigen::MatrixXd normals;      ///< dim x rows: n_j
  int NumConstraints() const { return static_cast<int>(initial_gap.size()); }
};

/// Builds the constraints. Master segments are found for each slave segment with a
/// bounding-box tree over the master segments (Boost.Geometry R-tree): O(n log n) in the
/// surface size. Throws std::invalid_argument naming the key for a body index out of
/// range, a slave body equal to the master body, a missing group (with the groups the
/// body has), 3D bodies (not supported yet), an interface none of whose slave nodes is
/// covered by the master surface, and bodies that overlap in the reference configuration:
/// a gap below -1e-9 times the interface's size, reported with its amount and the slave
/// node's position.
MortarConstraints AssembleMortar(const std::vector<Body>& bodies,
                                 const BodySystem& system,
                                 const std::vector<MortarInterface>& interfaces);

}  // namespace contact
