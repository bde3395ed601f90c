/// \file vtk_writer.hpp
/// Output of a mesh with point fields as a legacy ASCII VTK unstructured grid (.vtk),
/// which ParaView opens directly (apply "Warp By Vector" on the displacement to see the
/// motion).
#pragma once

#include <string>
#include <vector>

#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact {

/// A field with one value per mesh node.
struct PointField {
  std::string name;  ///< no spaces (VTK legacy format)
  /// components x NumNodes: 1 row = scalar; dim rows = vector (padded with z = 0 in 2D).
  Eigen::MatrixXd values;
};

/// The point field of a node-major dof vector u (size dim * NumNodes), e.g. the
/// displacement [m]: column i is (u(dim i), ..., u(dim i + dim - 1)).
PointField NodalVectorField(const std::string& name, const Mesh& mesh, const Vector& u);

/// Writes the volume elements of `mesh` with the given point fields. Throws
/// std::invalid_argument if a field has the wrong number of columns, 0 or more than 3
/// rows (other than dim), or a name with spaces, and std::runtime_error if the file
/// cannot be written.
void WriteVtk(const std::string& path, const Mesh& mesh,
              const std::vector<PointField>& point_fields = {});

}  // namespace contact
