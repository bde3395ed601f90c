/// \file quadratic_mesh.hpp
/// Quadratic meshes from linear ones: mid-edge (and mid-face, centre) nodes added at the
/// means of their corners, so every edge is straight. Curved boundaries need the mesh
/// generator's curved mid-side nodes instead (gmsh order 2, e.g. MakeQuarterDiskMesh with
/// order = 2).
#pragma once

#include "contact/mesh.hpp"

namespace contact {

/// The mesh `linear` (Triangle3, Quadrilateral4, Tetrahedron4 or Hexahedron8) with
/// elements of type `quadratic` on the same corners: Triangle6 from Triangle3,
/// Quadrilateral8/9 from Quadrilateral4, Tetrahedron10 from Tetrahedron4, Hexahedron20/27
/// from Hexahedron8. Corner nodes keep their indices; the new nodes follow, numbered in
/// order of first appearance. Boundary groups become groups of quadratic facets on the
/// same corners. Throws std::invalid_argument if `quadratic` is not a quadratic element
/// with the linear element of `linear` as corners.
Mesh MakeQuadraticMesh(const Mesh& linear, ElementType quadratic);

}  // namespace contact
