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
                  double end_time,
                  const std::string& normal_source = "normal_source = \"obstacle\"\n") {
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
                         "offset = -0.05\n"
                      << normal_source
                      << "[friction]\ncoefficient = 0.5\n"
                         "[solver]\nfriction = \"lagged-bound\"\n"
                         "[time]\ndt = 1e-5\nend_time = "
                      << end_time << "\ninitial_state = \"velocity\"\n"
                      << "initial_velocity = [0.0, 0.0]\n";
  return LoadScene(path.string());
}

// A run of the rolling disc: its summary, the centre's acceleration along the slope
// [m/s^2] (least squares of x = x0 + v0 t + a t^2 / 2 after the first 20 ms: the contact
// force builds up from zero at the start, and with it the friction bound) and its last
// displacement along the slope [m].
struct RollingRun {
  DynamicSummary summary;
  double acceleration = 0.0, distance = 0.0;
};
RollingRun RunRollingDisc(const SceneModel& built) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  RollingRun run;
  DynamicOptions options = built.options;
  options.on_step = [&](const StepRecord& rec, const Eigen::VectorXd& u,
                        const ContactSystem::Result&, double) {
    run.distance = u(built.dofs.FreeIndex(0));  // the centre node's
    if (rec.time < 0.02) return;
    const Eigen::Vector3d basis(1.0, rec.time, rec.time * rec.time / 2.0);
    normal += basis * basis.transpose();
    right += basis * run.distance;
  };
  run.summary = RunDynamics(built.model, options);
  run.acceleration = normal.ldlt().solve(right)(2);
  return run;
}

const double kRollingExact = 2.0 / 3.0 * 9.81 * std::sin(20.0 * kPi / 180.0);  // [m/s^2]

TEST_CASE("finite strain: with the body normal the contact frames turn with the disc") {
  // The default normal source: the body normals of the deformed disc at its current
  // contact nodes (the nodes touching the floor change as it rolls).
  const Scene scene = RollingDisc("rolling_disc_body_normal", "", 0.12, "");
  const SceneModel built = BuildSceneModel(scene, Disc(6));
  const RollingRun run = RunRollingDisc(built);
  INFO(run.summary.message);
  REQUIRE(run.summary.status == DynamicStatus::kCompleted);
  CHECK(run.summary.kinematics == "finite");
  CHECK_THAT(run.acceleration, WithinRel(kRollingExact, 0.02));
  CHECK(run.distance / kRadius > 0.25);
}

TEST_CASE("finite strain: a disc rolls down a slope at 2/3 g sin(alpha), area kept") {
  const Scene scene = RollingDisc("rolling_disc", "", 0.12);
  const SceneModel built = BuildSceneModel(scene, Disc(6));
  const RollingRun run = RunRollingDisc(built);
  const DynamicSummary& s = run.summary;
  INFO(s.message);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  CHECK(s.kinematics == "finite");
  CHECK(s.finite_strain_from_step > 0);  // auto started small (the disc at rest)
  CHECK(s.material_model == "saint-venant-kirchhoff");
  INFO("finite strain from step "
       << s.finite_strain_from_step << ", energy balance error " << s.energy_balance_error
       << " J of " << s.records.back().external_work << " J external work");
  CHECK_THAT(run.acceleration, WithinRel(kRollingExact, 0.02));
  // It turned by x / R (about 0.3 rad), and kept its area to the elastic strain.
  CHECK(run.distance / kRadius > 0.25);
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

// A disc spinning freely at omega [rad/s] about its centre (no load; the floor 0.95 m
// below it is never reached), finite kinematics, plane strain.
Scene SpinningDisc(double end_time) {
  const fs::path dir = fs::temp_directory_path() / "contact_finite_strain_tests";
  fs::create_directories(dir);
  const fs::path path = dir / "spinning_disc.toml";
  std::ofstream(path) << "[geometry]\ntype = \"rectangle\"\nsize = [0.1, 0.1]\n"
                         "cells = [1, 1]\ncontact = [\"ymin\"]\n"
                         "[material]\nyoung_modulus = 2e7\npoisson_ratio = 0.3\n"
                         "density = 1000\nmass = \"lumped\"\nkinematics = \"finite\"\n"
                         "[obstacle]\ntype = \"plane\"\nnormal = [0.0, 1.0]\n"
                         "offset = -1.0\n"
                         "[time]\ndt = 1e-5\nend_time = "
                      << end_time << "\ninitial_state = \"velocity\"\n"
                      << "initial_velocity = [0.0, 0.0]\n";
  return LoadScene(path.string());
}

TEST_CASE("finite strain: a free spinning disc grows as the rotating disc, keeps L") {
  // Rotating solid disc, linear elasticity (Timoshenko & Goodier): in plane stress
  //   u_r(r) = (1 - nu) rho w^2 r [(3 + nu) R^2 - (1 + nu) r^2] / (8 E),
  //   u_r(R) = (1 - nu) rho w^2 R^3 / (4 E);
  // plane strain (eps_zz = 0) is plane stress with E' = E / (1 - nu^2), nu' = nu / (1 -
  // nu):
  //   u_r(R) = (1 + nu) (1 - 2 nu) rho w^2 R^3 / (4 E).
  // Started from u = 0 the rim oscillates about this steady growth (radial modes, period
  // about 1 ms): its time mean over many periods is the steady value.
  const double E = 2e7, nu = 0.3, rho = 1000.0,
               omega = 120.0;  // [Pa], [-], [kg/m^3], [rad/s]
  const double turns = 2.0, end_time = turns * 2.0 * kPi / omega;
  const Scene scene = SpinningDisc(end_time);
  const Mesh mesh = Disc(8);
  const SceneModel built = BuildSceneModel(scene, mesh);
  REQUIRE(built.dofs.NumConstrainedDofs() == 0);
  DynamicOptions options = built.options;
  const int n = mesh.NumNodes();
  options.u0 = Eigen::VectorXd::Zero(2 * n);
  options.v0.resize(2 * n);
  for (int i = 0; i < n; ++i)  // v = w e_z x X
    options.v0.segment<2>(2 * i) =
        omega * Eigen::Vector2d(-mesh.nodes(1, i), mesh.nodes(0, i));
  const Eigen::VectorXd mass = built.model.M.diagonal();  // lumped [kg]
  // L = sum_i m_i x_i x v_i with v^{k+1/2} = (u^{k+1} - u^k) / dt: central differences
  // keep it exactly when the internal force is objective (sum_i x_i^k x f_i^k = 0).
  const auto angular_momentum = [&](const Eigen::VectorXd& u0, const Eigen::VectorXd& u1,
                                    double dt) {
    double L = 0.0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d x = mesh.nodes.col(i) + u0.segment<2>(2 * i);
      const Eigen::Vector2d v = (u1 - u0).segment<2>(2 * i) / dt;
      L += mass(2 * i) * (x(0) * v(1) - x(1) * v(0));
    }
    return L;
  };
  double L0 = 0.0;
  for (int i = 0; i < n; ++i) L0 += mass(2 * i) * omega * mesh.nodes.col(i).squaredNorm();
  const int first_rim = n - 6 * 8;  // the outer ring's nodes are the last 6 * rings
  double growth_sum = 0.0, max_L_error = 0.0;
  long samples = 0;
  Eigen::VectorXd u_previous = options.u0;
  options.on_step = [&](const StepRecord&, const Eigen::VectorXd& u,
                        const ContactSystem::Result&, double) {
    max_L_error = std::max(
        max_L_error, std::abs(angular_momentum(u_previous, u, options.dt) - L0) / L0);
    u_previous = u;
    double rim = 0.0;  // the rim's mean radial growth |X + u| - |X| [m]
    for (int i = first_rim; i < n; ++i)
      rim += (mesh.nodes.col(i) + u.segment<2>(2 * i)).norm() - mesh.nodes.col(i).norm();
    growth_sum += rim / (n - first_rim);
    ++samples;
  };
  const DynamicSummary s = RunDynamics(built.model, options);
  INFO(s.message);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  const double exact =
      (1 + nu) * (1 - 2 * nu) * rho * omega * omega * std::pow(kRadius, 3) / (4 * E);
  CHECK_THAT(growth_sum / samples, WithinRel(exact, 0.05));
  // (u^0 = 0 carries no internal force: v^{1/2} = v^0, the first L is L0 exactly.)
  CHECK(max_L_error < 1e-9);
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
