/// \file mesh_generation.hpp
/// Meshes of rectangles (2D) and boxes (3D) generated from parameters with the gmsh C++
/// API, and a direct structured hexahedral box generator for very large meshes.
///
/// Boundary groups: each side of the domain can be given a role; all sides with the same
/// role form one boundary group named after it ("fixed", "load", "contact"). A role that
/// no side has produces no group (asking the mesh for it then throws "no boundary
/// group").
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "contact/mesh.hpp"

namespace contact {

/// Limits of the generated grids, checked before gmsh is called: beyond them gmsh meshes
/// for hours, runs out of memory, or (for elements of extreme aspect ratio) stops to ask
/// on standard input whether to continue.
inline constexpr double kMaxGeneratedCells = 4e6;  ///< cells_x cells_y (cells_z)
inline constexpr double kMaxCellAspectRatio =
    1e4;  ///< max_k h_k / min_k h_k, h_k = size_k / cells_k
inline constexpr double kMaxGridExtent = 1e6;  ///< |origin_k| and size_k [m]
inline constexpr double kMinCellSize = 1e-9;   ///< h_k [m]
/// "" if `cells` cells along sides of lengths `size` [m] respect those limits, else the
/// reason, e.g. "1e+12 cells exceed the limit of 4e+06". Takes doubles so that
/// scene values are checked before their conversion to int.
std::string CheckGridLimits(const std::vector<double>& size,
                            const std::vector<double>& cells);

/// The sides of an axis-aligned rectangle or box.
enum class Side { kXMin, kXMax, kYMin, kYMax, kZMin, kZMax };

/// What a side of the generated domain is.
enum class BoundaryRole {
  kNone,     ///< traction-free, no group
  kFixed,    ///< group "fixed" (Dirichlet)
  kLoad,     ///< group "load" (prescribed traction)
  kContact,  ///< group "contact" (candidate contact boundary Gamma_c)
};

const char* ToString(Side side);
/// The group name of a role ("fixed", "load", "contact"; "" for kNone).
const char* GroupName(BoundaryRole role);

enum class MeshTopology {
  /// Transfinite (structured) mesh with exactly `cells[k]` elements along axis k;
  /// quadrilaterals/hexahedra are recombined, triangles/tetrahedra split the cells.
  kStructured,
  /// Unstructured (Delaunay/frontal) mesh with target size min_k(size[k] / cells[k]);
  /// quadrilaterals by recombination of triangles (2D only: no unstructured hexahedra).
  kUnstructured,
};

/// The rectangle [origin_x, origin_x + size_x] x [origin_y, origin_y + size_y] [m].
struct RectangleMeshOptions {
  std::array<double, 2> origin{0.0, 0.0};  ///< lower-left corner [m]
  std::array<double, 2> size{1.0, 1.0};    ///< side lengths Lx, Ly [m], > 0
  std::array<int, 2> cells{10, 10};        ///< elements per direction, >= 1
  ElementType element_type =
      ElementType::kQuadrilateral4;  ///< kTriangle3, kQuadrilateral4 or quadratic 2D
                                     ///< (the linear mesh made quadratic,
                                     ///< quadratic_mesh.hpp)
  MeshTopology topology = MeshTopology::kStructured;
  std::map<Side, BoundaryRole> side_roles;  ///< unlisted sides get kNone; only x/y sides
  std::string msh_output_path;  ///< if not empty, also save the gmsh mesh here
};

/// The box [origin, origin + size] [m].
struct BoxMeshOptions {
  std::array<double, 3> origin{0.0, 0.0,
                               0.0};  ///< corner with the smallest coordinates [m]
  std::array<double, 3> size{1.0, 1.0, 1.0};  ///< side lengths [m], > 0
  std::array<int, 3> cells{4, 4, 4};          ///< elements per direction, >= 1
  ElementType element_type =
      ElementType::kHexahedron8;  ///< kTetrahedron4, kHexahedron8 or quadratic 3D
                                  ///< (the linear mesh made quadratic)
  MeshTopology topology = MeshTopology::kStructured;
  std::map<Side, BoundaryRole> side_roles;  ///< unlisted sides get kNone
  std::string msh_output_path;  ///< if not empty, also save the gmsh mesh here
};

/// Meshes a rectangle with gmsh. Throws std::invalid_argument for invalid options.
Mesh MakeRectangleMesh(const RectangleMeshOptions& options);
/// Meshes a box with gmsh. Throws std::invalid_argument for invalid options, including
/// unstructured hexahedra.
Mesh MakeBoxMesh(const BoxMeshOptions& options);
/// The quarter disk {x >= 0, y <= R, x^2 + (y - R)^2 <= R^2}: half of a cylinder section
/// of radius R touching the plane y = 0 at the origin (Hertz contact), 3-node triangles
/// (or curved 6-node triangles with order = 2).
/// Groups: "fixed" = the symmetry line x = 0, "load" = the cut y = R, "contact" = the arc
/// from the origin to x = contact_extent. Element size contact_size within refined_radius
/// of the origin, growing with slope 1/4 up to max_size (gmsh Distance + Threshold
/// fields).
struct QuarterDiskMeshOptions {
  double radius = 1.0;          ///< R [m]
  double contact_size = 0.01;   ///< element size near the origin [m]
  double refined_radius = 0.1;  ///< radius of the refined zone [m]
  double contact_extent = 0.2;  ///< x where the "contact" arc ends [m], < R
  double max_size = 0.125;      ///< largest element size [m]
  /// 1: Triangle3; 2: Triangle6 with the mid-side nodes of the arc on the circle.
  int order = 1;
};
Mesh MakeQuarterDiskMesh(const QuarterDiskMeshOptions& options);

/// The structured hexahedral mesh of a box built directly (no gmsh; linear time and
/// memory, for meshes of millions of dofs). Node (i, j, k) has index i + (nx+1)(j +
/// (ny+1)k); element tags are 1-based indices. Requires element_type = kHexahedron8 and
/// topology = kStructured; msh_output_path is ignored.
Mesh MakeStructuredBoxMesh(const BoxMeshOptions& options);

}  // namespace contact
