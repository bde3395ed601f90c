// WriteVtk: the legacy file lists the points, cells, cell types and point data.
#include <catch2/catch.hpp>
#include <contact/mesh_generation.hpp>
#include <contact/vtk_writer.hpp>
#include <cstdio>
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

}  // namespace
}  // namespace contact
