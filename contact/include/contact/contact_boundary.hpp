/// \file contact_boundary.hpp
/// The candidate contact boundary Gamma_c of the body: its nodes, the boundary matrix A
/// that turns contact stresses into nodal forces (thesis eq. 60: the term A g_tau), its
/// row-sum lumped version (the tributary area of each contact node), and the outward unit
/// normals of the body at the contact nodes (thesis section 5: the normal to the contact
/// boundary of the body, used to build the rotation R).
///
/// Contact node k (0 <= k < NumNodes()) is mesh node nodes[k]; the nodes are increasing.
#pragma once

#include <string>
#include <vector>

#include "contact/elastic_body.hpp"
#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact {

struct ContactBoundary {
  /// Name of the boundary group, "contact" by default.
  std::string group;
  /// Mesh node index of contact node k, increasing.
  std::vector<int> nodes;
  /// Contact index of each mesh node, -1 if the node is not on Gamma_c (size NumNodes of
  /// the mesh).
  std::vector<int> contact_index;
  /// Consistent boundary matrix A_kl = h int_Gamma_c N_k N_l dS (Nc x Nc, scalar per
  /// node) [m^2]: nodal forces F_k = sum_l A_kl g_l for a contact stress g [Pa]
  /// interpolated from nodal values g_l. In 2D, h = thickness, so A has units m * m
  /// (length times thickness).
  SparseMatrix boundary_matrix;
  /// Row sums of A: the tributary area of contact node k, h int_Gamma_c N_k dS [m^2]
  /// (in 2D: tributary length times thickness). Dividing a nodal force by it gives the
  /// contact stress of the row-sum lumped boundary matrix.
  Vector tributary_area;
  /// dim x Nc; column k is the outward unit normal of the body at contact node k, the
  /// area-weighted average of the normals of the Gamma_c facets f around the node:
  ///   n_k = sum_f int_f n dS / |sum_f int_f n dS|.
  Eigen::MatrixXd normals;

  int NumNodes() const { return static_cast<int>(nodes.size()); }
  /// The lumped boundary matrix diag(tributary_area) as a sparse matrix.
  SparseMatrix LumpedBoundaryMatrix() const;
};

/// Builds the contact boundary of `body` from the boundary group `group`. Throws
/// std::invalid_argument if the group is missing, has no facets (empty contact set), a
/// facet is not a face of an element, or the normal at a node is undefined (the facet
/// normals around it cancel, e.g. both sides of a zero-thickness plate).
ContactBoundary MakeContactBoundary(const ElasticBody& body,
                                    const std::string& group = kContactGroup);

/// The outward unit normals (dim x number of group nodes, nodes in increasing order) of
/// the body at the nodes of a boundary group, by area-weighted averaging of facet
/// normals.
Eigen::MatrixXd OutwardNodalNormals(const Mesh& mesh, const std::string& group);

}  // namespace contact
