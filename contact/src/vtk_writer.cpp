#include "contact/vtk_writer.hpp"

#include <fstream>
#include <stdexcept>

namespace contact {
namespace {

// VTK cell types; the local node orders of mesh.hpp coincide with VTK's for these cells.
int VtkCellType(ElementType type) {
  switch (type) {
    case ElementType::kTriangle3:
      return 5;  // VTK_TRIANGLE
    case ElementType::kQuadrilateral4:
      return 9;  // VTK_QUAD
    case ElementType::kTetrahedron4:
      return 10;  // VTK_TETRA
    case ElementType::kHexahedron8:
      return 12;  // VTK_HEXAHEDRON
  }
  return 0;
}

}  // namespace

PointField NodalVectorField(const std::string& name, const Mesh& mesh, const Vector& u) {
  if (u.size() != mesh.NumDofs())
    throw std::invalid_argument("NodalVectorField '" + name + "': expected " +
                                std::to_string(mesh.NumDofs()) + " dofs, got " +
                                std::to_string(u.size()));
  return {name, Eigen::Map<const Eigen::MatrixXd>(u.data(), mesh.dim, mesh.NumNodes())};
}

void WriteVtk(const std::string& path, const Mesh& mesh,
              const std::vector<PointField>& point_fields) {
  for (const PointField& field : point_fields) {
    if (field.name.empty() || field.name.find_first_of(" \t\n") != std::string::npos)
      throw std::invalid_argument(
          "WriteVtk: field name must be non-empty without spaces, got '" + field.name +
          "'");
    if (field.values.cols() != mesh.NumNodes())
      throw std::invalid_argument("WriteVtk: field '" + field.name + "' needs " +
                                  std::to_string(mesh.NumNodes()) + " columns, got " +
                                  std::to_string(field.values.cols()));
    if (field.values.rows() != 1 && field.values.rows() != mesh.dim &&
        field.values.rows() != 3)
      throw std::invalid_argument("WriteVtk: field '" + field.name + "' needs 1, " +
                                  std::to_string(mesh.dim) + " or 3 rows, got " +
                                  std::to_string(field.values.rows()));
  }
  std::ofstream out(path);
  if (!out) throw std::runtime_error("WriteVtk: cannot open '" + path + "' for writing");
  out.precision(16);
  out << "# vtk DataFile Version 3.0\ncontact mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << mesh.NumNodes() << " double\n";
  for (int i = 0; i < mesh.NumNodes(); ++i)
    out << mesh.nodes(0, i) << ' ' << mesh.nodes(1, i) << ' '
        << (mesh.dim == 3 ? mesh.nodes(2, i) : 0.0) << '\n';
  const int nen = static_cast<int>(mesh.elements.rows());
  out << "CELLS " << mesh.NumElements() << ' ' << mesh.NumElements() * (nen + 1) << '\n';
  for (int e = 0; e < mesh.NumElements(); ++e) {
    out << nen;
    for (int a = 0; a < nen; ++a) out << ' ' << mesh.elements(a, e);
    out << '\n';
  }
  out << "CELL_TYPES " << mesh.NumElements() << '\n';
  for (int e = 0; e < mesh.NumElements(); ++e)
    out << VtkCellType(mesh.element_type) << '\n';
  if (!point_fields.empty()) out << "POINT_DATA " << mesh.NumNodes() << '\n';
  for (const PointField& field : point_fields) {
    if (field.values.rows() == 1) {
      out << "SCALARS " << field.name << " double 1\nLOOKUP_TABLE default\n";
      for (int i = 0; i < mesh.NumNodes(); ++i) out << field.values(0, i) << '\n';
    } else {
      out << "VECTORS " << field.name << " double\n";
      for (int i = 0; i < mesh.NumNodes(); ++i) {
        for (int k = 0; k < 3; ++k)
          out << (k ? " " : "") << (k < field.values.rows() ? field.values(k, i) : 0.0);
        out << '\n';
      }
    }
  }
  if (!out) throw std::runtime_error("WriteVtk: writing '" + path + "' failed");
}

}  // namespace contact
