// ReadGmshMesh on small hand-written MSH 4.1 files and on files written by the generator.
#include <catch2/catch.hpp>
#include <contact/contact_boundary.hpp>
#include <contact/gmsh_reader.hpp>
#include <contact/mesh_generation.hpp>
#include <cstdio>
#include <fstream>
#include <string>

namespace contact {
namespace {

using Catch::Matchers::WithinRel;

// Writes `text` to a file in the temporary directory and removes it on destruction.
class TemporaryFile {
 public:
  TemporaryFile(const std::string& name, const std::string& text)
      : path_(std::string(P_tmpdir) + "/contact_test_" + name) {
    std::ofstream(path_) << text;
  }
  ~TemporaryFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Unit square, two triangles, node tags 10..40 (non-contiguous), bottom edge "contact",
// left edge "fixed", top edge in the unnamed physical group 7.
const char* kSquareMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "contact"
1 2 "fixed"
2 3 "body"
$EndPhysicalNames
$Entities
0 3 1 0
1 0 0 0 1 0 0 1 1 0
2 0 0 0 0 1 0 1 2 0
3 0 1 0 1 1 0 1 7 0
1 0 0 0 1 1 0 1 3 3 1 2 3
$EndEntities
$Nodes
1 4 10 40
2 1 0 4
10
20
30
40
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
4 5 1 5
1 1 1 1
1 10 20
1 2 1 1
2 40 10
1 3 1 1
3 30 40
2 1 2 2
4 10 20 30
5 10 30 40
$EndElements
)";

// One second-order (6-node) triangle.
const char* kQuadraticTriangleMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 1 1 0 0 0
$EndEntities
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
1 0 0
0 1 0
0.5 0 0
0.5 0.5 0
0 0.5 0
$EndNodes
$Elements
1 1 1 1
2 1 9 1
1 1 2 3 4 5 6
$EndElements
)";

// One cubic 10-node triangle (gmsh type 21): not supported.
const char* kCubicTriangleMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 1 1 0 0 0
$EndEntities
$Nodes
1 10 1 10
2 1 0 10
1
2
3
4
5
6
7
8
9
10
0 0 0
3 0 0
0 3 0
1 0 0
2 0 0
2 1 0
1 2 0
0 2 0
0 1 0
1 1 0
$EndNodes
$Elements
1 1 1 1
2 1 21 1
1 1 2 3 4 5 6 7 8 9 10
$EndElements
)";

// A triangle and a quadrilateral side by side.
const char* kMixedMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 2 1 0 0 0
$EndEntities
$Nodes
1 5 1 5
2 1 0 5
1
2
3
4
5
0 0 0
1 0 0
1 1 0
0 1 0
2 0 0
$EndNodes
$Elements
2 2 1 2
2 1 3 1
1 1 2 3 4
2 1 2 1
2 2 5 3
$EndElements
)";

// The square with a "contact" group whose curve carries no elements.
const char* kEmptyContactMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
1 1 "contact"
$EndPhysicalNames
$Entities
0 1 1 0
1 0 0 0 1 0 0 1 1 0
1 0 0 0 1 1 0 0 1 1
$EndEntities
$Nodes
1 4 1 4
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
$EndNodes
$Elements
1 2 1 2
2 1 2 2
1 1 2 3
2 1 3 4
$EndElements
)";

TEST_CASE("a hand-written MSH 4.1 file is read with compact numbering and named groups",
          "[gmsh_reader]") {
  const TemporaryFile file("square.msh", kSquareMsh);
  const Mesh mesh = ReadGmshMesh(file.path());
  CHECK(mesh.dim == 2);
  CHECK(mesh.element_type == ElementType::kTriangle3);
  REQUIRE(mesh.NumNodes() == 4);
  REQUIRE(mesh.NumElements() == 2);
  CHECK(mesh.element_tags == std::vector<std::size_t>{4, 5});
  // tags 10, 20, 30, 40 -> 0, 1, 2, 3
  CHECK(mesh.nodes.col(2).isApprox(Eigen::Vector2d(1, 1)));
  CHECK(mesh.elements.col(1) == Eigen::Vector3i(0, 2, 3));
  REQUIRE(mesh.boundary_groups.size() == 3);
  CHECK(mesh.BoundaryGroup("contact").connectivity.col(0) == Eigen::Vector2i(0, 1));
  CHECK(mesh.BoundaryGroup("fixed").connectivity.col(0) == Eigen::Vector2i(3, 0));
  CHECK(mesh.BoundaryGroup("7").NumFacets() == 1);
  CHECK_THAT(DomainMeasure(mesh), WithinRel(1.0, 1e-15));
}

TEST_CASE("unsupported element types are rejected by name", "[gmsh_reader]") {
  const TemporaryFile cubic("cubic.msh", kCubicTriangleMsh);
  CHECK_THROWS_AS(ReadGmshMesh(cubic.path()), std::invalid_argument);
  CHECK_THROWS_WITH(
      ReadGmshMesh(cubic.path()),
      Catch::Contains("unsupported element type 'Triangle 10' (gmsh type 21, order 3") &&
          Catch::Contains(cubic.path()));
  // The quadratic triangle is read: area 1/2 from its 6 nodes.
  const TemporaryFile quadratic("quadratic.msh", kQuadraticTriangleMsh);
  const Mesh mesh = ReadGmshMesh(quadratic.path());
  CHECK(mesh.element_type == ElementType::kTriangle6);
  CHECK_THAT(DomainMeasure(mesh), WithinRel(0.5, 1e-14));
  const TemporaryFile mixed("mixed.msh", kMixedMsh);
  CHECK_THROWS_WITH(ReadGmshMesh(mixed.path()),
                    Catch::Contains("unsupported mixed element types"));
}

TEST_CASE("a contact group without facets is an empty contact set", "[gmsh_reader]") {
  const TemporaryFile file("empty_contact.msh", kEmptyContactMsh);
  const Mesh mesh = ReadGmshMesh(file.path());
  REQUIRE(mesh.HasBoundaryGroup("contact"));
  CHECK(mesh.BoundaryGroup("contact").NumFacets() == 0);
  const ElasticBody body(mesh, IsotropicMaterial{1e9, 0.3, 1000});
  CHECK_THROWS_WITH(MakeContactBoundary(body), Catch::Contains("empty contact set"));
}

// gmsh 4.8 keeps tags as int and crashed (SIGSEGV in GModel::getMeshVertexByTag) on a
// node tag of 1e12; such files, binary files and non-.msh files are refused before gmsh
// opens them.
TEST_CASE("tags beyond the limit and non-ASCII or non-.msh files are refused by name",
          "[gmsh_reader]") {
  std::string big_tag = kSquareMsh;
  for (size_t at = big_tag.find("40"); at != std::string::npos;
       at = big_tag.find("40", at))
    big_tag.replace(at, 2, "1000000000000");
  const TemporaryFile big("big_tag.msh", big_tag);
  CHECK_THROWS_WITH(
      ReadGmshMesh(big.path()),
      Catch::Contains(
          "big_tag.msh:18: node tag 1000000000000 lies outside [0, 100000000]"));
  std::string binary = kSquareMsh;
  binary.replace(binary.find("4.1 0 8"), 7, "4.1 1 8");
  const TemporaryFile binary_file("binary.msh", binary);
  CHECK_THROWS_WITH(ReadGmshMesh(binary_file.path()),
                    Catch::Contains("binary.msh:2: binary .msh files"));
  const TemporaryFile script("square.geo", kSquareMsh);
  CHECK_THROWS_WITH(ReadGmshMesh(script.path()),
                    Catch::Contains("square.geo' must end in .msh"));
  // A node moved far away (fuzz case, seed 7): the mesh error names the file.
  std::string moved = kSquareMsh;
  moved.replace(moved.find("0 1 0\n$EndNodes"), 5,
                "0 -1e8 0");  // node 40: element 5 inverted
  const TemporaryFile far("moved.msh", moved);
  CHECK_THROWS_WITH(ReadGmshMesh(far.path()),
                    Catch::Contains("moved.msh'): inverted element: element 1"));
  std::string truncated = kSquareMsh;
  truncated.resize(truncated.find("$Elements") + 14);
  const TemporaryFile cut("truncated.msh", truncated);
  CHECK_THROWS_WITH(ReadGmshMesh(cut.path()), Catch::Contains("truncated.msh:"));
}

TEST_CASE("unreadable files", "[gmsh_reader]") {
  CHECK_THROWS_WITH(ReadGmshMesh("/nonexistent/mesh.msh"),
                    Catch::Contains("cannot open mesh file '/nonexistent/mesh.msh'"));
  const TemporaryFile garbage("garbage.msh", "this is not a mesh\n");
  CHECK_THROWS_AS(ReadGmshMesh(garbage.path()), std::invalid_argument);
}

TEST_CASE("generated meshes written as .msh read back identically", "[gmsh_reader]") {
  const std::string path = std::string(P_tmpdir) + "/contact_test_box.msh";
  BoxMeshOptions options;
  options.size = {1.0, 0.5, 0.25};
  options.cells = {4, 2, 2};
  options.element_type = ElementType::kTetrahedron4;
  options.topology = MeshTopology::kUnstructured;
  options.side_roles = {{Side::kZMin, BoundaryRole::kContact},
                        {Side::kXMin, BoundaryRole::kFixed}};
  options.msh_output_path = path;
  const Mesh generated = MakeBoxMesh(options);
  const Mesh read = ReadGmshMesh(path);
  std::remove(path.c_str());
  CHECK(read.NumNodes() == generated.NumNodes());
  CHECK(read.NumElements() == generated.NumElements());
  CHECK(read.BoundaryGroup("contact").NumFacets() ==
        generated.BoundaryGroup("contact").NumFacets());
  CHECK(read.BoundaryGroup("fixed").NumFacets() ==
        generated.BoundaryGroup("fixed").NumFacets());
  CHECK_THAT(DomainMeasure(read), WithinRel(0.125, 1e-12));
  CHECK_THAT(BoundaryMeasure(read, "contact"), WithinRel(0.5, 1e-12));
}

}  // namespace
}  // namespace contact
