// WriteVtk: the legacy file lists the points, cells, cell types and point data.
// WriteVtu / WritePvd: the XML files' structure (tests/python/test_vtk_output.py reads
// them back with VTK's reader). ElementStress: Hooke's law of a linear displacement
// field, exact on every element type (patch test). ClassifyContact: open / stick / slip.
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>
#include <contact/vtk_writer.hpp>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace contact {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST_CASE("a 2D Q4 mesh with a displacement and a scalar field", "[vtk_writer]") {
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {2, 2};
  const Mesh mesh = MakeRectangleMesh(options);
  Vector u = Vector::Zero(mesh.NumDofs());
  for (int i = 0; i < mesh.NumNodes(); ++i) u(2 * i + 1) = -0.5 * mesh.nodes(0, i);
  const PointField displacement = NodalVectorField("displacement", mesh, u);
  CHECK(displacement.values.rows() == 2);
  CHECK(displacement.values(1, 4) == u(9));
  PointField node_index{"node", Eigen::RowVectorXd::LinSpaced(9, 0, 8)};

  const std::string path = std::string(P_tmpdir) + "/contact_test_mesh.vtk";
  WriteVtk(path, mesh, {displacement, node_index});
  const std::string text = ReadAll(path);
  std::remove(path.c_str());
  CHECK(text.rfind("# vtk DataFile Version 3.0\n", 0) == 0);
  CHECK(text.find("POINTS 9 double\n") != std::string::npos);
  CHECK(text.find("CELLS 4 20\n") != std::string::npos);
  CHECK(text.find("CELL_TYPES 4\n9\n9\n9\n9\n") != std::string::npos);
  CHECK(text.find("POINT_DATA 9\nVECTORS displacement double\n") != std::string::npos);
  CHECK(text.find("SCALARS node double 1\nLOOKUP_TABLE default\n0\n1\n") !=
        std::string::npos);
  // The node at x = 2 moves by (0, -1, 0).
  CHECK(text.find("\n0 -1 0\n") != std::string::npos);
}

TEST_CASE("bad fields are rejected", "[vtk_writer]") {
  BoxMeshOptions options;
  options.cells = {1, 1, 1};
  const Mesh mesh = MakeStructuredBoxMesh(options);
  CHECK_THROWS_WITH(
      WriteVtk("/tmp/never.vtk", mesh, {{"u", Eigen::MatrixXd::Zero(3, 7)}}),
      Catch::Contains("needs 8 columns, got 7"));
  CHECK_THROWS_WITH(
      WriteVtk("/tmp/never.vtk", mesh, {{"my field", Eigen::MatrixXd::Zero(1, 8)}}),
      Catch::Contains("without spaces"));
  CHECK_THROWS_WITH(NodalVectorField("u", mesh, Vector::Zero(5)),
                    Catch::Contains("expected 24 dofs, got 5"));
  CHECK_THROWS_AS(WriteVtk("/nonexistent/dir/out.vtk", mesh), std::runtime_error);
}

TEST_CASE("the stress of a linear displacement field is Hooke's law on every element",
          "[vtk_writer]") {
  const IsotropicMaterial steel{2e11, 0.3, 7800};
  const double lambda = steel.Lambda(), mu = steel.ShearModulus();
  // u = G x with a general gradient G (dimensionless), eps = (G + G') / 2.
  Eigen::Matrix3d G;
  G << 1e-3, 2e-4, -5e-4,  //
      -3e-4, -2e-3, 1e-4,  //
      4e-4, 6e-4, 5e-4;
  auto check = [&](const Mesh& mesh, const PlaneSettings& plane) {
    const ElasticBody body(mesh, steel, plane);
    const int dim = mesh.dim;
    Vector u(mesh.NumDofs());
    for (int i = 0; i < mesh.NumNodes(); ++i)
      u.segment(dim * i, dim) = G.topLeftCorner(dim, dim) * mesh.nodes.col(i);
    Eigen::Matrix3d eps = Eigen::Matrix3d::Zero();
    eps.topLeftCorner(dim, dim) =
        0.5 * (G.topLeftCorner(dim, dim) + G.topLeftCorner(dim, dim).transpose());
    double l = lambda;
    const bool plane_stress = dim == 2 && plane.model == PlaneModel::kPlaneStress;
    if (plane_stress) l = 2 * mu * lambda / (lambda + 2 * mu);  // E nu / (1 - nu^2)
    Eigen::Matrix3d sigma = l * eps.trace() * Eigen::Matrix3d::Identity() + 2 * mu * eps;
    if (plane_stress) sigma(2, 2) = 0;
    const Eigen::MatrixXd stress = ElementStress(body, u);
    REQUIRE(stress.cols() == mesh.NumElements());
    for (int e = 0; e < mesh.NumElements(); ++e)
      for (int k = 0; k < 9; ++k)
        CHECK_THAT(stress(k, e),
                   Catch::Matchers::WithinAbs(sigma(k / 3, k % 3), 1e-6 * sigma.norm()));
  };
  for (const ElementType type : {ElementType::kTriangle3, ElementType::kQuadrilateral4}) {
    RectangleMeshOptions options;
    options.size = {2.0, 1.0};
    options.cells = {3, 2};
    options.element_type = type;
    options.topology = MeshTopology::kUnstructured;  // distorted elements
    check(MakeRectangleMesh(options), {PlaneModel::kPlaneStrain, 1.0});
    check(MakeRectangleMesh(options), {PlaneModel::kPlaneStress, 0.1});
  }
  for (const ElementType type : {ElementType::kTetrahedron4, ElementType::kHexahedron8}) {
    BoxMeshOptions options;
    options.cells = {2, 2, 2};
    options.element_type = type;
    check(MakeBoxMesh(options), {});
  }
}

TEST_CASE("contact state: round-off forces are open, slip within accuracy is stick",
          "[vtk_writer]") {
  CHECK(ClassifyContact(0.0, 0.0, 1e-6, 1e-12) == ContactState::kOpen);
  CHECK(ClassifyContact(3.9e-19, 0.0, 1e-6, 1e-12) == ContactState::kOpen);  // in flight
  CHECK(ClassifyContact(1e-6, 1.0, 1e-6, 1e-12) ==
        ContactState::kOpen);  // at the accuracy
  CHECK(ClassifyContact(2e-6, 1e-12, 1e-6, 1e-12) == ContactState::kStick);
  CHECK(ClassifyContact(2e-6, 2e-12, 1e-6, 1e-12) == ContactState::kSlip);
  CHECK(ClassifyContact(std::nan(""), 0.0, 1e-6, 1e-12) == ContactState::kOpen);
}

TEST_CASE("VTK XML files: a .vtu per snapshot and a .pvd series", "[vtk_writer]") {
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {2, 1};
  const Mesh mesh = MakeRectangleMesh(options);
  const std::string vtu = std::string(P_tmpdir) + "/contact_test_mesh.vtu";
  WriteVtu(vtu, mesh, {{"node", Eigen::RowVectorXd::LinSpaced(6, 0, 5)}},
           {{"cell", Eigen::RowVectorXd::Constant(2, std::nan(""))}});
  const std::string text = ReadAll(vtu);
  std::remove(vtu.c_str());
  CHECK(text.find("<VTKFile type=\"UnstructuredGrid\"") != std::string::npos);
  CHECK(text.find("<Piece NumberOfPoints=\"6\" NumberOfCells=\"2\">") !=
        std::string::npos);
  CHECK(text.find("Name=\"node\" NumberOfComponents=\"1\" format=\"binary\"") !=
        std::string::npos);
  CHECK(text.find("Name=\"cell\"") != std::string::npos);
  // types: base64 of (UInt32 2, UInt8 9, 9) = 02 00 00 00 09 09.
  CHECK(text.find("Name=\"types\" NumberOfComponents=\"1\" format=\"binary\">\n          "
                  "AgAAAAkJ\n") != std::string::npos);
  CHECK_THROWS_WITH(WriteVtu(vtu, mesh, {}, {{"stress", Eigen::MatrixXd::Zero(4, 2)}}),
                    Catch::Contains("needs 1, 3 or 9 rows"));
  CHECK_THROWS_WITH(WriteVtu(vtu, mesh, {{"a<b", Eigen::MatrixXd::Zero(1, 6)}}),
                    Catch::Contains("without spaces or XML characters"));

  const std::string pvd = std::string(P_tmpdir) + "/contact_test_series.pvd";
  WritePvd(pvd, {{0.0, "snapshot_00000.vtu"}, {0.25, "snapshot_00010.vtu"}});
  const std::string series = ReadAll(pvd);
  std::remove(pvd.c_str());
  CHECK(series.find(
            "<DataSet timestep=\"0\" part=\"0\" file=\"snapshot_00000.vtu\"/>\n    "
            "<DataSet timestep=\"0.25\" part=\"0\" file=\"snapshot_00010.vtu\"/>") !=
        std::string::npos);
}

// Two pieces of one mesh (its left and right halves, as two MPI ranks would write them)
// joined by a .pvtu, written into $NCP_PVTU_DIR; tests/python/test_vtk_output.py runs
// this hidden case and reads the result with VTK's parallel reader.
TEST_CASE("pieces joined by a .pvtu", "[.vtu-pieces]") {
  const char* dir = std::getenv("NCP_PVTU_DIR");
  REQUIRE(dir != nullptr);
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {2, 1};
  const Mesh mesh = MakeRectangleMesh(options);  // 6 nodes, 2 Q4 elements
  std::vector<std::string> pieces;
  for (int half = 0; half < 2; ++half) {
    // The element of this half with its own 4 nodes, renumbered 0..3.
    Mesh piece;
    piece.dim = 2;
    piece.element_type = mesh.element_type;
    piece.nodes.resize(2, 4);
    piece.elements.resize(4, 1);
    Eigen::MatrixXd x(1, 4);
    for (int a = 0; a < 4; ++a) {
      const int node = mesh.elements(a, half);
      piece.nodes.col(a) = mesh.nodes.col(node);
      piece.elements(a, 0) = a;
      x(0, a) = mesh.nodes(0, node);  // a point field: the x coordinate [m]
    }
    pieces.push_back("piece_" + std::to_string(half) + ".vtu");
    WriteVtu(std::string(dir) + "/" + pieces.back(), piece, {{"x", x}},
             {{"rank", Eigen::MatrixXd::Constant(1, 1, half)}});
  }
  WritePvtu(std::string(dir) + "/joined.pvtu", {{"x", Eigen::MatrixXd::Zero(1, 4)}},
            {{"rank", Eigen::MatrixXd::Zero(1, 1)}}, pieces);
  CHECK_THROWS_WITH(WritePvtu(std::string(dir) + "/none.pvtu", {}, {}, {}),
                    Catch::Contains("no piece"));
}

}  // namespace
}  // namespace contact
