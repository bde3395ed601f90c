// Generated rectangles and boxes: element and node counts, groups on the chosen sides,
// agreement of the gmsh and direct box generators, option validation.
#include <algorithm>
#include <catch2/catch.hpp>
#include <contact/mesh_generation.hpp>

namespace contact {
namespace {

using Catch::Matchers::WithinRel;

TEST_CASE("structured rectangles have the requested cells and side groups",
          "[mesh_generation]") {
  RectangleMeshOptions options;
  options.origin = {1.0, -2.0};
  options.size = {3.0, 0.5};
  options.cells = {6, 2};
  options.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                        {Side::kYMin, BoundaryRole::kContact},
                        {Side::kYMax, BoundaryRole::kContact},
                        {Side::kXMax, BoundaryRole::kNone}};
  SECTION("Q4") {
    const Mesh mesh = MakeRectangleMesh(options);
    CHECK(mesh.dim == 2);
    CHECK(mesh.element_type == ElementType::kQuadrilateral4);
    CHECK(mesh.NumElements() == 12);
    CHECK(mesh.NumNodes() == 21);
    CHECK(mesh.boundary_groups.size() == 2);
    CHECK(mesh.BoundaryGroup(kFixedGroup).NumFacets() == 2);
    CHECK(mesh.BoundaryGroup(kContactGroup).NumFacets() == 12);
    CHECK_FALSE(mesh.HasBoundaryGroup(kLoadGroup));
    CHECK_THAT(BoundaryMeasure(mesh, kContactGroup), WithinRel(6.0, 1e-14));
    CHECK_THAT(DomainMeasure(mesh), WithinRel(1.5, 1e-14));
    CHECK(mesh.nodes.row(0).minCoeff() == 1.0);
    CHECK(mesh.nodes.row(1).maxCoeff() == -1.5);
    for (const int node : mesh.BoundaryGroup(kFixedGroup).Nodes())
      CHECK(mesh.nodes(0, node) == 1.0);
  }
  SECTION("T3") {
    options.element_type = ElementType::kTriangle3;
    const Mesh mesh = MakeRectangleMesh(options);
    CHECK(mesh.element_type == ElementType::kTriangle3);
    CHECK(mesh.NumElements() == 24);
    CHECK(mesh.NumNodes() == 21);
  }
  SECTION("unstructured Q4 for several resolutions contains quadrilaterals only") {
    options.topology = MeshTopology::kUnstructured;
    for (const int n : {3, 7, 12}) {
      options.cells = {2 * n, n};
      const Mesh mesh = MakeRectangleMesh(options);
      CHECK(mesh.element_type == ElementType::kQuadrilateral4);
      CHECK_THAT(DomainMeasure(mesh), WithinRel(1.5, 1e-12));
    }
  }
}

TEST_CASE("boxes: gmsh structured hexahedra match the direct generator",
          "[mesh_generation]") {
  BoxMeshOptions options;
  options.origin = {0.5, 0.0, -1.0};
  options.size = {2.0, 1.0, 0.6};
  options.cells = {4, 3, 2};
  options.side_roles = {{Side::kZMin, BoundaryRole::kContact},
                        {Side::kXMin, BoundaryRole::kFixed},
                        {Side::kXMax, BoundaryRole::kLoad},
                        {Side::kYMax, BoundaryRole::kLoad}};
  const Mesh from_gmsh = MakeBoxMesh(options);
  const Mesh direct = MakeStructuredBoxMesh(options);
  for (const Mesh* mesh : {&from_gmsh, &direct}) {
    CHECK(mesh->NumElements() == 24);
    CHECK(mesh->NumNodes() == 60);
    CHECK(mesh->BoundaryGroup(kContactGroup).NumFacets() == 12);
    CHECK(mesh->BoundaryGroup(kFixedGroup).NumFacets() == 6);
    CHECK(mesh->BoundaryGroup(kLoadGroup).NumFacets() == 6 + 8);
    CHECK_THAT(DomainMeasure(*mesh), WithinRel(1.2, 1e-14));
    CHECK_THAT(BoundaryMeasure(*mesh, kLoadGroup), WithinRel(0.6 + 2.0 * 0.6, 1e-14));
    REQUIRE_NOTHROW(ValidateMesh(*mesh));
  }
  // The same node set up to numbering.
  auto sorted_points = [](const Mesh& mesh) {
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < mesh.NumNodes(); ++i)
      points.push_back({mesh.nodes(0, i), mesh.nodes(1, i), mesh.nodes(2, i)});
    std::sort(points.begin(), points.end());
    return points;
  };
  const auto a = sorted_points(from_gmsh), b = sorted_points(direct);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k) CHECK(std::abs(a[i][k] - b[i][k]) < 1e-14);
}

TEST_CASE("boxes of tetrahedra", "[mesh_generation]") {
  BoxMeshOptions options;
  options.size = {1.0, 2.0, 1.0};
  options.cells = {2, 3, 2};
  options.element_type = ElementType::kTetrahedron4;
  options.side_roles = {{Side::kZMax, BoundaryRole::kContact}};
  const Mesh structured = MakeBoxMesh(options);
  CHECK(structured.element_type == ElementType::kTetrahedron4);
  CHECK(structured.NumElements() == 6 * 12);  // each transfinite cell split in 6
  CHECK(structured.NumNodes() == 3 * 4 * 3);
  CHECK(structured.BoundaryGroup(kContactGroup).NumFacets() == 2 * 6);
  options.topology = MeshTopology::kUnstructured;
  const Mesh unstructured = MakeBoxMesh(options);
  CHECK_THAT(DomainMeasure(unstructured), WithinRel(2.0, 1e-12));
  CHECK_THAT(BoundaryMeasure(unstructured, kContactGroup), WithinRel(2.0, 1e-12));
}

// Before these limits, size 1e300 made gmsh mesh without end and an aspect ratio of 1e12
// made it ask "Do you really want to continue?" on standard input.
TEST_CASE("grids beyond the limits are refused before gmsh runs", "[mesh_generation]") {
  RectangleMeshOptions rectangle;
  rectangle.size = {1e300, 1e300};
  CHECK_THROWS_WITH(
      MakeRectangleMesh(rectangle),
      Catch::Contains("MakeRectangleMesh: size 1e+300 m lies outside (0, 1e+06] m"));
  rectangle.size = {1.0, 1e-8};
  rectangle.cells = {1, 1};
  CHECK_THROWS_WITH(MakeRectangleMesh(rectangle),
                    Catch::Contains("MakeRectangleMesh: cells of aspect ratio 1e+08 "
                                    "(edges 1 m and 1e-08 m) exceed the limit of 10000"));
  rectangle.size = {1.0, 1.0};
  rectangle.cells = {3000, 3000};
  CHECK_THROWS_WITH(
      MakeRectangleMesh(rectangle),
      Catch::Contains("MakeRectangleMesh: 9e+06 cells exceed the limit of 4e+06"));
  BoxMeshOptions box;
  box.origin = {0.0, 2e6, 0.0};
  CHECK_THROWS_WITH(MakeBoxMesh(box),
                    Catch::Contains("|origin[1]| = 2e+06 m exceeds 1e+06 m"));
  CHECK(CheckGridLimits({1.0, 0.2}, {10, 2}).empty());
}

TEST_CASE("generator options are validated", "[mesh_generation]") {
  RectangleMeshOptions rectangle;
  rectangle.size = {1.0, 0.0};
  CHECK_THROWS_WITH(MakeRectangleMesh(rectangle),
                    Catch::Contains("size along y must be finite and > 0, got 0"));
  rectangle.size = {1.0, 1.0};
  rectangle.cells = {0, 3};
  CHECK_THROWS_WITH(MakeRectangleMesh(rectangle),
                    Catch::Contains("cells along x must be >= 1, got 0"));
  rectangle.cells = {3, 3};
  rectangle.element_type = ElementType::kHexahedron8;
  CHECK_THROWS_WITH(
      MakeRectangleMesh(rectangle),
      Catch::Contains("must be kTriangle3 or kQuadrilateral4, got Hexahedron8"));
  rectangle.element_type = ElementType::kTriangle3;
  rectangle.side_roles = {{Side::kZMin, BoundaryRole::kContact}};
  CHECK_THROWS_WITH(MakeRectangleMesh(rectangle),
                    Catch::Contains("side zmin does not exist in 2D"));

  BoxMeshOptions box;
  box.topology = MeshTopology::kUnstructured;
  CHECK_THROWS_WITH(MakeBoxMesh(box),
                    Catch::Contains("unstructured hexahedral meshes are not supported"));
  CHECK_THROWS_WITH(MakeStructuredBoxMesh(box),
                    Catch::Contains("only structured kHexahedron8"));
  box.topology = MeshTopology::kStructured;
  box.element_type = ElementType::kQuadrilateral4;
  CHECK_THROWS_WITH(MakeBoxMesh(box),
                    Catch::Contains("must be kTetrahedron4 or kHexahedron8"));
}

}  // namespace
}  // namespace contact
