// Mesh: validation messages (inverted element with id and centroid, bad indices, wrong
// facet types), group lookup, measures.
#include <catch2/catch.hpp>
#include <contact/elastic_body.hpp>
#include <contact/mesh.hpp>
#include <contact/mesh_generation.hpp>

namespace contact {
namespace {

using Catch::Matchers::WithinRel;

Mesh UnitCubeHexes() {
  BoxMeshOptions options;
  options.cells = {2, 2, 2};
  options.side_roles = {{Side::kZMin, BoundaryRole::kContact},
                        {Side::kZMax, BoundaryRole::kLoad}};
  return MakeStructuredBoxMesh(options);
}

TEST_CASE("an inverted element is reported with its index, tag and centroid", "[mesh]") {
  SECTION("Hex8 with mirrored node order") {
    Mesh mesh = UnitCubeHexes();
    REQUIRE_NOTHROW(ValidateMesh(mesh));
    auto element = mesh.elements.col(0);  // the cell [0, 0.5]^3
    std::swap(element(1), element(3));
    std::swap(element(5), element(7));
    CHECK_THROWS_AS(ValidateMesh(mesh), std::invalid_argument);
    CHECK_THROWS_WITH(ValidateMesh(mesh),
                      Catch::Contains("inverted element: element 0 (source tag 1)") &&
                          Catch::Contains("centroid (0.25, 0.25, 0.25)") &&
                          Catch::Contains("expected > 0"));
    const IsotropicMaterial material{1e9, 0.3, 1000};
    CHECK_THROWS_WITH(ElasticBody(mesh, material), Catch::Contains("inverted element"));
  }
  SECTION("Q4 folded by moving a shared node past its neighbour's far side") {
    // [0, 2] x [0, 1] in two squares; node (1, 1) moved to (2.5, 0.5) turns the right
    // element into a bow tie (centroid (1.875, 0.375)) and leaves the left one convex.
    RectangleMeshOptions options;
    options.size = {2.0, 1.0};
    options.cells = {2, 1};
    Mesh mesh = MakeRectangleMesh(options);
    int shared = -1;
    for (int i = 0; i < mesh.NumNodes(); ++i)
      if ((mesh.nodes.col(i) - Eigen::Vector2d(1, 1)).norm() < 1e-12) shared = i;
    REQUIRE(shared >= 0);
    mesh.nodes.col(shared) << 2.5, 0.5;
    int folded = -1;
    for (int e = 0; e < mesh.NumElements(); ++e)
      if (mesh.ElementCentroid(e).isApprox(Eigen::Vector2d(1.875, 0.375))) folded = e;
    REQUIRE(folded >= 0);
    CHECK_THROWS_WITH(ValidateMesh(mesh), Catch::Contains("inverted element: element " +
                                                          std::to_string(folded)) &&
                                              Catch::Contains("centroid (1.875, 0.375)"));
  }
}

TEST_CASE("structural errors in a hand-made mesh", "[mesh]") {
  Mesh mesh = UnitCubeHexes();
  SECTION("node index out of range") {
    mesh.elements(3, 2) = mesh.NumNodes();
    CHECK_THROWS_WITH(ValidateMesh(mesh), Catch::Contains("must lie in [0, 27)") &&
                                              Catch::Contains("got range [0, 27]"));
  }
  SECTION("facet type not matching the elements") {
    mesh.boundary_groups[kContactGroup].type = FacetType::kTriangle3;
    CHECK_THROWS_WITH(ValidateMesh(mesh),
                      Catch::Contains("group 'contact' has facets of type Triangle3") &&
                          Catch::Contains("need facets of type Quadrilateral4"));
  }
  SECTION("dimension mismatch") {
    mesh.dim = 2;
    CHECK_THROWS_WITH(ValidateMesh(mesh),
                      Catch::Contains("Hexahedron8 is 3D but mesh.dim = 2"));
  }
}

// A quad with a repeated node has det J > 0 at its 2 x 2 Gauss points: before the
// connectivity check it was accepted and run, with a hole in the mesh.
TEST_CASE("degenerate, duplicate elements and unused nodes are named errors", "[mesh]") {
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {2, 1};
  const Mesh good = MakeRectangleMesh(options);
  REQUIRE(good.NumElements() == 2);
  REQUIRE_NOTHROW(ValidateMesh(good));
  SECTION("repeated node") {
    Mesh mesh = good;
    const int kept = mesh.elements(2, 1);  // collapse the right quad into a triangle
    mesh.elements(3, 1) = kept;
    CHECK_THROWS_WITH(ValidateMesh(mesh),
                      Catch::Contains("degenerate element: element 1") &&
                          Catch::Contains("repeats node " + std::to_string(kept)));
  }
  SECTION("duplicate element") {
    Mesh mesh = good;
    mesh.elements.col(1) = mesh.elements.col(0);
    CHECK_THROWS_WITH(ValidateMesh(mesh),
                      Catch::Contains("duplicate element: element 1"));
  }
  SECTION("unused node") {
    Mesh mesh = good;
    mesh.nodes.conservativeResize(2, mesh.NumNodes() + 1);
    mesh.nodes.col(mesh.NumNodes() - 1) << 5.0, 5.0;
    CHECK_THROWS_WITH(
        ValidateMesh(mesh),
        Catch::Contains("unused node " + std::to_string(mesh.NumNodes() - 1) +
                        " at (5, 5) belongs to no element"));
  }
}

TEST_CASE("a missing group names the available ones", "[mesh]") {
  const Mesh mesh = UnitCubeHexes();
  CHECK(mesh.HasBoundaryGroup("load"));
  CHECK_FALSE(mesh.HasBoundaryGroup("fixed"));
  CHECK_THROWS_AS(mesh.BoundaryGroup("fixed"), std::invalid_argument);
  CHECK_THROWS_WITH(mesh.BoundaryGroup("fixed"),
                    Catch::Contains("mesh has no boundary group 'fixed'") &&
                        Catch::Contains("available groups: 'contact', 'load'"));
}

TEST_CASE("measures and group nodes", "[mesh]") {
  const Mesh mesh = UnitCubeHexes();
  CHECK_THAT(DomainMeasure(mesh), WithinRel(1.0, 1e-14));
  CHECK_THAT(BoundaryMeasure(mesh, kContactGroup), WithinRel(1.0, 1e-14));
  const std::vector<int> nodes = mesh.BoundaryGroup(kContactGroup).Nodes();
  CHECK(nodes.size() == 9);
  CHECK(std::is_sorted(nodes.begin(), nodes.end()));
  CHECK(mesh.NumDofs() == 81);
  CHECK(mesh.ElementCentroid(7).isApprox(Eigen::Vector3d(0.75, 0.75, 0.75)));
}

}  // namespace
}  // namespace contact
