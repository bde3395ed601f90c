// Finite strain in dynamic runs: a disc rolling without slip down a slope with the
// default kinematics ("auto") against the closed form a = 2/3 g sin(alpha), keeping its
// area; the same disc forced to small strain ends outside-small-strain; a scene that does
// not rotate keeps small strain; an inverted element ends the run with a status naming
// it; bad names are refused with the key.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "contact/scene.hpp"

using namespace contact;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double kRadius = 0.05;  // [m]
constexpr double kPi = 3.14159265358979323846;

// A T3 disc of `rings` rings around its centre node (ring i: 6 i nodes at equal angles,
// neighbouring rings zipped by angle), centre at the origin; the outer edges form the
// "contact" group.
Mesh Disc(int rings) {
  Mesh mesh;
  mesh.dim = 2;
  mesh.element_type = ElementType::kTriangle3;
  std::vector<Eigen::Vector2d> nodes{Eigen::Vector2d::Zero()};
  std::vector<int> first{0};  // first node of each ring
  for (int i = 1; i <= rings; ++i) {
    first.push_back(static_cast<int>(nodes.size()));
    for (int j = 0; j < 6 * i; ++j) {
      const double angle = 2 * kPi * j / (6 * i);
      nodes.emplace_back(kRadius * i / rings *
                         Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  }
  std::vector<Eigen::Vector3i> triangles;
  for (int i = 1; i <= rings; ++i) {
    const int m = i == 1 ? 1 : 6 * (i - 1), n = 6 * i;
    const auto inner = [&](int k) { return first[i - 1] + (k % m); };
    const auto outer = [&](int k) { return first[i] + (k % n); };
    int a = 0, b = 0;
    while (a < (i == 1 ? 0 : m) || b < n) {
      const bool advance_inner =
          i > 1 && a < m &&
          (b == n || static_cast<double>(a + 1) / m < static_cast<double>(b + 1) / n);
      if (advance_inner) {
        triangles.emplace_back(inner(a), outer(b), inner(a + 1));
        ++a;
      } else {
        triangles.emplace_back(inner(a), outer(b), outer(b + 1));
        ++b;
      }
    }
  }
  mesh.nodes.resize(2, static_cast<Eigen::Index>(nodes.size()));
  for (size_t k = 0; k < nodes.size(); ++k)
    mesh.nodes.col(static_cast<Eigen::Index>(k)) = nodes[k];
  mesh.elements.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (size_t k = 0; k < triangles.size(); ++k)
    mesh.elements.col(static_cast<Eigen::Index>(k)) = triangles[k];
  BoundaryFacets contact;
  contact.type = FacetType::kLine2;
  contact.connectivity.resize(2, 6 * rings);
  for (int j = 0; j < 6 * rings; ++j) {
    contact.connectivity(0, j) = first[rings] + j;
    contact.connectivity(1, j) = first[rings] + (j + 1) % (6 * rings);
  }
  mesh.boundary_groups[kContactGroup] = contact;
  return mesh;
}

double DeformedArea(const Mesh& mesh, const Eigen::VectorXd& u) {
  double area = 0.0;
  for (int e = 0; e < mesh.NumElements(); ++e) {
    Eigen::Vector2d x[3];
    for (int a = 0; a < 3; ++a) {
      const int node = mesh.elements(a, e);
      x[a] = mesh.nodes.col(node) + u.segment<2>(2 * node);
    }
    const Eigen::Vector2d p = x[1] - x[0], q = x[2] - x[0];
    area += 0.5 * (p(0) * q(1) - p(1) * q(0));
  }
  return area;
}

// The disc (E = 2e7 Pa, rho = 1000 kg/m^3) on the floor y >= -R under gravity tilted by
// alpha = 20 degrees (the slope), f_c = 0.5 > tan(alpha) / 3: it rolls without slip.
Scene RollingDisc(const std::string& name, const std::string& material_extra,
                  double end_time) {
  const double g = 9.81, alpha = 20.0 * kPi / 180.0, rho = 1000.0;
  const fs::path dir = fs::temp_directory_path() / "contact_finite_strain_tests";
  fs::create_directories(dir);
  const fs::path path = dir / (name + ".toml");
  char loads[120];
  std::snprintf(loads, sizeof loads, "[loads]\nbody_force = [%.17g, %.17g]\n",
                rho * g * std::sin(alpha), -rho * g * std::cos(alpha));
  std::ofstream(path) << "[geometry]\ntype = \"rectangle\"\nsize = [0.1, 0.1]\n"
                         "cells = [1, 1]\ncontact = [\"ymin\"]\n"
                         "[material]\nyoung_modulus = 2e7\npoisson_ratio = 0.3\n"
                         "density = 1000\nmass = \"lumped\"\n"
                      << material_extra << loads
                      << "[obstacle]\ntype = \"plane\"\nnormal = [0.0, 1.0]\n"
                         "offset = -0.05\nnormal_source = \"obstacle\"\n"
                         "[friction]\ncoefficient = 0.5\n"
                         "[solver]\nfriction = \"lagged-bound\"\n"
                         "[time]\ndt = 1e-5\nend_time = "
                      << end_time << "\ninitial_state = \"velocity\"\n"
                      << "initial_velocity = [0.0, 0.0]\n";
  return LoadScene(path.string());
}

TEST_CASE("finite strain: a disc rolls down a slope at 2/3 g sin(alpha), area kept") {
  const Scene scene = RollingDisc("rolling_disc", "", 0.12);
  const SceneModel built = BuildSceneModel(scene, Disc(6));
  // The centre node's displacement along the slope at every step.
  std::vector<double> t, x;
  DynamicOptions options = built.options;
  options.on_step = [&](const StepRecord& rec, const Eigen::VectorXd& u,
                        const ContactSystem::Result&, double) {
    t.push_back(rec.time);
    x.push_back(u(built.dofs.FreeIndex(0)));
  };
  const DynamicSummary s = RunDynamics(built.model, options);
  INFO(s.message);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  CHECK(s.kinematics == "finite");
  CHECK(s.finite_strain_from_step > 0);  // auto started small (the disc at rest)
  CHECK(s.material_model == "saint-venant-kirchhoff");
  // Least squares of x = x0 + v0 t + a t^2 / 2 after the first 20 ms (the contact force
  // builds up from zero at the start, and with it the friction bound).
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 0.02) continue;
    const Eigen::Vector3d basis(1.0, t[k], t[k] * t[k] / 2.0);
    normal += basis * basis.transpose();
    right += basis * x[k];
  }
  const double a = normal.ldlt().solve(right)(2);
  const double exact = 2.0 / 3.0 * 9.81 * std::sin(20.0 * kPi / 180.0);
  INFO("finite strain from step "
       << s.finite_strain_from_step << ", energy balance error " << s.energy_balance_error
       << " J of " << s.records.back().external_work << " J external work");
  CHECK_THAT(a, WithinRel(exact, 0.02));
  // It turned by x / R (about 0.3 rad), and kept its area to the elastic strain.
  CHECK(x.back() / kRadius > 0.25);
  const Mesh& mesh = built.body->mesh();
  const double area0 = DeformedArea(mesh, Eigen::VectorXd::Zero(mesh.NumDofs()));
  CHECK_THAT(DeformedArea(mesh, built.dofs.Expand(s.u)), WithinRel(area0, 1e-3));
  // The energy balance closes to a small part of the work of gravity.
  CHECK(s.energy_balance_error <= 1e-3 * s.records.back().external_work);
}

TEST_CASE("finite strain: the rolling disc forced to small strain is not completed") {
  const Scene scene = RollingDisc("rolling_disc_small", "kinematics = \"small\"\n", 0.04);
  const SceneModel built = BuildSceneModel(scene, Disc(3));
  const DynamicSummary s = RunDynamics(built.model, built.options);
  CHECK(s.status == DynamicStatus::kOutsideSmallStrain);
  CHECK(s.kinematics == "small");
  CHECK(s.small_strain_invalid_step > 0);
  CHECK(s.max_rotation > 1e-3);
  CHECK_THAT(s.message, Contains("rotation") && Contains("material.kinematics"));
}

TEST_CASE("finite strain: an inverted element ends the run naming element and step") {
  const Scene scene =
      RollingDisc("rolling_disc_inverted", "kinematics = \"finite\"\n", 0.01);
  const SceneModel built = BuildSceneModel(scene, Disc(2));
  DynamicOptions options = built.options;
  // The centre node alone thrown through its ring of nodes (2.5 cm away) in one step.
  options.v0 = Eigen::VectorXd::Zero(built.dofs.NumFreeDofs());
  options.v0(built.dofs.FreeIndex(0)) = 5000.0;  // [m/s]: 5 cm in one step of 1e-5 s
  options.allow_unstable_time_step = true;
  const DynamicSummary s = RunDynamics(built.model, options);
  CHECK(s.status == DynamicStatus::kInvertedElement);
  CHECK_THAT(s.message, Contains("step 1") && Contains("element") && Contains("det F"));
  CHECK(std::string(ToString(s.status)) == "inverted-element");
}

TEST_CASE("finite strain: bad material and kinematics names are refused with the key") {
  CHECK_THROWS_WITH(RollingDisc("bad_model", "model = \"mooney\"\n", 0.01),
                    Contains("material.model"));
  CHECK_THROWS_WITH(RollingDisc("bad_kinematics", "kinematics = \"large\"\n", 0.01),
                    Contains("material.kinematics"));
  CHECK_THROWS_WITH(RollingDisc("bad_tolerance", "kinematics_tolerance = 0\n", 0.01),
                    Contains("material.kinematics_tolerance"));
  CHECK_THROWS_WITH(
      RollingDisc("small_neo_hookean",
                  "model = \"neo-hookean\"\nkinematics = \"small\"\n", 0.01),
      Contains("material.model") && Contains("finite-strain model"));
}

}  // namespace
