// Several bodies in mortar contact: the contact patch test, a stack at rest, Coulomb
// friction on an incline and in a tilted stack, and two bars
// colliding, each against its closed form.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "contact/bodies.hpp"
#include "contact/bodies_contact.hpp"
#include "contact/bodies_scene.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/mortar.hpp"
#include "contact/scene.hpp"

namespace {

using contact::Body;
using contact::BoundaryRole;
using contact::DirichletCondition;
using contact::ElementType;
using contact::Side;

/// Adds the group `name` of the element edges whose nodes all lie on x = value.
void AddEdgeGroup(contact::Mesh* mesh, const std::string& name, double value) {
  const int corners = contact::NodesPerElement(mesh->element_type);
  std::vector<std::pair<int, int>> edges;
  const double tolerance = 1e-12 * (1.0 + std::abs(value));
  for (int e = 0; e < mesh->NumElements(); ++e)
    for (int i = 0; i < corners; ++i) {
      const int a = mesh->elements(i, e), b = mesh->elements((i + 1) % corners, e);
      if (std::abs(mesh->nodes(0, a) - value) < tolerance &&
          std::abs(mesh->nodes(0, b) - value) < tolerance)
        edges.emplace_back(a, b);
    }
  contact::BoundaryFacets facets;
  facets.connectivity.resize(2, static_cast<Eigen::Index>(edges.size()));
  for (size_t k = 0; k < edges.size(); ++k)
    facets.connectivity.col(static_cast<Eigen::Index>(k)) << edges[k].first,
        edges[k].second;
  mesh->boundary_groups[name] = facets;
}

contact::Mesh Rectangle(double x0, double y0, double width, double height, int nx, int ny,
                        ElementType type, std::map<Side, BoundaryRole> roles) {
  contact::RectangleMeshOptions options;
  options.origin = {x0, y0};
  options.size = {width, height};
  options.cells = {nx, ny};
  options.element_type = type;
  options.side_roles = std::move(roles);
  return contact::MakeRectangleMesh(options);
}

DirichletCondition Condition(const std::string& group, int component,
                             double value = 0.0) {
  DirichletCondition c;
  c.group = group;
  c.components = {component};
  c.displacement = [value](const Eigen::VectorXd&) {
    return Eigen::Vector2d(value, value).eval();
  };
  return c;
}

/// Plane strain with sigma_xx = 0: eps_yy = sigma_yy (1 - nu^2) / E.
double PlaneStrainCompliance(const contact::IsotropicMaterial& m) {
  return (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus;
}

}  // namespace

// Taylor-Papadopoulos: two blocks of different materials with non-matching meshes
// (quadrilaterals below, triangles above), pressed together by a prescribed shortening
// delta. The exact solution is uniaxial: sigma_yy = -p in both blocks, with
// delta = p sum_i H_i (1 - nu_i^2) / E_i, and the mortar pressure must be p at every
// slave node, with either block as the slave.
TEST_CASE("bodies: mortar contact patch test, non-matching meshes, both roles",
          "[bodies]") {
  const double width = 1.0, H1 = 0.5, H2 = 0.4, delta = 1e-4;
  const contact::IsotropicMaterial lower_material{70e9, 0.3, 2700.0};
  const contact::IsotropicMaterial upper_material{210e9, 0.25, 7800.0};
  contact::Mesh lower = Rectangle(
      0.0, 0.0, width, H1, 5, 2, ElementType::kQuadrilateral4,
      {{Side::kYMin, BoundaryRole::kFixed}, {Side::kYMax, BoundaryRole::kContact}});
  contact::Mesh upper = Rectangle(
      0.0, H1, width, H2, 3, 2, ElementType::kTriangle3,
      {{Side::kYMax, BoundaryRole::kLoad}, {Side::kYMin, BoundaryRole::kContact}});
  AddEdgeGroup(&lower, "symmetry", 0.0);
  AddEdgeGroup(&upper, "symmetry", 0.0);
  contact::PlaneSettings plane;
  plane.thickness = 0.01;
  std::vector<Body> bodies;
  bodies.push_back({"lower",
                    contact::ElasticBody(lower, lower_material, plane),
                    {Condition("fixed", 1), Condition("symmetry", 0)}});
  bodies.push_back({"upper",
                    contact::ElasticBody(upper, upper_material, plane),
                    {Condition("load", 1, -delta), Condition("symmetry", 0)}});
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  const double p = delta / (H1 * PlaneStrainCompliance(lower_material) +
                            H2 * PlaneStrainCompliance(upper_material));
  for (const bool upper_is_slave : {true, false}) {
    contact::MortarInterface in;
    in.slave_body = upper_is_slave ? 1 : 0;
    in.master_body = upper_is_slave ? 0 : 1;
    in.slave_group = in.master_group = "contact";
    const contact::MortarConstraints constraints =
        contact::AssembleMortar(bodies, system, {in});
    REQUIRE(constraints.NumConstraints() == (upper_is_slave ? 4 : 6));
    const contact::BodiesStaticResult result = contact::SolveBodiesStatic(
        system, constraints, contact::Vector::Zero(system.NumDofs()));
    INFO(result.message);
    REQUIRE(result.converged);
    for (int j = 0; j < constraints.NumConstraints(); ++j) {
      CHECK(std::abs(result.pressure(j) - p) <= 1e-10 * p);
      CHECK(std::abs(result.gap(j)) <= 1e-10 * delta);
    }
    // The whole field is the uniaxial one: u_y = eps_yy (y - y_i) + u_y(y_i),
    // u_x = -nu / (1 - nu) eps_yy x.
    const double eps1 = -p * PlaneStrainCompliance(lower_material);
    const double eps2 = -p * PlaneStrainCompliance(upper_material);
    for (int b = 0; b < 2; ++b) {
      const contact::Mesh& mesh = bodies[static_cast<size_t>(b)].body.mesh();
      const double nu = bodies[static_cast<size_t>(b)].body.material().poisson_ratio;
      const double eps = b == 0 ? eps1 : eps2;
      for (int node = 0; node < mesh.NumNodes(); ++node) {
        const double x = mesh.nodes(0, node), y = mesh.nodes(1, node);
        const double uy = b == 0 ? eps1 * y : eps1 * H1 + eps2 * (y - H1);
        const double ux = -nu / (1.0 - nu) * eps * x;
        CHECK(std::abs(result.u(system.GlobalDof(b, node, 0)) - ux) <= 1e-10 * delta);
        CHECK(std::abs(result.u(system.GlobalDof(b, node, 1)) - uy) <= 1e-10 * delta);
      }
    }
  }
}

// Two blocks stacked on a clamped floor block under gravity: each interface carries the
// weight of the blocks above it, rho g A h (equilibrium of the discrete bodies is exact).
TEST_CASE("bodies: a stack at rest carries the weights above each interface",
          "[bodies]") {
  const double g = 9.81;
  const contact::IsotropicMaterial steel{210e9, 0.3, 7800.0};
  const contact::IsotropicMaterial wood{12e9, 0.35, 600.0};
  contact::Mesh floor = Rectangle(
      0.0, 0.0, 1.0, 0.2, 4, 1, ElementType::kQuadrilateral4,
      {{Side::kYMin, BoundaryRole::kFixed}, {Side::kYMax, BoundaryRole::kContact}});
  contact::Mesh middle = Rectangle(
      0.0, 0.2, 1.0, 0.3, 5, 2, ElementType::kTriangle3,
      {{Side::kYMin, BoundaryRole::kContact}, {Side::kYMax, BoundaryRole::kLoad}});
  contact::Mesh top = Rectangle(0.1, 0.5, 0.6, 0.25, 4, 2, ElementType::kQuadrilateral4,
                                {{Side::kYMin, BoundaryRole::kContact}});
  AddEdgeGroup(&middle, "symmetry", 0.0);
  AddEdgeGroup(&top, "symmetry", 0.1);
  std::vector<Body> bodies;
  bodies.push_back({"floor", contact::ElasticBody(floor, steel), {}});
  bodies.back().dirichlet.emplace_back();  // "fixed", all components, 0
  bodies.push_back(
      {"middle", contact::ElasticBody(middle, steel), {Condition("symmetry", 0)}});
  bodies.push_back({"top", contact::ElasticBody(top, wood), {Condition("symmetry", 0)}});
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  contact::Vector f = contact::Vector::Zero(system.NumDofs());
  for (int b = 0; b < 3; ++b) {
    const contact::ElasticBody& body = bodies[static_cast<size_t>(b)].body;
    f.segment(system.offset[static_cast<size_t>(b)], body.NumDofs()) =
        body.BodyForceLoad(Eigen::Vector2d(0.0, -body.material().density * g));
  }
  contact::MortarInterface lower, upper;
  lower.slave_body = 1;
  lower.slave_group = "contact";
  lower.master_body = 0;
  lower.master_group = "contact";
  upper.slave_body = 2;
  upper.slave_group = "contact";
  upper.master_body = 1;
  upper.master_group = "load";
  const contact::MortarConstraints constraints =
      contact::AssembleMortar(bodies, system, {lower, upper});
  const contact::BodiesStaticResult result =
      contact::SolveBodiesStatic(system, constraints, f);
  INFO(result.message);
  REQUIRE(result.converged);
  const double weight_top = wood.density * g * 0.6 * 0.25;
  const double weight_middle = steel.density * g * 1.0 * 0.3;
  double lower_force = 0.0, upper_force = 0.0;
  for (int j = 0; j < constraints.NumConstraints(); ++j)
    (constraints.interface[static_cast<size_t>(j)] == 0 ? lower_force : upper_force) +=
        result.normal_force(j);
  CHECK(std::abs(upper_force - weight_top) <= 1e-9 * weight_top);
  CHECK(std::abs(lower_force - weight_top - weight_middle) <=
        1e-9 * (weight_top + weight_middle));
}

// Overlapping bodies and missing names are refused with the amount and the name.
TEST_CASE("bodies: overlap and missing groups are refused", "[bodies]") {
  const contact::IsotropicMaterial steel{210e9, 0.3, 7800.0};
  const contact::Mesh a =
      Rectangle(0.0, 0.0, 1.0, 0.5, 2, 1, ElementType::kQuadrilateral4,
                {{Side::kYMax, BoundaryRole::kContact}});
  const contact::Mesh b =
      Rectangle(0.0, 0.499, 1.0, 0.5, 3, 1, ElementType::kQuadrilateral4,
                {{Side::kYMin, BoundaryRole::kContact}});
  std::vector<Body> bodies;
  bodies.push_back({"a", contact::ElasticBody(a, steel), {}});
  bodies.push_back({"b", contact::ElasticBody(b, steel), {}});
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  contact::MortarInterface in;
  in.slave_body = 1;
  in.slave_group = "contact";
  in.master_body = 0;
  in.master_group = "contact";
  try {
    contact::AssembleMortar(bodies, system, {in});
    FAIL("overlap not refused");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.find("overlap by 0.001") != std::string::npos);
  }
  in.master_group = "top";
  try {
    contact::AssembleMortar(bodies, system, {in});
    FAIL("missing group not refused");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.find("'top'") != std::string::npos);
  }
  CHECK_THROWS_AS(contact::FindBody(bodies, "c"), std::invalid_argument);
}

// Two equal elastic bars (nu = 0: the 1D wave equation, c = sqrt(E / rho)) collide at
// speed v: by 1D wave theory the contact lasts 2 L / c and the bars exchange their
// velocities.
TEST_CASE("bodies: two equal bars colliding exchange velocities after 2L/c", "[bodies]") {
  const double L = 1.0, h = 0.05, gap = 1e-4, v = 1.0;
  const int cells = 200;
  const contact::IsotropicMaterial material{2e11, 0.0, 8000.0};
  const double c = std::sqrt(material.youngs_modulus / material.density);
  std::vector<Body> bodies;
  bodies.push_back({"left",
                    contact::ElasticBody(
                        Rectangle(0.0, 0.0, L, h, cells, 1, ElementType::kQuadrilateral4,
                                  {{Side::kXMax, BoundaryRole::kContact}}),
                        material),
                    {}});
  bodies.push_back(
      {"right",
       contact::ElasticBody(
           Rectangle(L + gap, 0.0, L, h, cells, 1, ElementType::kQuadrilateral4,
                     {{Side::kXMin, BoundaryRole::kContact}}),
           material),
       {}});
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  contact::MortarInterface in;
  in.slave_body = 0;
  in.slave_group = "contact";
  in.master_body = 1;
  in.master_group = "contact";
  const contact::MortarConstraints constraints =
      contact::AssembleMortar(bodies, system, {in});
  contact::Vector v0 = contact::Vector::Zero(system.NumDofs());
  for (int dof = 0; dof < system.offset[1]; dof += 2) v0(dof) = v;
  contact::BodiesDynamicOptions options;
  options.lumped_mass = true;
  options.time_step = 1.0 * (L / cells) / c;
  const double duration = 2.0 * L / c, closing = gap / v;
  options.steps = static_cast<int>((closing + 1.5 * duration) / options.time_step);
  const contact::BodiesDynamicSummary run = contact::RunBodiesDynamics(
      system, constraints, contact::Vector::Zero(system.NumDofs()),
      contact::Vector::Zero(system.NumDofs()), v0, options);
  INFO(run.message);
  REQUIRE(run.status == contact::BodiesDynamicStatus::kCompleted);
  int contact_steps = 0;
  for (const contact::BodiesStepRecord& r : run.records)
    if (r.interface_force[0] > 0.0) ++contact_steps;
  const double measured = contact_steps * options.time_step;
  INFO("contact duration " << measured << " s, 2L/c = " << duration << " s");
  CHECK(std::abs(measured - duration) <= 0.01 * duration);
  auto mean_velocity = [&](int b) {
    const contact::Vector part = system.BodyPart(run.velocity, b);
    const contact::Vector m = system.BodyPart(system.lumped_mass, b);
    double momentum = 0.0, mass = 0.0;
    for (int dof = 0; dof < part.size(); dof += 2) {
      momentum += m(dof) * part(dof);
      mass += m(dof);
    }
    return momentum / mass;
  };
  // Momentum is conserved exactly (the mortar forces on the two sides balance); the
  // velocities are exchanged up to the energy left in the bars' vibrations.
  const double before = run.records.front().energy, after = run.records.back().energy;
  INFO("velocities after: " << mean_velocity(0) << ", " << mean_velocity(1)
                            << "; energy after / before " << after / before);
  std::printf(
      "colliding bars: contact %.6e s (2L/c %.6e s), velocities after %.3e %.6f, "
      "energy after / before %.12f\n",
      measured, duration, mean_velocity(0), mean_velocity(1), after / before);
  CHECK(std::abs(mean_velocity(0) + mean_velocity(1) - v) <= 1e-12 * v);
  CHECK(std::abs(mean_velocity(0)) <= 0.01 * v);
  CHECK(std::abs(mean_velocity(1) - v) <= 0.01 * v);
  // The scheme's known dissipation: the contact faces' nodes (a fraction 1 / (2 cells) of
  // each bar's lumped mass) meet in a plastic impact, losing their kinetic energy
  // 1 / (4 cells) of the total; measured to 1e-9.
  CHECK(std::abs(after / before - (1.0 - 0.25 / cells)) <= 1e-6);
}

namespace {

/// The mesh mirrored in y -> -y, element and facet orders reversed to keep them
/// positively oriented.
contact::Mesh MirrorY(contact::Mesh mesh) {
  mesh.nodes.row(1) *= -1.0;
  for (int e = 0; e < mesh.NumElements(); ++e)
    std::swap(mesh.elements(1, e), mesh.elements(2, e));
  for (auto& [name, facets] : mesh.boundary_groups)
    facets.connectivity.row(0).swap(facets.connectivity.row(1));
  return mesh;
}

}  // namespace

// Hertz, two cylinders (Johnson, Contact Mechanics, 1985, eq. 4.43-4.45), plane strain:
// radii R1, R2 and materials (E_i, nu_i) pressed by P per unit length touch over the
// half-width a = sqrt(4 P R / (pi E*)) with peak pressure p0 = 2 P / (pi a),
// 1 / R = 1 / R1 + 1 / R2, 1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2. Half models
// x >= 0 (u_x = 0 on x = 0) of the upper quarter disk (steel, R1, its cut y = R1 moved
// down by delta) and the lower one (aluminium, R2, clamped on its cut), different element
// sizes at the contact (a / 20 and a / 14). P is measured (twice the vertical contact
// force of the half model) and delta chosen to give a of about 0.02 R1, where the
// parabolic gap and the half-space of the theory hold to 1e-4 (see the one-body Hertz
// test in test_static_contact.cpp). Displacement-driven: both bodies are held, so every
// Newton system is regular from the start.
TEST_CASE("bodies: Hertz contact of two cylinders, half-width and peak pressure",
          "[bodies][hertz]") {
  const double R1 = 0.05, R2 = 0.08, delta = 8.19e-5;
  const contact::IsotropicMaterial steel{210e9, 0.3, 7800.0};
  const contact::IsotropicMaterial aluminium{70e9, 0.33, 2700.0};
  const double R = 1.0 / (1.0 / R1 + 1.0 / R2);
  const double E_star =
      1.0 / (PlaneStrainCompliance(steel) + PlaneStrainCompliance(aluminium));
  const double a_nominal = 0.02 * R1;
  auto disk = [&](double radius, double h) {
    contact::QuarterDiskMeshOptions o;
    o.radius = radius;
    o.contact_size = h;
    o.refined_radius = 1.5 * a_nominal;
    o.contact_extent = 3.0 * a_nominal;
    o.max_size = radius / 8.0;
    return contact::MakeQuarterDiskMesh(o);
  };
  std::vector<Body> bodies;
  bodies.push_back({"upper",
                    contact::ElasticBody(disk(R1, a_nominal / 20.0), steel),
                    {Condition("fixed", 0), Condition("load", 1, -delta)}});
  bodies.push_back({"lower",
                    contact::ElasticBody(MirrorY(disk(R2, a_nominal / 14.0)), aluminium),
                    {Condition("fixed", 0), Condition("load", 0), Condition("load", 1)}});
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  contact::MortarInterface in;
  in.slave_body = 0;
  in.master_body = 1;
  in.slave_group = in.master_group = "contact";
  const contact::MortarConstraints constraints =
      contact::AssembleMortar(bodies, system, {in});
  const contact::BodiesStaticResult result = contact::SolveBodiesStatic(
      system, constraints, contact::Vector::Zero(system.NumDofs()));
  INFO(result.message);
  REQUIRE(result.converged);
  CHECK(result.newton_iterations <= 30);
  double vertical = 0.0;  // sum_j lambda_j n_j,y = -P / 2
  for (int j = 0; j < constraints.NumConstraints(); ++j)
    vertical += result.normal_force(j) * constraints.normals(1, j);
  const double P = -2.0 * vertical;
  const double a = std::sqrt(4.0 * P * R / (M_PI * E_star));
  const double p0 = 2.0 * P / (M_PI * a);
  // Pressure profile by slave node position; p^2 = p0^2 (1 - x^2 / a^2) is linear in x^2:
  // a from the line through the last two loaded nodes.
  std::vector<std::pair<double, double>> profile;  // (x, p)
  for (int j = 0; j < constraints.NumConstraints(); ++j)
    profile.emplace_back(
        bodies[0].body.mesh().nodes(0, constraints.slave_node[static_cast<size_t>(j)]),
        result.pressure(j));
  std::sort(profile.begin(), profile.end());
  size_t last = 0;
  const double threshold = 1e-9 * p0;
  while (last + 1 < profile.size() && profile[last + 1].second > threshold) ++last;
  REQUIRE(last >= 3);
  const auto [x1, p1] = profile[last - 1];
  const auto [x2, p2] = profile[last];
  const double a_measured =
      std::sqrt(x2 * x2 + p2 * p2 * (x2 * x2 - x1 * x1) / (p1 * p1 - p2 * p2));
  const double p0_measured = profile.front().second;
  INFO("a = " << a_measured << " m (Hertz " << a << "), p0 = " << p0_measured
              << " Pa (Hertz " << p0 << "), loaded nodes " << last + 1);
  CHECK(profile.front().first == 0.0);
  CHECK(std::abs(a / a_nominal - 1.0) <= 0.05);
  CHECK(std::abs(a_measured - a) <= 0.02 * a);
  CHECK(std::abs(p0_measured - p0) <= 0.02 * p0);
  std::printf(
      "two-cylinder Hertz: a / R1 = %.4f, a error %.3e, p0 error %.3e, %d loaded nodes, "
      "%d "
      "dofs, %d Newton iterations\n",
      a / R1, a_measured / a - 1.0, p0_measured / p0 - 1.0, static_cast<int>(last + 1),
      system.NumDofs(), result.newton_iterations);
}

// The example scenes with several bodies against their closed forms: the stack's weights
// per interface, the bars' exchange of velocities (contact force back to 0 after 2L/c).
TEST_CASE("bodies: example scenes reproduce their closed forms", "[bodies][scene]") {
  const std::string dir = std::string(NCP_SOURCE_DIR) + "/examples/bodies/";
  const contact::BodiesSceneSummary stack =
      contact::RunBodiesScene(dir + "stack_2d.toml", std::string());
  INFO(stack.message);
  REQUIRE(stack.status == "completed");
  REQUIRE(stack.pair_force.size() == 2);
  const double top = 600.0 * 9.81 * 0.6 * 0.25, middle = 7800.0 * 9.81 * 0.3;
  CHECK(std::abs(stack.pair_force[1] - top) <= 1e-6 * top);
  CHECK(std::abs(stack.pair_force[0] - top - middle) <= 1e-6 * (top + middle));
  // Output: one .vtu per body in one ParaView collection, one part per body.
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / "bodies_stack_output";
  std::filesystem::remove_all(out);
  contact::RunBodiesScene(dir + "stack_2d.toml", out.string());
  for (const char* file : {"floor_0.vtu", "middle_0.vtu", "top_0.vtu", "pairs.csv"})
    CHECK(std::filesystem::exists(out / file));
  std::ifstream pvd(out / "solution.pvd");
  const std::string collection((std::istreambuf_iterator<char>(pvd)),
                               std::istreambuf_iterator<char>());
  CHECK(collection.find("part=\"2\" file=\"top_0.vtu\"") != std::string::npos);
  std::filesystem::remove_all(out);
  const contact::BodiesSceneSummary blocks =
      contact::RunBodiesScene(dir + "two_blocks_2d.toml", std::string());
  REQUIRE(blocks.status == "completed");
  // p = delta / (H1 / E1 + H2 / E2) over the width 1 m and thickness 1 m.
  const double p = 1e-4 / (0.5 / 70e9 + 0.4 / 210e9);
  CHECK(std::abs(blocks.pair_force[0] - p) <= 1e-9 * p);
}

// Unsupported or inconsistent scene input is refused naming the key (or the body).
TEST_CASE("bodies: scene refusals name the key", "[bodies][scene]") {
  const std::string base = std::string(NCP_SOURCE_DIR) + "/examples/bodies/";
  std::ifstream in(base + "stack_2d.toml");
  const std::string stack((std::istreambuf_iterator<char>(in)),
                          std::istreambuf_iterator<char>());
  const std::string path =
      (std::filesystem::temp_directory_path() / "bodies_refusal.toml").string();
  auto refusal = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      contact::RunBodiesScene(path, std::string());
    } catch (const contact::SceneError& e) {
      return std::string(e.what());
    }
    return std::string("not refused");
  };
  const std::string friction =
      refusal(stack +
              "\n[[contact]]\nslave_body = \"top\"\nmaster_body = "
              "\"floor\"\nfriction = -0.3\n");
  CHECK(friction.find("'contact[2].friction'") != std::string::npos);
  const std::string missing =
      refusal(stack + "\n[[contact]]\nslave_body = \"lid\"\nmaster_body = \"floor\"\n");
  CHECK(missing.find("'contact[2].slave_body'") != std::string::npos);
  CHECK(missing.find("'lid'") != std::string::npos);
  CHECK_THROWS_AS(contact::LoadScene(base + "stack_2d.toml"), contact::SceneError);
  std::filesystem::remove(path);
}

namespace {

/// A stack of `blocks` steel blocks (0.4 x 0.2 m each, nu = 0, non-matching meshes) on a
/// clamped steel floor, under gravity g tilted by theta: body force rho g (sin theta,
/// -cos theta), the floor's frame being the incline's. Friction mu at every interface.
/// Starts at rest from the static frictionless equilibrium under the normal part of
/// gravity (the blocks held along x at one edge for that solve only). Returns per block
/// its centre-of-mass velocity along x after `steps` steps (from its momentum: lumped
/// masses times velocities), and per interface the means over the steps of the normal
/// and friction forces [N/m].
struct TiltedStack {
  double time = 0.0;
  std::vector<double> velocity, mass, normal, friction;
};

TiltedStack RunTiltedStack(int blocks, double mu, double g, double theta, int steps) {
  const contact::IsotropicMaterial steel{210e9, 0.0, 7800.0};
  std::vector<Body> bodies;
  bodies.push_back({"floor",
                    contact::ElasticBody(
                        Rectangle(0.0, 0.0, 1.0, 0.2, 5, 1, ElementType::kQuadrilateral4,
                                  {{Side::kYMin, BoundaryRole::kFixed},
                                   {Side::kYMax, BoundaryRole::kContact}}),
                        steel),
                    {}});
  bodies.back().dirichlet.emplace_back();
  std::vector<contact::MortarInterface> pairs;
  for (int i = 0; i < blocks; ++i) {
    contact::Mesh block = Rectangle(
        0.3, 0.2 * (i + 1), 0.4, 0.2, 3 + i % 2, 2, ElementType::kQuadrilateral4,
        {{Side::kYMin, BoundaryRole::kContact}, {Side::kYMax, BoundaryRole::kLoad}});
    AddEdgeGroup(&block, "left", 0.3);
    bodies.push_back({"block " + std::to_string(i),
                      contact::ElasticBody(block, steel),
                      {Condition("left", 0)}});
    contact::MortarInterface pair;
    pair.slave_body = i + 1;
    pair.slave_group = "contact";
    pair.master_body = i;
    pair.master_group = i == 0 ? "contact" : "load";
    pairs.push_back(pair);
  }
  auto load = [&](const contact::BodySystem& system, double along) {
    contact::Vector f = contact::Vector::Zero(system.NumDofs());
    for (int b = 1; b <= blocks; ++b) {
      const contact::ElasticBody& body = bodies[static_cast<size_t>(b)].body;
      const double rho = body.material().density;
      f.segment(system.offset[static_cast<size_t>(b)], body.NumDofs()) =
          body.BodyForceLoad(rho * g * Eigen::Vector2d(along, -std::cos(theta)));
    }
    return f;
  };
  const contact::BodySystem held = contact::AssembleBodies(bodies);
  const contact::BodiesStaticResult rest = contact::SolveBodiesStatic(
      held, contact::AssembleMortar(bodies, held, pairs), load(held, 0.0));
  REQUIRE(rest.converged);
  for (int b = 1; b <= blocks; ++b) bodies[static_cast<size_t>(b)].dirichlet.clear();
  for (auto& pair : pairs) pair.friction = mu;
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  const contact::MortarConstraints constraints =
      contact::AssembleMortar(bodies, system, pairs);
  contact::BodiesDynamicOptions options;
  options.time_step = 0.5 * 0.2 / 5189.0;  // half of h / c
  options.steps = steps;
  options.lumped_mass = true;
  const contact::BodiesDynamicSummary run = contact::RunBodiesDynamics(
      system, constraints, load(system, std::sin(theta)), rest.u,
      contact::Vector::Zero(system.NumDofs()), options);
  INFO(run.message);
  REQUIRE(run.status == contact::BodiesDynamicStatus::kCompleted);
  TiltedStack out;
  out.time = steps * options.time_step;
  for (int b = 1; b <= blocks; ++b) {
    double momentum = 0.0, mass = 0.0;
    for (int i = system.offset[static_cast<size_t>(b)];
         i < system.offset[static_cast<size_t>(b) + 1]; i += 2) {
      momentum += system.lumped_mass(i) * run.velocity(i);
      mass += system.lumped_mass(i);
    }
    out.velocity.push_back(momentum / mass);
    out.mass.push_back(mass);
  }
  out.normal.assign(static_cast<size_t>(blocks), 0.0);
  out.friction.assign(static_cast<size_t>(blocks), 0.0);
  for (const auto& r : run.records)
    for (size_t p = 0; p < out.normal.size(); ++p) {
      out.normal[p] += r.interface_force[p] / steps;
      out.friction[p] += r.interface_tangential_force[p] / steps;
    }
  return out;
}

}  // namespace

// Coulomb friction between two bodies: a block on an incline of angle theta. Above its
// angle (tan theta > mu) it slides with a = g (sin theta - mu cos theta), the friction
// force being mu N, N = m g cos theta; below it sticks: no momentum gained along the
// incline.
TEST_CASE("bodies: a block on an incline slides above its angle at the closed form",
          "[bodies][friction]") {
  const double mu = 0.3, g = 9.81;
  const int steps = 1500;
  const double steep = std::atan(2.0 * mu), gentle = std::atan(0.5 * mu);
  const TiltedStack slides = RunTiltedStack(1, mu, g, steep, steps);
  const double a = g * (std::sin(steep) - mu * std::cos(steep));
  const double weight = slides.mass[0] * g;
  INFO("slides: v = " << slides.velocity[0] << " m/s, expected " << a * slides.time
                      << ", N = " << slides.normal[0] << ", friction "
                      << slides.friction[0] << ", m g = " << weight);
  CHECK(std::abs(slides.velocity[0] - a * slides.time) <= 0.02 * a * slides.time);
  CHECK(std::abs(slides.normal[0] - weight * std::cos(steep)) <= 0.02 * weight);
  CHECK(std::abs(std::abs(slides.friction[0]) - mu * slides.normal[0]) <=
        2e-3 * slides.normal[0]);  // the first steps stick
  const TiltedStack sticks = RunTiltedStack(1, mu, g, gentle, steps);
  const double free_flight = g * std::sin(gentle) * sticks.time;  // frictionless
  INFO("sticks: v = " << sticks.velocity[0] << " m/s against " << free_flight
                      << " frictionless; friction " << sticks.friction[0]);
  CHECK(std::abs(sticks.velocity[0]) <= 0.01 * free_flight);
}

// A stack of three blocks on an incline below its angle (tan theta = mu / 2): friction
// holds every block (no momentum gained), and each interface carries the weight above
// it, m_above g (sin theta, cos theta) along and across the incline, on average.
TEST_CASE("bodies: friction holds a tilted stack below its angle", "[bodies][friction]") {
  const double mu = 0.4, g = 9.81, theta = std::atan(0.5 * mu);
  const TiltedStack stack = RunTiltedStack(3, mu, g, theta, 1500);
  const double free_flight = g * std::sin(theta) * stack.time;
  double above = 0.0;
  for (int i = 2; i >= 0; --i) {
    const size_t b = static_cast<size_t>(i);
    above += stack.mass[b];
    INFO("block " << i << ": v = " << stack.velocity[b] << " m/s, N = " << stack.normal[b]
                  << ", friction " << stack.friction[b]);
    CHECK(std::abs(stack.velocity[b]) <= 0.01 * free_flight);
    CHECK(std::abs(stack.normal[b] - above * g * std::cos(theta)) <= 0.02 * above * g);
    CHECK(std::abs(std::abs(stack.friction[b]) - above * g * std::sin(theta)) <=
          0.05 * above * g * std::sin(theta));
  }
}

// A static solve with friction condenses on the bodies (Delassus form): a body held only
// by contact has a singular stiffness and is refused with the reason.
TEST_CASE("bodies: static friction with a body held only by contact is refused",
          "[bodies][friction]") {
  const contact::IsotropicMaterial steel{210e9, 0.3, 7800.0};
  std::vector<Body> bodies;
  bodies.push_back({"floor",
                    contact::ElasticBody(
                        Rectangle(0.0, 0.0, 1.0, 0.2, 4, 1, ElementType::kQuadrilateral4,
                                  {{Side::kYMin, BoundaryRole::kFixed},
                                   {Side::kYMax, BoundaryRole::kContact}}),
                        steel),
                    {}});
  bodies.back().dirichlet.emplace_back();
  bodies.push_back({"block",
                    contact::ElasticBody(
                        Rectangle(0.2, 0.2, 0.4, 0.2, 3, 2, ElementType::kQuadrilateral4,
                                  {{Side::kYMin, BoundaryRole::kContact}}),
                        steel),
                    {}});
  contact::MortarInterface pair;
  pair.slave_body = 1;
  pair.slave_group = "contact";
  pair.master_body = 0;
  pair.master_group = "contact";
  pair.friction = 0.3;
  const contact::BodySystem system = contact::AssembleBodies(bodies);
  const contact::MortarConstraints constraints =
      contact::AssembleMortar(bodies, system, {pair});
  CHECK_THROWS_WITH(contact::SolveBodiesStatic(system, constraints,
                                               contact::Vector::Zero(system.NumDofs())),
                    Catch::Contains("Dirichlet"));
  pair.friction = -0.1;
  CHECK_THROWS_WITH(contact::AssembleMortar(bodies, system, {pair}),
                    Catch::Contains("friction"));
}
