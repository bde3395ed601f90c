/// \file gmsh_reader.hpp
/// Reading a gmsh mesh file: an ASCII .msh, format 2.2 or 4.1 (binary files are refused).
#pragma once

#include <string>

#include "contact/mesh.hpp"

namespace contact {

/// Limits of a .msh file, checked by reading the file before gmsh does: gmsh 4.8 keeps
/// tags as int and sizes tables by the largest tag (a node tag of 1e12 crashes it), and
/// it runs any script a .geo file holds.
inline constexpr unsigned long long kMaxMshTag =
    100000000;  ///< node and element tags, 1e8
inline constexpr unsigned long long kMaxMshFileBytes = 1ULL << 30;  ///< 1 GiB

/// Reads the mesh in `path` into a Mesh.
///  - dimension: the highest dimension of the elements in the file (2 or 3); a 2D
///    mesh must lie in the plane z = 0;
///  - elements: all elements of that dimension, of one supported type (3-node
///    triangles, 4-node quadrilaterals, 4-node tetrahedra or 8-node hexahedra);
///  - boundary groups: the physical groups of dimension dim - 1, by name (an unnamed
///    group is named by its number, e.g. "7"); groups of the same name are merged;
///  - nodes: those used by the elements, renumbered 0 .. N-1 by increasing gmsh tag.
/// Throws std::invalid_argument if the file cannot be read, contains unsupported elements
/// (second-order, prisms, pyramids, mixed types), no 2D/3D elements, facets whose nodes
/// are not nodes of the elements, or an inverted element (see ValidateMesh); and before
/// gmsh opens it, a file that is not an ASCII .msh (format 2 or 4), larger than
/// kMaxMshFileBytes, with a tag outside [1, kMaxMshTag], or with a physical name of a
/// dimension outside [0, 3]
/// ("file:line: ..." in the message).
Mesh ReadGmshMesh(const std::string& path);

}  // namespace contact
