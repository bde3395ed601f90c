// ElasticBody: mass totals and element values, rigid-body null space of K, symmetry and
// definiteness, strain energy of a constant strain, load vector totals.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <contact/elastic_body.hpp>
#include <contact/mesh_generation.hpp>

#include "fem_test_support.hpp"

namespace contact {
namespace {

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

const IsotropicMaterial kMaterial{70e9, 0.33, 2700};

Mesh Rectangle(ElementType type, MeshTopology topology,
               std::array<int, 2> cells = {5, 3}) {
  RectangleMeshOptions options;
  options.origin = {-0.4, 0.2};
  options.size = {2.0, 0.75};
  options.cells = cells;
  options.element_type = type;
  options.topology = topology;
  options.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                        {Side::kXMax, BoundaryRole::kLoad},
                        {Side::kYMin, BoundaryRole::kContact}};
  return MakeRectangleMesh(options);
}

Mesh Box(ElementType type, MeshTopology topology, std::array<int, 3> cells = {3, 2, 2}) {
  BoxMeshOptions options;
  options.origin = {0.1, -0.3, 0.5};
  options.size = {1.5, 0.6, 0.4};
  options.cells = cells;
  options.element_type = type;
  options.topology = topology;
  options.side_roles = {{Side::kXMin, BoundaryRole::kFixed},
                        {Side::kXMax, BoundaryRole::kLoad},
                        {Side::kZMin, BoundaryRole::kContact}};
  return MakeBoxMesh(options);
}

struct Case {
  const char* label;
  Mesh mesh;
  double volume;  // of the domain, without thickness
};

std::vector<Case> Cases() {
  Mesh distorted_quads =
      Rectangle(ElementType::kQuadrilateral4, MeshTopology::kStructured);
  testing::PerturbInteriorNodes(&distorted_quads, 0.25, 0.2);
  Mesh distorted_hexes = Box(ElementType::kHexahedron8, MeshTopology::kStructured);
  testing::PerturbInteriorNodes(&distorted_hexes, 0.2, 0.2);
  return {
      {"T3 unstructured", Rectangle(ElementType::kTriangle3, MeshTopology::kUnstructured),
       1.5},
      {"Q4 distorted", distorted_quads, 1.5},
      {"Q4 unstructured",
       Rectangle(ElementType::kQuadrilateral4, MeshTopology::kUnstructured), 1.5},
      {"Tet4 unstructured", Box(ElementType::kTetrahedron4, MeshTopology::kUnstructured),
       0.36},
      {"Hex8 distorted", distorted_hexes, 0.36},
  };
}

double MaxAbs(const SparseMatrix& A) {
  double m = 0;
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it)
      m = std::max(m, std::abs(it.value()));
  return m;
}

TEST_CASE("total consistent and lumped mass equal rho * volume per direction",
          "[elastic_body]") {
  const double thickness = 0.05;
  for (const Case& c : Cases()) {
    INFO(c.label);
    const ElasticBody body(c.mesh, kMaterial, {PlaneModel::kPlaneStress, thickness});
    const double expected =
        kMaterial.density * c.volume * (body.dim() == 2 ? thickness : 1.0);
    const SparseMatrix M = body.ConsistentMassMatrix();
    const Vector lumped = body.LumpedMass();
    for (int k = 0; k < body.dim(); ++k) {
      Vector direction = Vector::Zero(body.NumDofs());
      for (int i = 0; i < c.mesh.NumNodes(); ++i) direction(body.dim() * i + k) = 1.0;
      CHECK_THAT(direction.dot(M * direction), WithinRel(expected, 1e-12));
      CHECK_THAT(direction.dot(lumped), WithinRel(expected, 1e-12));
    }
    // The lumped mass is the row sum of M.
    CHECK(((M * Vector::Ones(body.NumDofs())) - lumped).lpNorm<Eigen::Infinity>() <
          1e-12 * lumped.maxCoeff());
    CHECK(lumped.minCoeff() > 0);
  }
}

TEST_CASE("element mass matrices match the closed forms", "[elastic_body]") {
  SECTION("Q4 rectangle a x b: M_aa = rho a b h / 9, opposite corners rho a b h / 36") {
    RectangleMeshOptions options;
    options.size = {0.8, 0.5};
    options.cells = {1, 1};
    const ElasticBody body(MakeRectangleMesh(options), kMaterial,
                           {PlaneModel::kPlaneStrain, 2.0});
    const SparseMatrix M = body.ConsistentMassMatrix();
    const double m = kMaterial.density * 0.8 * 0.5 * 2.0;
    const auto& nodes = body.mesh().elements;
    CHECK_THAT(M.coeff(2 * nodes(0, 0), 2 * nodes(0, 0)), WithinRel(m / 9, 1e-14));
    CHECK_THAT(M.coeff(2 * nodes(0, 0) + 1, 2 * nodes(2, 0) + 1),
               WithinRel(m / 36, 1e-14));
    CHECK_THAT(M.coeff(2 * nodes(0, 0), 2 * nodes(1, 0)), WithinRel(m / 18, 1e-14));
    CHECK(M.coeff(2 * nodes(0, 0), 2 * nodes(1, 0) + 1) == 0.0);
  }
  SECTION("Tet4: M_aa = rho V / 10, M_ab = rho V / 20") {
    Mesh mesh;
    mesh.dim = 3;
    mesh.element_type = ElementType::kTetrahedron4;
    mesh.nodes.resize(3, 4);
    mesh.nodes << 0.1, 1.1, 0.3, 0.2,  //
        0.0, 0.2, 0.9, 0.1,            //
        0.0, 0.1, 0.2, 1.3;
    mesh.elements.resize(4, 1);
    mesh.elements << 0, 1, 2, 3;
    const double volume =
        (mesh.nodes.col(1) - mesh.nodes.col(0))
            .dot(Eigen::Vector3d(mesh.nodes.col(2) - mesh.nodes.col(0))
                     .cross(Eigen::Vector3d(mesh.nodes.col(3) - mesh.nodes.col(0)))) /
        6.0;
    REQUIRE(volume > 0);
    const SparseMatrix M = ElasticBody(mesh, kMaterial).ConsistentMassMatrix();
    CHECK_THAT(M.coeff(3 * 2 + 1, 3 * 2 + 1),
               WithinRel(kMaterial.density * volume / 10, 1e-13));
    CHECK_THAT(M.coeff(3 * 0 + 2, 3 * 3 + 2),
               WithinRel(kMaterial.density * volume / 20, 1e-13));
  }
}

TEST_CASE("K annihilates the rigid-body modes and is symmetric like M",
          "[elastic_body]") {
  for (const Case& c : Cases()) {
    INFO(c.label);
    const ElasticBody body(c.mesh, kMaterial, {PlaneModel::kPlaneStrain, 0.3});
    const SparseMatrix K = body.StiffnessMatrix();
    const SparseMatrix M = body.ConsistentMassMatrix();
    CHECK(K.nonZeros() == body.NumNonZeros());
    const DenseMatrix modes = testing::RigidBodyModes(c.mesh);
    REQUIRE(modes.cols() == (body.dim() == 2 ? 3 : 6));
    for (int r = 0; r < modes.cols(); ++r) {
      // relative to the size of K and of the mode
      const double relative = (K * modes.col(r)).lpNorm<Eigen::Infinity>() /
                              (MaxAbs(K) * modes.col(r).lpNorm<Eigen::Infinity>());
      CHECK(relative < 1e-9);
    }
    CHECK(MaxAbs(SparseMatrix(K - SparseMatrix(K.transpose()))) <= 1e-14 * MaxAbs(K));
    CHECK(MaxAbs(SparseMatrix(M - SparseMatrix(M.transpose()))) <= 1e-14 * MaxAbs(M));
  }
}

TEST_CASE("spectra on small meshes: M > 0 and K >= 0 with exactly the rigid null space",
          "[elastic_body]") {
  std::vector<Case> small = {
      {"T3", Rectangle(ElementType::kTriangle3, MeshTopology::kStructured, {2, 2}), 1.5},
      {"Q4", Rectangle(ElementType::kQuadrilateral4, MeshTopology::kStructured, {3, 2}),
       1.5},
      {"Tet4", Box(ElementType::kTetrahedron4, MeshTopology::kStructured, {2, 1, 1}),
       0.36},
      {"Hex8", Box(ElementType::kHexahedron8, MeshTopology::kStructured, {2, 2, 1}),
       0.36}};
  testing::PerturbInteriorNodes(&small[1].mesh, 0.2, 0.2);
  for (const Case& c : small) {
    INFO(c.label);
    const ElasticBody body(c.mesh, kMaterial, {PlaneModel::kPlaneStress, 1.0});
    const DenseMatrix K = DenseMatrix(body.StiffnessMatrix());
    const DenseMatrix M = DenseMatrix(body.ConsistentMassMatrix());
    const Eigen::SelfAdjointEigenSolver<DenseMatrix> k_eigen(K, Eigen::EigenvaluesOnly);
    const Eigen::SelfAdjointEigenSolver<DenseMatrix> m_eigen(M, Eigen::EigenvaluesOnly);
    REQUIRE(k_eigen.info() == Eigen::Success);
    REQUIRE(m_eigen.info() == Eigen::Success);
    const Eigen::VectorXd k_values = k_eigen.eigenvalues();  // increasing
    const int rigid = body.dim() == 2 ? 3 : 6;
    const double largest = k_values(k_values.size() - 1);
    for (int i = 0; i < rigid; ++i) CHECK(std::abs(k_values(i)) < 1e-9 * largest);
    // The first deformation mode is far from zero: no spurious zero-energy modes.
    CHECK(k_values(rigid) > 1e-4 * largest);
    CHECK(m_eigen.eigenvalues().minCoeff() > 0);
  }
}

TEST_CASE("strain energy of a constant strain is h V sigma : eps", "[elastic_body]") {
  // u = B x with symmetric B = eps; u^T K u = int sigma : eps = h V (lambda tr(eps)^2 +
  // 2 mu eps : eps), with plane-stress lambda* = E nu / (1 - nu^2).
  for (const PlaneModel model : {PlaneModel::kPlaneStrain, PlaneModel::kPlaneStress}) {
    for (const Case& c : Cases()) {
      if (c.mesh.dim == 3 && model == PlaneModel::kPlaneStress) continue;
      INFO(c.label);
      const double h = 0.2;
      const ElasticBody body(c.mesh, kMaterial, {model, h});
      const int dim = body.dim();
      Eigen::MatrixXd eps(3, 3);
      eps << 1.0, 0.3, -0.2,  //
          0.3, -0.5, 0.4,     //
          -0.2, 0.4, 0.7;
      eps = 1e-4 * eps.topLeftCorner(dim, dim).eval();
      const Vector u = testing::LinearField(c.mesh, Eigen::VectorXd::Zero(dim), eps);
      const double E = kMaterial.youngs_modulus, nu = kMaterial.poisson_ratio;
      const double mu = E / (2 * (1 + nu));
      const double lambda = (dim == 2 && model == PlaneModel::kPlaneStress)
                                ? E * nu / (1 - nu * nu)
                                : E * nu / ((1 + nu) * (1 - 2 * nu));
      const double density =
          lambda * eps.trace() * eps.trace() + 2 * mu * eps.squaredNorm();
      const double expected = (dim == 2 ? h : 1.0) * c.volume * density;
      CHECK_THAT(u.dot(body.StiffnessMatrix() * u), WithinRel(expected, 1e-11));
    }
  }
}

TEST_CASE("load vectors integrate body forces and tractions", "[elastic_body]") {
  for (const Case& c : Cases()) {
    INFO(c.label);
    const double h = 0.4;
    const ElasticBody body(c.mesh, kMaterial, {PlaneModel::kPlaneStress, h});
    const int dim = body.dim();
    const double factor = dim == 2 ? h : 1.0;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
    b(dim - 1) = -9.81 * kMaterial.density;
    const Vector f_body = body.BodyForceLoad(b);
    // Resultant = b V h, and the moment about the origin = (int x dV) x b.
    CHECK_THAT(f_body.sum(), WithinRel(b.sum() * c.volume * factor, 1e-12));

    // A pressure p on the "load" side x = xmax (outward normal +x) pushes in -x:
    // t = -p n, resultant -p * area * h along x.
    const double p = 2.5e6;
    const Vector f_pressure = body.TractionFieldLoad(
        [&](const Eigen::VectorXd&, const Eigen::VectorXd& n) -> Eigen::VectorXd {
          return -p * n;
        });
    const double area = dim == 2 ? 0.75 : 0.6 * 0.4;
    Eigen::VectorXd resultant = Eigen::VectorXd::Zero(dim);
    for (int i = 0; i < c.mesh.NumNodes(); ++i)
      resultant += f_pressure.segment(dim * i, dim);
    CHECK_THAT(resultant(0), WithinRel(-p * area * factor, 1e-12));
    for (int k = 1; k < dim; ++k)
      CHECK_THAT(resultant(k), WithinAbs(0.0, 1e-9 * p * area));

    // A linearly varying traction t_y = s * x on the contact side integrates exactly.
    const double s = 1e5;
    const Vector f_linear = body.TractionFieldLoad(
        [&](const Eigen::VectorXd& x, const Eigen::VectorXd&) -> Eigen::VectorXd {
          Eigen::VectorXd t = Eigen::VectorXd::Zero(dim);
          t(1) = s * x(0);
          return t;
        },
        kContactGroup);
    // int over the contact side of x dS: 2D [-0.4, 1.6]: (1.6^2 - 0.4^2)/2 = 1.2;
    // 3D [0.1, 1.6] x width 0.6: (1.6^2 - 0.1^2)/2 * 0.6 = 0.765.
    const double moment = dim == 2 ? 1.2 : 0.765;
    CHECK_THAT(f_linear.sum(), WithinRel(s * moment * factor, 1e-12));
  }
}

TEST_CASE("invalid loads are rejected with the expected size", "[elastic_body]") {
  const ElasticBody body(Rectangle(ElementType::kTriangle3, MeshTopology::kStructured),
                         kMaterial);
  CHECK_THROWS_WITH(
      body.BodyForceLoad(Eigen::VectorXd::Zero(3)),
      Catch::Contains("must have 2 components") && Catch::Contains("got 3"));
  CHECK_THROWS_WITH(body.TractionLoad(Eigen::VectorXd::Zero(2), "top"),
                    Catch::Contains("no boundary group 'top'"));
}

}  // namespace
}  // namespace contact
