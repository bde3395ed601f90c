/// \file mesh.hpp
/// The finite element mesh of the elastic body as plain data: node coordinates, one type
/// of linear or quadratic element, and named boundary facet groups (gmsh physical groups
/// of dimension dim - 1). Nothing here depends on gmsh; see mesh_generation.hpp and
/// gmsh_reader.hpp for the ways to obtain a Mesh.
///
/// Local node order of elements and facets is the gmsh (and VTK) order:
///   Triangle3       (0,0) (1,0) (0,1)                        counter-clockwise
///   Quadrilateral4  (-1,-1) (1,-1) (1,1) (-1,1)              counter-clockwise
///   Tetrahedron4    (0,0,0) (1,0,0) (0,1,0) (0,0,1)          node 3 on the side where
///                                                            0-1-2 is counter-clockwise
///   Hexahedron8     bottom face 0-1-2-3 (zeta = -1), top face 4-5-6-7 (zeta = +1)
/// Quadratic elements list their corners first (as the linear element), then the
/// mid-edge, mid-face and centre nodes in gmsh's order (see docs/quadratic-elements.md):
///   Line3           ends 0 1, mid 2
///   Triangle6       mid-edges 3 (0-1) 4 (1-2) 5 (2-0)
///   Quadrilateral8  mid-edges 4 (0-1) 5 (1-2) 6 (2-3) 7 (3-0); Quadrilateral9 + centre 8
///   Tetrahedron10   mid-edges 4 (0-1) 5 (1-2) 6 (2-0) 7 (3-0) 8 (3-2) 9 (3-1)
///   Hexahedron20    mid-edges 8 (0-1) 9 (0-3) 10 (0-4) 11 (1-2) 12 (1-5) 13 (2-3)
///                   14 (2-6) 15 (3-7) 16 (4-5) 17 (4-7) 18 (5-6) 19 (6-7)
///   Hexahedron27    + face centres 20 (0123) 21 (0154) 22 (0374) 23 (1265) 24 (2376)
///                   25 (4567), centre 26
/// Elements must be positively oriented: det(dx/dxi) > 0 at every integration point.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "contact/types.hpp"

namespace contact {

/// The supported (isoparametric Lagrange and serendipity) volume elements.
enum class ElementType {
  kTriangle3,       ///< 2D, 3 nodes (gmsh type 2)
  kQuadrilateral4,  ///< 2D, 4 nodes (gmsh type 3)
  kTetrahedron4,    ///< 3D, 4 nodes (gmsh type 4)
  kHexahedron8,     ///< 3D, 8 nodes (gmsh type 5)
  kTriangle6,       ///< 2D quadratic, 6 nodes (gmsh type 9)
  kQuadrilateral8,  ///< 2D quadratic serendipity, 8 nodes (gmsh type 16)
  kQuadrilateral9,  ///< 2D biquadratic, 9 nodes (gmsh type 10)
  kTetrahedron10,   ///< 3D quadratic, 10 nodes (gmsh type 11)
  kHexahedron20,    ///< 3D quadratic serendipity, 20 nodes (gmsh type 17)
  kHexahedron27,    ///< 3D triquadratic, 27 nodes (gmsh type 12)
};

/// The boundary facets of those elements: an edge in 2D, a face in 3D.
enum class FacetType {
  kLine2,           ///< facet of Triangle3 and Quadrilateral4 (gmsh type 1)
  kTriangle3,       ///< facet of Tetrahedron4 (gmsh type 2)
  kQuadrilateral4,  ///< facet of Hexahedron8 (gmsh type 3)
  kLine3,           ///< facet of the quadratic 2D elements (gmsh type 8)
  kTriangle6,       ///< facet of Tetrahedron10 (gmsh type 9)
  kQuadrilateral8,  ///< facet of Hexahedron20 (gmsh type 16)
  kQuadrilateral9,  ///< facet of Hexahedron27 (gmsh type 10)
};

const char* ToString(ElementType type);
const char* ToString(FacetType type);
/// Spatial dimension of the element (2 or 3).
int Dimension(ElementType type);
int NodesPerElement(ElementType type);
int NodesPerFacet(FacetType type);
/// The facet type of the element's boundary.
FacetType FacetTypeOf(ElementType type);
/// Polynomial order of the element's shape functions: 1 (linear) or 2 (quadratic).
int ElementOrder(ElementType type);
/// The linear element with the same corners (kTriangle6 -> kTriangle3, ...); the identity
/// for linear elements.
ElementType LinearElementOf(ElementType type);
/// Number of corner (vertex) nodes, which come first in the element's node list.
int CornersPerElement(ElementType type);
int CornersPerFacet(FacetType type);

/// One named part of the boundary, e.g. "fixed", "load" or "contact".
struct BoundaryFacets {
  FacetType type = FacetType::kLine2;
  /// NodesPerFacet(type) x number of facets; column f holds the node indices of facet f.
  Eigen::MatrixXi connectivity;

  int NumFacets() const { return static_cast<int>(connectivity.cols()); }
  /// The distinct node indices of the group, increasing.
  std::vector<int> Nodes() const;
};

/// Conventional names of the boundary groups used by the contact module.
inline constexpr const char* kFixedGroup = "fixed";  ///< Dirichlet boundary Gamma_u
inline constexpr const char* kLoadGroup = "load";    ///< traction boundary Gamma_t
inline constexpr const char* kContactGroup =
    "contact";  ///< candidate contact boundary Gamma_c

struct Mesh {
  /// Spatial dimension, 2 or 3.
  int dim = 0;
  /// dim x NumNodes(); column i holds the coordinates of node i [m]. Nodes are numbered
  /// compactly 0 .. NumNodes()-1, and every node belongs to at least one element.
  Eigen::MatrixXd nodes;
  ElementType element_type = ElementType::kTriangle3;
  /// NodesPerElement(element_type) x NumElements(); column e lists the nodes of
  /// element e.
  Eigen::MatrixXi elements;
  /// Identifier of element e in its source (the gmsh element tag), used in error
  /// messages. Either empty or of size NumElements().
  std::vector<std::size_t> element_tags;
  /// Boundary groups by name (gmsh physical groups of dimension dim - 1).
  std::map<std::string, BoundaryFacets> boundary_groups;

  int NumNodes() const { return static_cast<int>(nodes.cols()); }
  int NumElements() const { return static_cast<int>(elements.cols()); }
  /// Number of displacement degrees of freedom, dim * NumNodes(). Layout is node-major:
  /// dof = dim * node + component.
  int NumDofs() const { return dim * NumNodes(); }

  bool HasBoundaryGroup(const std::string& name) const;
  /// The group `name`; throws std::invalid_argument naming the available groups if the
  /// mesh has none of that name.
  const BoundaryFacets& BoundaryGroup(const std::string& name) const;
  /// Mean of the element's node coordinates [m].
  Eigen::VectorXd ElementCentroid(int element) const;
  /// "element 12 (source tag 345)", for error messages.
  std::string DescribeElement(int element) const;
};

/// Checks the consistency of a mesh and throws std::invalid_argument on the first
/// problem: dim and sizes, node indices in range, facet types matching the element type,
/// finite coordinates, and orientation: an inverted element (det(dx/dxi) <= 0 at one of
/// its integration points) is reported with its index, source tag and centroid.
void ValidateMesh(const Mesh& mesh);

/// Length (2D) or area (3D) of a boundary group [m or m^2].
double BoundaryMeasure(const Mesh& mesh, const std::string& group);

/// Area (2D) or volume (3D) of the mesh [m^2 or m^3].
double DomainMeasure(const Mesh& mesh);

}  // namespace contact
