// ContactBoundary: boundary matrix A, tributary areas and outward nodal normals.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/contact_boundary.hpp>
#include <contact/mesh_generation.hpp>

namespace contact {
namespace {

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

const IsotropicMaterial kMaterial{1e9, 0.25, 1000};

TEST_CASE("2D: tributary lengths times thickness sum to the contact length",
          "[contact_boundary]") {
  // Gamma_c = bottom (length 3) and right side (length 1.2) of [0, 3] x [0, 1.2].
  for (const ElementType type : {ElementType::kTriangle3, ElementType::kQuadrilateral4}) {
    for (const MeshTopology topology :
         {MeshTopology::kStructured, MeshTopology::kUnstructured}) {
      RectangleMeshOptions options;
      options.size = {3.0, 1.2};
      options.cells = {6, 4};
      options.element_type = type;
      options.topology = topology;
      options.side_roles = {{Side::kYMin, BoundaryRole::kContact},
                            {Side::kXMax, BoundaryRole::kContact},
                            {Side::kXMin, BoundaryRole::kFixed}};
      const double h = 0.2;
      const ElasticBody body(MakeRectangleMesh(options), kMaterial,
                             {PlaneModel::kPlaneStrain, h});
      const ContactBoundary gamma = MakeContactBoundary(body);
      INFO(ToString(type));
      CHECK_THAT(gamma.tributary_area.sum(), WithinRel(h * (3.0 + 1.2), 1e-13));
      CHECK_THAT(Vector::Ones(gamma.NumNodes())
                     .dot(gamma.boundary_matrix * Vector::Ones(gamma.NumNodes())),
                 WithinRel(h * 4.2, 1e-13));
      CHECK(gamma.tributary_area.minCoeff() > 0);
      CHECK(SparseMatrix(gamma.boundary_matrix -
                         SparseMatrix(gamma.boundary_matrix.transpose()))
                .norm() == 0.0);
      CHECK(gamma.LumpedBoundaryMatrix().diagonal().isApprox(gamma.tributary_area));
      // Every contact node is on y = 0 or x = 3, and contact_index inverts nodes.
      for (int k = 0; k < gamma.NumNodes(); ++k) {
        const Eigen::VectorXd x = body.mesh().nodes.col(gamma.nodes[k]);
        CHECK((std::abs(x(1)) < 1e-12 || std::abs(x(0) - 3.0) < 1e-12));
        CHECK(gamma.contact_index[gamma.nodes[k]] == k);
      }
    }
  }
}

TEST_CASE("2D structured: nodal tributary lengths and normals, including the corner",
          "[contact_boundary]") {
  RectangleMeshOptions options;
  options.size = {3.0, 1.2};
  options.cells = {6, 4};  // dx = 0.5, dy = 0.3
  options.side_roles = {{Side::kYMin, BoundaryRole::kContact},
                        {Side::kXMax, BoundaryRole::kContact}};
  const ElasticBody body(MakeRectangleMesh(options), kMaterial);
  const ContactBoundary gamma = MakeContactBoundary(body);
  REQUIRE(gamma.NumNodes() == 7 + 4);
  for (int k = 0; k < gamma.NumNodes(); ++k) {
    const Eigen::Vector2d x = body.mesh().nodes.col(gamma.nodes[k]);
    const Eigen::Vector2d n = gamma.normals.col(k);
    INFO("node at " << x.transpose());
    if (x.isApprox(Eigen::Vector2d(3.0, 0.0))) {
      // corner: (0.5 (0,-1) + 0.3 (1,0)) / |.| — dx/2 + dy/2 tributary length
      CHECK_THAT(gamma.tributary_area(k), WithinRel(0.25 + 0.15, 1e-13));
      CHECK_THAT(n(0), WithinRel(0.3 / std::hypot(0.3, 0.5), 1e-13));
      CHECK_THAT(n(1), WithinRel(-0.5 / std::hypot(0.3, 0.5), 1e-13));
    } else if (std::abs(x(1)) < 1e-12) {
      CHECK_THAT(gamma.tributary_area(k), WithinRel(x(0) == 0.0 ? 0.25 : 0.5, 1e-13));
      CHECK_THAT(n(0), WithinAbs(0.0, 1e-15));
      CHECK_THAT(n(1), WithinAbs(-1.0, 1e-15));
    } else {
      CHECK_THAT(gamma.tributary_area(k),
                 WithinRel(std::abs(x(1) - 1.2) < 1e-12 ? 0.15 : 0.3, 1e-13));
      CHECK_THAT(n(0), WithinAbs(1.0, 1e-15));
      CHECK_THAT(n(1), WithinAbs(0.0, 1e-15));
    }
  }
}

TEST_CASE("normals follow a rotation of the body", "[contact_boundary]") {
  RectangleMeshOptions options;
  options.size = {2.0, 1.0};
  options.cells = {4, 3};
  options.element_type = ElementType::kTriangle3;
  options.side_roles = {{Side::kYMin, BoundaryRole::kContact}};
  Mesh mesh = MakeRectangleMesh(options);
  const double angle = 0.6;
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(angle).toRotationMatrix();
  mesh.nodes = rotation * mesh.nodes;
  const Eigen::MatrixXd normals = OutwardNodalNormals(mesh, kContactGroup);
  const Eigen::Vector2d expected = rotation * Eigen::Vector2d(0, -1);
  for (int k = 0; k < normals.cols(); ++k)
    CHECK((normals.col(k) - expected).norm() < 1e-14);
  CHECK_THAT(BoundaryMeasure(mesh, kContactGroup), WithinRel(2.0, 1e-14));
}

TEST_CASE("3D: tributary areas sum to the contact area, normals are outward",
          "[contact_boundary]") {
  for (const ElementType type : {ElementType::kTetrahedron4, ElementType::kHexahedron8}) {
    BoxMeshOptions options;
    options.origin = {-1.0, 0.0, 2.0};
    options.size = {2.0, 1.5, 0.5};
    options.cells = {4, 3, 2};
    options.element_type = type;
    options.topology = type == ElementType::kTetrahedron4 ? MeshTopology::kUnstructured
                                                          : MeshTopology::kStructured;
    options.side_roles = {{Side::kZMin, BoundaryRole::kContact},
                          {Side::kYMax, BoundaryRole::kLoad}};
    const ElasticBody body(MakeBoxMesh(options), kMaterial);
    const ContactBoundary gamma = MakeContactBoundary(body);
    INFO(ToString(type));
    CHECK_THAT(gamma.tributary_area.sum(), WithinRel(2.0 * 1.5, 1e-13));
    CHECK_THAT(BoundaryMeasure(body.mesh(), kLoadGroup), WithinRel(2.0 * 0.5, 1e-13));
    for (int k = 0; k < gamma.NumNodes(); ++k)
      CHECK((gamma.normals.col(k) - Eigen::Vector3d(0, 0, -1)).norm() < 1e-14);
    const Eigen::MatrixXd load_normals = OutwardNodalNormals(body.mesh(), kLoadGroup);
    for (int k = 0; k < load_normals.cols(); ++k)
      CHECK((load_normals.col(k) - Eigen::Vector3d(0, 1, 0)).norm() < 1e-14);
  }
  SECTION("structured Hex8: interior contact node of a 4 x 3 grid has area dx dy") {
    BoxMeshOptions options;
    options.size = {2.0, 1.5, 0.5};
    options.cells = {4, 3, 2};
    options.side_roles = {{Side::kZMax, BoundaryRole::kContact}};
    const ElasticBody body(MakeStructuredBoxMesh(options), kMaterial);
    const ContactBoundary gamma = MakeContactBoundary(body);
    REQUIRE(gamma.NumNodes() == 5 * 4);
    const double dx = 0.5, dy = 0.5;
    for (int k = 0; k < gamma.NumNodes(); ++k) {
      const Eigen::Vector3d x = body.mesh().nodes.col(gamma.nodes[k]);
      const bool edge_x = std::abs(x(0)) < 1e-12 || std::abs(x(0) - 2.0) < 1e-12;
      const bool edge_y = std::abs(x(1)) < 1e-12 || std::abs(x(1) - 1.5) < 1e-12;
      CHECK_THAT(gamma.tributary_area(k),
                 WithinRel(dx * dy * (edge_x ? 0.5 : 1.0) * (edge_y ? 0.5 : 1.0), 1e-13));
      CHECK((gamma.normals.col(k) - Eigen::Vector3d(0, 0, 1)).norm() < 1e-14);
    }
    // Consistent A of a dx x dy bilinear face: A_kk = dx dy / 9 from each adjacent face.
    const int corner =
        gamma.contact_index[body.mesh().BoundaryGroup(kContactGroup).connectivity(0, 0)];
    CHECK_THAT(gamma.boundary_matrix.coeff(corner, corner),
               WithinRel(dx * dy / 9, 1e-13));
  }
}

TEST_CASE("contact boundary errors name the group", "[contact_boundary]") {
  RectangleMeshOptions options;
  options.side_roles = {{Side::kXMin, BoundaryRole::kFixed}};
  ElasticBody without_contact(MakeRectangleMesh(options), kMaterial);
  CHECK_THROWS_WITH(MakeContactBoundary(without_contact),
                    Catch::Contains("no boundary group 'contact'") &&
                        Catch::Contains("available groups: 'fixed'"));

  Mesh mesh = MakeRectangleMesh(options);
  mesh.boundary_groups[kContactGroup].type = FacetType::kLine2;
  mesh.boundary_groups[kContactGroup].connectivity.resize(2, 0);
  const ElasticBody empty_contact(mesh, kMaterial);
  CHECK_THROWS_AS(MakeContactBoundary(empty_contact), std::invalid_argument);
  CHECK_THROWS_WITH(
      MakeContactBoundary(empty_contact),
      Catch::Contains("empty contact set") && Catch::Contains("'contact' has 0 facets"));

  // A "facet" through the interior is not a face of any element.
  Mesh interior = MakeRectangleMesh(options);
  BoundaryFacets bogus;
  bogus.type = FacetType::kLine2;
  bogus.connectivity.resize(2, 1);
  bogus.connectivity << interior.elements(0, 0), interior.elements(2, 0);  // a diagonal
  interior.boundary_groups[kContactGroup] = bogus;
  const ElasticBody diagonal(interior, kMaterial);
  CHECK_THROWS_WITH(MakeContactBoundary(diagonal),
                    Catch::Contains("is not a face of any element"));

  // The edge x = 0.5 between two elements of a 2 x 1 mesh is interior.
  RectangleMeshOptions two_cells;
  two_cells.cells = {2, 1};
  Mesh interface = MakeRectangleMesh(two_cells);
  BoundaryFacets middle;
  middle.type = FacetType::kLine2;
  middle.connectivity.resize(2, 1);
  int column = 0;
  for (int i = 0; i < interface.NumNodes(); ++i)
    if (interface.nodes(0, i) == 0.5) middle.connectivity(column++, 0) = i;
  REQUIRE(column == 2);
  interface.boundary_groups[kContactGroup] = middle;
  const ElasticBody interior_face(interface, kMaterial);
  CHECK_THROWS_WITH(MakeContactBoundary(interior_face),
                    Catch::Contains("is an interior face shared by element"));
}

}  // namespace
}  // namespace contact
