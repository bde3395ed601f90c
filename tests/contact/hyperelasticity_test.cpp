// ElasticBody at finite strain: exact under rigid motion for every element type, the
// tangent against central differences of the internal force, the small-strain limit
// (f_int = K u, W = u'Ku/2), the plane-stress condition, and refused input.
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

const IsotropicMaterial kMaterial{2e7, 0.3, 1200};

Mesh Rectangle(ElementType type) {
  RectangleMeshOptions options;
  options.origin = {-0.04, 0.01};
  options.size = {0.1, 0.05};
  options.cells = {4, 3};
  options.element_type = type;
  options.topology = MeshTopology::kStructured;
  options.side_roles = {{Side::kYMin, BoundaryRole::kContact}};
  Mesh mesh = MakeRectangleMesh(options);
  testing::PerturbInteriorNodes(&mesh, 0.0125, 0.2);
  return mesh;
}

Mesh Box(ElementType type) {
  BoxMeshOptions options;
  options.origin = {0.01, -0.03, 0.05};
  options.size = {0.1, 0.06, 0.04};
  options.cells = {3, 2, 2};
  options.element_type = type;
  options.topology = MeshTopology::kStructured;
  options.side_roles = {{Side::kZMin, BoundaryRole::kContact}};
  Mesh mesh = MakeBoxMesh(options);
  testing::PerturbInteriorNodes(&mesh, 0.02, 0.2);
  return mesh;
}

struct Case {
  const char* label;
  ElasticBody body;
};

std::vector<Case> Cases(PlaneModel plane = PlaneModel::kPlaneStrain) {
  const PlaneSettings settings{plane, 0.02};
  return {
      {"T3", ElasticBody(Rectangle(ElementType::kTriangle3), kMaterial, settings)},
      {"Q4", ElasticBody(Rectangle(ElementType::kQuadrilateral4), kMaterial, settings)},
      {"Tet4", ElasticBody(Box(ElementType::kTetrahedron4), kMaterial)},
      {"Hex8", ElasticBody(Box(ElementType::kHexahedron8), kMaterial)}};
}

// u = (R - I) X + c for a rotation by `angle` (2D: about z; 3D: about a skew axis).
Vector RigidMotion(const Mesh& mesh, double angle) {
  const int dim = mesh.dim;
  Eigen::MatrixXd R;
  if (dim == 2)
    R = Eigen::Rotation2Dd(angle).toRotationMatrix();
  else
    R = Eigen::AngleAxisd(angle, Eigen::Vector3d(1, -2, 3).normalized())
            .toRotationMatrix();
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(dim, 0.3, -0.2);
  return testing::LinearField(mesh, c, R - Eigen::MatrixXd::Identity(dim, dim));
}

// A smooth non-affine field of amplitude `scale` [m] (strains of order scale / 0.1 m).
Vector Bending(const Mesh& mesh, double scale) {
  Vector u(mesh.NumDofs());
  for (int i = 0; i < mesh.NumNodes(); ++i)
    for (int k = 0; k < mesh.dim; ++k) {
      const Eigen::VectorXd x = mesh.nodes.col(i) / 0.1;
      u(mesh.dim * i + k) = scale * std::sin(1.0 + k + 2.0 * x(0) - x(1) * (k + 1)) *
                            (1.0 + 0.5 * x(mesh.dim - 1) * x(0));
    }
  return u;
}

constexpr MaterialModel kModels[] = {MaterialModel::kLinear,
                                     MaterialModel::kSaintVenantKirchhoff,
                                     MaterialModel::kNeoHookean};

TEST_CASE("finite strain: any rigid motion gives zero force, energy and stress") {
  for (PlaneModel plane : {PlaneModel::kPlaneStrain, PlaneModel::kPlaneStress})
    for (const Case& c : Cases(plane))
      for (MaterialModel model : kModels)
        for (double angle : {0.3, 1.7, 3.0, -2.4}) {
          INFO(c.label << " " << ToString(model) << " angle " << angle);
          const Vector u = RigidMotion(c.body.mesh(), angle);
          Vector f;
          const HyperelasticEvaluation r = c.body.InternalForce(u, model, &f);
          REQUIRE(r.ok);
          // Scale: the force of a unit strain on the body, E h V / L.
          const double force_scale = kMaterial.youngs_modulus * 1e-3;
          CHECK(f.lpNorm<Eigen::Infinity>() <= 1e-12 * force_scale);
          // Energy: round-off of the energy scale E V (V <= 1e-3 m^3); a spurious strain
          // of 1e-6 would store E 1e-12 V.
          CHECK(std::abs(r.energy) <= 1e-14 * kMaterial.youngs_modulus * 1e-3);
          Eigen::MatrixXd sigma;
          REQUIRE(c.body.CauchyStress(u, model, &sigma).ok);
          CHECK(sigma.lpNorm<Eigen::Infinity>() <= 1e-12 * kMaterial.youngs_modulus);
          const StrainMeasure m = c.body.MeasureStrain(u);
          CHECK_THAT(m.spurious_strain, WithinRel(1.0 - std::cos(angle), 1e-6) ||
                                            WithinAbs(0.0, 1.0 - std::cos(angle)));
        }
}

TEST_CASE("finite strain: the tangent is the derivative of the internal force") {
  for (PlaneModel plane : {PlaneModel::kPlaneStrain, PlaneModel::kPlaneStress})
    for (const Case& c : Cases(plane))
      for (MaterialModel model : kModels) {
        if (c.body.dim() == 3 && plane == PlaneModel::kPlaneStress) continue;
        INFO(c.label << " " << ToString(model) << " " << static_cast<int>(plane));
        // Strains of about 5 % on top of a large rotation.
        const Vector u = RigidMotion(c.body.mesh(), 0.8) + Bending(c.body.mesh(), 4e-3);
        SparseMatrix K;
        REQUIRE(c.body.TangentStiffness(u, model, &K).ok);
        const Vector direction = Bending(c.body.mesh(), 1.0);
        const double h = 1e-6;
        Vector f_plus, f_minus;
        REQUIRE(c.body.InternalForce(u + h * direction, model, &f_plus).ok);
        REQUIRE(c.body.InternalForce(u - h * direction, model, &f_minus).ok);
        const Vector difference = (f_plus - f_minus) / (2 * h);
        const Vector Kd = K * direction;
        CHECK((difference - Kd).lpNorm<Eigen::Infinity>() <=
              1e-6 * Kd.lpNorm<Eigen::Infinity>());
        // The energy's derivative is the force: dW/du . d = f . d.
        const double dW = (c.body.StoredEnergy(u + h * direction, model).energy -
                           c.body.StoredEnergy(u - h * direction, model).energy) /
                          (2 * h);
        Vector f;
        c.body.InternalForce(u, model, &f);
        CHECK_THAT(dW, WithinRel(f.dot(direction), 1e-6));
      }
}

TEST_CASE("finite strain: the small-strain limit is K u and u'Ku/2") {
  for (PlaneModel plane : {PlaneModel::kPlaneStrain, PlaneModel::kPlaneStress})
    for (const Case& c : Cases(plane))
      for (MaterialModel model : kModels) {
        INFO(c.label << " " << ToString(model));
        const SparseMatrix K = c.body.StiffnessMatrix();
        SparseMatrix K0;
        REQUIRE(c.body.TangentStiffness(Vector::Zero(c.body.NumDofs()), model, &K0).ok);
        CHECK((Eigen::MatrixXd(K0 - K)).lpNorm<Eigen::Infinity>() <=
              1e-12 * (Eigen::MatrixXd(K)).lpNorm<Eigen::Infinity>());
        // Strain 2e-5: the nonlinear terms are 2e-5 of the linear ones (smaller strains
        // lose the neo-Hookean energy to round-off, 1e-16 / strain^2 relative).
        const Vector u = Bending(c.body.mesh(), 1e-6);
        Vector f;
        const HyperelasticEvaluation r = c.body.InternalForce(u, model, &f);
        const Vector Ku = K * u;
        CHECK((f - Ku).lpNorm<Eigen::Infinity>() <= 1e-4 * Ku.lpNorm<Eigen::Infinity>());
        CHECK_THAT(r.energy, WithinRel(0.5 * u.dot(Ku), 1e-4));
      }
}

TEST_CASE("finite strain: plane stress is a 3D body free in z") {
  // A uniform stretch F = diag(1 + s, 1): in plane stress the in-plane stress equals
  // that of a 3D body stretched alike and free in z (S_zz = 0 solved for C_zz).
  const double stretch = 0.2;
  for (MaterialModel model :
       {MaterialModel::kSaintVenantKirchhoff, MaterialModel::kNeoHookean}) {
    INFO(ToString(model));
    ElasticBody plate(Rectangle(ElementType::kQuadrilateral4), kMaterial,
                      {PlaneModel::kPlaneStress, 0.02});
    Eigen::Matrix2d B2 = Eigen::Matrix2d::Zero();
    B2(0, 0) = stretch;
    Eigen::MatrixXd sigma2;
    REQUIRE(
        plate
            .CauchyStress(testing::LinearField(plate.mesh(), Eigen::Vector2d::Zero(), B2),
                          model, &sigma2)
            .ok);
    // 3D: the same stretch with u_z = w z, w chosen so that sigma_zz = 0 (bisection).
    ElasticBody block(Box(ElementType::kHexahedron8), kMaterial);
    const auto sigma3_of = [&](double w) {
      Eigen::Matrix3d B3 = Eigen::Matrix3d::Zero();
      B3(0, 0) = stretch;
      B3(2, 2) = w;
      Eigen::MatrixXd sigma3;
      block.CauchyStress(testing::LinearField(block.mesh(), Eigen::Vector3d::Zero(), B3),
                         model, &sigma3);
      return Eigen::Matrix<double, 9, 1>(sigma3.col(0));
    };
    double lo = -0.3, hi = 0.0;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (sigma3_of(mid)(8) > 0 ? hi : lo) = mid;
    }
    const Eigen::Matrix<double, 9, 1> sigma3 = sigma3_of(0.5 * (lo + hi));
    for (int e = 0; e < plate.mesh().NumElements(); ++e) {
      CHECK_THAT(sigma2(0, e), WithinRel(sigma3(0), 1e-9));
      CHECK_THAT(sigma2(4, e), WithinRel(sigma3(4), 1e-9));
      CHECK(sigma2(8, e) == 0.0);
    }
  }
}

TEST_CASE("finite strain: an inverted element is named, bad names are refused") {
  ElasticBody body(Rectangle(ElementType::kTriangle3), kMaterial);
  Eigen::Matrix2d B = Eigen::Matrix2d::Zero();
  B(0, 0) = -1.5;  // x -> -x/2: det F = -0.5 everywhere
  Vector f;
  const HyperelasticEvaluation r =
      body.InternalForce(testing::LinearField(body.mesh(), Eigen::Vector2d::Zero(), B),
                         MaterialModel::kNeoHookean, &f);
  CHECK_FALSE(r.ok);
  CHECK(r.inverted_element == 0);
  CHECK_THAT(r.det_F, WithinRel(-0.5, 1e-12));
  CHECK_THAT(r.message, Catch::Matchers::Contains("element 0"));
  CHECK_THROWS_WITH(MaterialModelFromString("mooney"),
                    Catch::Matchers::Contains("material.model") &&
                        Catch::Matchers::Contains("neo-hookean"));
  CHECK(MaterialModelFromString("neo-hookean") == MaterialModel::kNeoHookean);
  // Neo-Hookean with nu = 0.5 (incompressible: lambda infinite) is refused.
  CHECK_THROWS_WITH(ElasticBody(Rectangle(ElementType::kTriangle3), {2e7, 0.5, 1200}),
                    Catch::Matchers::Contains("nu"));
}

}  // namespace
}  // namespace contact
