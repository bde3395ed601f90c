#include "contact/vtk_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <vector>

#include "ncp/output_file.hpp"
#include "reference_element.hpp"

namespace contact {
namespace {

// VTK cell types; the local node orders of mesh.hpp coincide with VTK's for these cells
// except where VtkNodeOrder says otherwise.
int VtkCellType(ElementType type) {
  switch (type) {
    case ElementType::kTriangle6:
      return 22;  // VTK_QUADRATIC_TRIANGLE
    case ElementType::kQuadrilateral8:
      return 23;  // VTK_QUADRATIC_QUAD
    case ElementType::kQuadrilateral9:
      return 28;  // VTK_BIQUADRATIC_QUAD
    case ElementType::kTetrahedron10:
      return 24;  // VTK_QUADRATIC_TETRA
    case ElementType::kHexahedron20:
      return 25;  // VTK_QUADRATIC_HEXAHEDRON
    case ElementType::kHexahedron27:
      return 29;  // VTK_TRIQUADRATIC_HEXAHEDRON
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

// VTK's local node a is our (gmsh's) local node order[a]. VTK orders the mid-edge nodes
// of a hexahedron bottom ring, top ring, verticals and its face centres x-, x+, y-, y+,
// z-, z+; its Tetrahedron10 has the edges 1-3 and 2-3 in the other order.
std::vector<int> VtkNodeOrder(ElementType type) {
  std::vector<int> order(static_cast<std::size_t>(NodesPerElement(type)));
  for (std::size_t a = 0; a < order.size(); ++a) order[a] = static_cast<int>(a);
  if (type == ElementType::kTetrahedron10) std::swap(order[8], order[9]);
  if (type == ElementType::kHexahedron20 || type == ElementType::kHexahedron27) {
    const int edges[12] = {8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
    std::copy(edges, edges + 12, order.begin() + 8);
  }
  if (type == ElementType::kHexahedron27) {
    const int faces[6] = {22, 23, 21, 24, 20, 25};
    std::copy(faces, faces + 6, order.begin() + 20);
  }
  return order;
}

// Base64 (RFC 4648) of a byte string.
std::string Base64(const std::string& bytes) {
  static const char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (size_t k = 0; k < 4; ++k)
      out += k <= n ? kDigits[(v >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

// A VTK XML inline binary DataArray body: base64 of (UInt32 byte count, the raw values),
// the layout VTK's readers expect for header_type="UInt32" without compression.
template <typename T>
std::string BinaryArray(const std::vector<T>& values) {
  const std::uint32_t size = static_cast<std::uint32_t>(values.size() * sizeof(T));
  std::string bytes(sizeof size + size, '\0');
  std::memcpy(&bytes[0], &size, sizeof size);
  if (size > 0) std::memcpy(&bytes[sizeof size], values.data(), size);
  return Base64(bytes);
}

template <typename T>
void WriteDataArray(std::ostream& out, const char* type, const std::string& name,
                    int components, const std::vector<T>& values) {
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name
      << "\" NumberOfComponents=\"" << components << "\" format=\"binary\">\n          "
      << BinaryArray(values) << "\n        </DataArray>\n";
}

void CheckName(const std::string& who, const std::string& name) {
  if (name.empty() || name.find_first_of(" \t\n\"<>&") != std::string::npos)
    throw std::invalid_argument(who +
                                ": field name must be non-empty without spaces or XML "
                                "characters, got '" +
                                name + "'");
}

// Values of a field, entity-major, with `components` components (rows beyond the field's
// are 0: a 2D vector becomes (x, y, 0)).
std::vector<double> Interleave(const Eigen::MatrixXd& values, int components) {
  std::vector<double> out(
      static_cast<size_t>(values.cols()) * static_cast<size_t>(components), 0.0);
  for (Eigen::Index i = 0; i < values.cols(); ++i)
    for (Eigen::Index k = 0; k < values.rows(); ++k)
      out[static_cast<size_t>(i * components + k)] = values(k, i);
  return out;
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
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  std::ostream& out = file.stream();
  out.precision(16);
  out << "# vtk DataFile Version 3.0\ncontact mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << mesh.NumNodes() << " double\n";
  for (int i = 0; i < mesh.NumNodes(); ++i)
    out << mesh.nodes(0, i) << ' ' << mesh.nodes(1, i) << ' '
        << (mesh.dim == 3 ? mesh.nodes(2, i) : 0.0) << '\n';
  const int nen = static_cast<int>(mesh.elements.rows());
  out << "CELLS " << mesh.NumElements() << ' ' << mesh.NumElements() * (nen + 1) << '\n';
  const std::vector<int> vtk_order = VtkNodeOrder(mesh.element_type);
  for (int e = 0; e < mesh.NumElements(); ++e) {
    out << nen;
    for (int a = 0; a < nen; ++a) out << ' ' << mesh.elements(vtk_order[a], e);
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
  file.Close();
}

void WriteVtu(const std::string& path, const Mesh& mesh,
              const std::vector<PointField>& point_fields,
              const std::vector<CellField>& cell_fields) {
  for (const PointField& field : point_fields) {
    CheckName("WriteVtu", field.name);
    if (field.values.cols() != mesh.NumNodes() ||
        (field.values.rows() != 1 && field.values.rows() != mesh.dim &&
         field.values.rows() != 3))
      throw std::invalid_argument("WriteVtu: point field '" + field.name + "' needs 1, " +
                                  std::to_string(mesh.dim) + " or 3 rows and " +
                                  std::to_string(mesh.NumNodes()) + " columns, got " +
                                  std::to_string(field.values.rows()) + " x " +
                                  std::to_string(field.values.cols()));
  }
  for (const CellField& field : cell_fields) {
    CheckName("WriteVtu", field.name);
    const Eigen::Index rows = field.values.rows();
    if (field.values.cols() != mesh.NumElements() ||
        (rows != 1 && rows != 3 && rows != 9))
      throw std::invalid_argument(
          "WriteVtu: cell field '" + field.name + "' needs 1, 3 or 9 rows and " +
          std::to_string(mesh.NumElements()) + " columns, got " + std::to_string(rows) +
          " x " + std::to_string(field.values.cols()));
  }
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  std::ostream& out = file.stream();
  const int nen = static_cast<int>(mesh.elements.rows());
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << mesh.NumNodes() << "\" NumberOfCells=\""
      << mesh.NumElements() << "\">\n";
  out << "      <PointData>\n";
  for (const PointField& field : point_fields) {
    const int components = field.values.rows() == 1 ? 1 : 3;
    WriteDataArray(out, "Float64", field.name, components,
                   Interleave(field.values, components));
  }
  out << "      </PointData>\n      <CellData>\n";
  for (const CellField& field : cell_fields)
    WriteDataArray(out, "Float64", field.name, static_cast<int>(field.values.rows()),
                   Interleave(field.values, static_cast<int>(field.values.rows())));
  out << "      </CellData>\n      <Points>\n";
  WriteDataArray(out, "Float64", "Points", 3, Interleave(mesh.nodes, 3));
  out << "      </Points>\n      <Cells>\n";
  std::vector<std::int64_t> connectivity, offsets;
  const std::vector<int> vtk_order = VtkNodeOrder(mesh.element_type);
  std::vector<std::uint8_t> types(
      static_cast<size_t>(mesh.NumElements()),
      static_cast<std::uint8_t>(VtkCellType(mesh.element_type)));
  for (int e = 0; e < mesh.NumElements(); ++e) {
    for (int a = 0; a < nen; ++a) connectivity.push_back(mesh.elements(vtk_order[a], e));
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  WriteDataArray(out, "Int64", "connectivity", 1, connectivity);
  WriteDataArray(out, "Int64", "offsets", 1, offsets);
  WriteDataArray(out, "UInt8", "types", 1, types);
  out << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  file.Close();
}

void WritePvtu(const std::string& path, const std::vector<PointField>& point_fields,
               const std::vector<CellField>& cell_fields,
               const std::vector<std::string>& pieces) {
  if (pieces.empty())
    throw std::invalid_argument("WritePvtu: no piece for '" + path + "'");
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  std::ostream& out = file.stream();
  // The component counts as WriteVtu writes them: point vectors padded to 3.
  auto array = [&](const std::string& name, Eigen::Index rows) {
    CheckName("WritePvtu", name);
    out << "      <PDataArray type=\"Float64\" Name=\"" << name
        << "\" NumberOfComponents=\"" << rows << "\"/>\n";
  };
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" "
         "header_type=\"UInt32\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    "
         "<PPointData>\n";
  for (const PointField& field : point_fields)
    array(field.name, field.values.rows() == 1 ? 1 : 3);
  out << "    </PPointData>\n    <PCellData>\n";
  for (const CellField& field : cell_fields) array(field.name, field.values.rows());
  out << "    </PCellData>\n    <PPoints>\n"
         "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
         "    </PPoints>\n";
  for (const std::string& piece : pieces)
    out << "    <Piece Source=\"" << piece << "\"/>\n";
  out << "  </PUnstructuredGrid>\n</VTKFile>\n";
  file.Close();
}

void WritePvd(const std::string& path,
              const std::vector<std::pair<double, std::string>>& snapshots) {
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  std::ostream& out = file.stream();
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
         "  <Collection>\n";
  for (const auto& [time, file] : snapshots)
    out << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << file
        << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  file.Close();
}

ContactState ClassifyContact(double normal_force, double slip_length,
                             double force_accuracy, double displacement_accuracy) {
  if (!(normal_force > force_accuracy)) return ContactState::kOpen;
  return slip_length > displacement_accuracy ? ContactState::kSlip : ContactState::kStick;
}

Eigen::MatrixXd ElementStress(const ElasticBody& body, const Vector& u) {
  const Mesh& mesh = body.mesh();
  const int dim = mesh.dim;
  if (u.size() != mesh.NumDofs())
    throw std::invalid_argument("ElementStress: expected " +
                                std::to_string(mesh.NumDofs()) + " dofs, got " +
                                std::to_string(u.size()));
  // sigma = lambda tr(eps) I + 2 mu eps; plane stress: lambda* = 2 mu lambda / (lambda +
  // 2 mu) and sigma_zz = 0, plane strain: eps_zz = 0 and sigma_zz = lambda tr(eps).
  const double mu = body.material().ShearModulus();
  double lambda = body.material().Lambda();
  const bool plane_stress = dim == 2 && body.plane().model == PlaneModel::kPlaneStress;
  if (plane_stress) lambda = 2.0 * mu * lambda / (lambda + 2.0 * mu);
  Eigen::MatrixXd stress = Eigen::MatrixXd::Zero(9, mesh.NumElements());
  internal::DispatchElement(mesh.element_type, [&](auto tag) {
    constexpr ElementType kType = decltype(tag)::value;
    using Traits = internal::ElementTraits<kType>;
    const auto& shape = internal::ShapeData<kType>(internal::RulePurpose::kStiffness);
    for (int e = 0; e < mesh.NumElements(); ++e) {
      const auto X = internal::ElementCoordinates<kType>(mesh, e);
      Eigen::Matrix<double, Traits::kDim, Traits::kNodes> U;
      for (int a = 0; a < Traits::kNodes; ++a)
        U.col(a) = u.segment<Traits::kDim>(Traits::kDim * mesh.elements(a, e));
      Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
      for (int q = 0; q < shape.NumPoints(); ++q) {
        const Eigen::Matrix<double, Traits::kDim, Traits::kDim> J = X * shape.dN_dxi[q];
        const auto dN_dx = (shape.dN_dxi[q] * J.inverse()).eval();  // dN_a / dx_j
        const Eigen::Matrix<double, Traits::kDim, Traits::kDim> grad = U * dN_dx;
        Eigen::Matrix3d eps = Eigen::Matrix3d::Zero();
        eps.topLeftCorner<Traits::kDim, Traits::kDim>() = 0.5 * (grad + grad.transpose());
        Eigen::Matrix3d s =
            lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2.0 * mu * eps;
        if (plane_stress) s(2, 2) = 0.0;
        sigma += s / shape.NumPoints();
      }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) stress(3 * i + j, e) = sigma(i, j);
    }
  });
  return stress;
}

std::pair<std::vector<PointField>, std::vector<CellField>> ContactSnapshotFields(
    const ElasticBody& body, const ContactSnapshot& s) {
  const Mesh& mesh = body.mesh();
  const int dim = mesh.dim;
  const std::vector<ContactNode> no_nodes;
  const std::vector<ContactNode>& nodes = s.contact_nodes ? *s.contact_nodes : no_nodes;
  const Eigen::Index num_contact = static_cast<Eigen::Index>(nodes.size());
  if (s.displacement.size() != mesh.NumDofs() ||
      s.previous_displacement.size() != mesh.NumDofs() ||
      s.normal_force.size() != num_contact || s.gap.size() != num_contact ||
      s.tangent_force.cols() != num_contact ||
      (num_contact > 0 && s.tangent_force.rows() != dim - 1))
    throw std::invalid_argument(
        "ContactSnapshotFields: expected " + std::to_string(mesh.NumDofs()) +
        " dofs and " + std::to_string(num_contact) +
        " contact nodes, got displacements of " + std::to_string(s.displacement.size()) +
        " and " + std::to_string(s.previous_displacement.size()) + ", normal forces of " +
        std::to_string(s.normal_force.size()) + ", gaps of " +
        std::to_string(s.gap.size()) + ", tangent forces of " +
        std::to_string(s.tangent_force.rows()) + " x " +
        std::to_string(s.tangent_force.cols()));
  if (!(s.dt > 0.0))
    throw std::invalid_argument("ContactSnapshotFields: dt must be > 0 s, got " +
                                std::to_string(s.dt));
  const Vector increment = s.displacement - s.previous_displacement;  // u^{k+1} - u^k [m]
  const int n = mesh.NumNodes();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd gap = Eigen::MatrixXd::Constant(1, n, nan);
  Eigen::MatrixXd normal_force = Eigen::MatrixXd::Zero(3, n),
                  friction_force = normal_force, slip = normal_force,
                  contact_normal = normal_force;
  Eigen::MatrixXd state =
      Eigen::MatrixXd::Constant(1, n, static_cast<double>(ContactState::kNotContact));
  for (Eigen::Index c = 0; c < num_contact; ++c) {
    const ContactNode& node = nodes[static_cast<size_t>(c)];
    const int i = node.node;
    gap(0, i) = s.gap(c);
    contact_normal.col(i) = node.normal;
    // The obstacle pushes the body against its outward normal n_c.
    normal_force.col(i) = -s.normal_force(c) * node.normal;
    friction_force.col(i) = s.tangent_force(0, c) * node.tangent1;
    if (dim == 3) friction_force.col(i) += s.tangent_force(1, c) * node.tangent2;
    Eigen::Vector3d du = Eigen::Vector3d::Zero();
    du.head(dim) = increment.segment(dim * i, dim);
    slip.col(i) = du - node.normal.dot(du) * node.normal;
    state(0, i) = std::isnan(s.normal_force(c))
                      ? nan
                      : static_cast<double>(
                            ClassifyContact(s.normal_force(c), slip.col(i).norm(),
                                            s.force_accuracy, s.displacement_accuracy));
  }
  Eigen::MatrixXd stress;
  // (an inverted element has no Cauchy stress: then the linear one, as the run's status
  // says why it stopped)
  if (!s.finite_strain ||
      !body.CauchyStress(s.displacement, s.finite_strain_model, &stress).ok)
    stress = ElementStress(body, s.displacement);
  Eigen::MatrixXd von_mises(1, mesh.NumElements());
  for (int e = 0; e < mesh.NumElements(); ++e) {
    const Eigen::Map<const Eigen::Matrix3d> sigma(stress.col(e).data());
    const Eigen::Matrix3d deviator =
        sigma - sigma.trace() / 3.0 * Eigen::Matrix3d::Identity();
    von_mises(0, e) = std::sqrt(1.5 * deviator.squaredNorm());  // sqrt(3/2 s:s)
  }
  std::vector<PointField> points = {
      NodalVectorField("displacement", mesh, s.displacement),
      NodalVectorField("velocity", mesh, increment / s.dt),
      {"gap", gap},
      {"normal_force", normal_force},
      {"friction_force", friction_force},
      {"slip", slip},
      {"contact_state", state},
      {"contact_normal", contact_normal}};
  return {points, {{"stress", stress}, {"von_mises", von_mises}}};
}

ContactSnapshot InitialContactSnapshot(int dim, double time, const Vector& u0,
                                       const Vector& v0, double dt,
                                       const std::vector<ContactNode>& contact_nodes) {
  if (u0.size() != v0.size())
    throw std::invalid_argument("InitialContactSnapshot: u0 has " +
                                std::to_string(u0.size()) + " dofs, v0 " +
                                std::to_string(v0.size()));
  const Eigen::Index num_contact = static_cast<Eigen::Index>(contact_nodes.size());
  ContactSnapshot s;
  s.time = time;
  s.displacement = u0;
  s.previous_displacement = u0 - dt * v0;  // velocity (u^0 - u^-1) / dt = v^0
  s.dt = dt;
  s.contact_nodes = &contact_nodes;
  s.normal_force =
      Eigen::VectorXd::Constant(num_contact, std::numeric_limits<double>::quiet_NaN());
  s.tangent_force = Eigen::MatrixXd::Constant(dim - 1, num_contact,
                                              std::numeric_limits<double>::quiet_NaN());
  s.gap.resize(num_contact);
  for (Eigen::Index c = 0; c < num_contact; ++c) {
    const ContactNode& node = contact_nodes[static_cast<size_t>(c)];
    s.gap(c) = node.gap - node.normal.head(dim).dot(u0.segment(dim * node.node, dim));
  }
  return s;
}

VtuSeriesWriter::VtuSeriesWriter(std::string directory, const ElasticBody& body)
    : directory_(std::move(directory)), body_(body) {}

std::string VtuSeriesWriter::pvd_path() const {
  return (std::filesystem::path(directory_) / "solution.pvd").string();
}

std::string SnapshotFileName(int step, const std::string& suffix) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05d", step);
  return "snapshot_" + std::string(digits) + suffix;
}

std::string VtuSeriesWriter::Write(int step, const ContactSnapshot& snapshot) {
  const std::string name = SnapshotFileName(step, ".vtu");
  const std::string path = (std::filesystem::path(directory_) / name).string();
  const auto [points, cells] = ContactSnapshotFields(body_, snapshot);
  WriteVtu(path, body_.mesh(), points, cells);
  snapshots_.emplace_back(snapshot.time, name);
  WritePvd(pvd_path(), snapshots_);
  return path;
}

void VtuSeriesWriter::Continue(std::vector<std::pair<double, std::string>> snapshots) {
  snapshots_ = std::move(snapshots);
  WritePvd(pvd_path(), snapshots_);
}

}  // namespace contact
