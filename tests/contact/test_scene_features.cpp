// Scene features against closed forms: Rayleigh damping (logarithmic decrement, damped
// critical step, energy balance), a punch pressed then slid by obstacle.motion (friction
// force mu N), a mesh's own group names (geometry.groups) and a prescribed displacement
// of the fixed group (geometry.fixed_displacement).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "contact/dynamics.hpp"
#include "contact/scene.hpp"
#include "contact/simulation.hpp"
#include "scene/scene_load.hpp"  // (internal: SerialOnlySceneFeature)

using namespace contact;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string WriteFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "contact_scene_feature_tests";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// Two uncoupled oscillators (stiffness k and k/4 [N/m], mass m [kg]) without contact,
// the stiffer one released from u0 = 1 mm.
DynamicModel Oscillator(double k, double m, RayleighDamping damping) {
  DynamicModel model;
  model.dim = 2;
  model.K.resize(2, 2);
  model.M.resize(2, 2);
  for (int i = 0; i < 2; ++i)
    model.K.insert(i, i) = i == 0 ? k : k / 4, model.M.insert(i, i) = m;
  model.load = [](double, Eigen::VectorXd* f) { f->setZero(); };
  model.damping = damping;
  return model;
}

DynamicOptions Released(double dt, double end_time) {
  DynamicOptions o;
  o.dt = dt;
  o.end_time = end_time;
  o.step_method = StepMethod::kExplicit;
  o.initial_state = InitialState::kPrescribed;
  o.u0 = Eigen::Vector2d(1e-3, 0.0);
  o.v0 = Eigen::Vector2d::Zero();
  return o;
}

// ln(A_i / A_{i+1}) of successive maxima of u_x, each maximum refined by the parabola
// through the sample and its neighbours.
std::vector<double> LogDecrements(const std::vector<double>& u) {
  std::vector<double> peaks;
  for (size_t i = 1; i + 1 < u.size(); ++i)
    if (u[i] > u[i - 1] && u[i] >= u[i + 1] && u[i] > 0) {
      const double a = 0.5 * (u[i - 1] - 2 * u[i] + u[i + 1]),
                   b = 0.5 * (u[i + 1] - u[i - 1]);
      peaks.push_back(u[i] - b * b / (4 * a));
    }
  std::vector<double> d;
  for (size_t i = 0; i + 1 < peaks.size(); ++i)
    d.push_back(std::log(peaks[i] / peaks[i + 1]));
  return d;
}

std::vector<double> TrajectoryX(const DynamicModel& model, DynamicOptions options,
                                DynamicSummary* summary) {
  std::vector<double> u{options.u0(0)};
  options.on_step = [&u](const StepRecord&, const Eigen::VectorXd& x,
                         const ContactSystem::Result&, double) { u.push_back(x(0)); };
  *summary = RunDynamics(model, options);
  return u;
}

}  // namespace

TEST_CASE("Rayleigh damping: logarithmic decrement 2 pi xi / sqrt(1 - xi^2)",
          "[scene-features][damping]") {
  const double k = 4e4, m = 1.0, omega = std::sqrt(k / m);  // 200 rad/s
  const double dt = 2e-5, period = 2 * kPi / omega;
  for (const auto& [damping, xi] :
       {std::pair{RayleighDamping{2 * 0.02 * omega, 0.0}, 0.02},  // mass: a = 2 xi omega
        std::pair{RayleighDamping{0.0, 2 * 0.05 / omega}, 0.05}}) {  // stiffness: b
    DynamicSummary s;
    const std::vector<double> u =
        TrajectoryX(Oscillator(k, m, damping), Released(dt, 6 * period), &s);
    REQUIRE(s.status == DynamicStatus::kCompleted);
    const double expected = 2 * kPi * xi / std::sqrt(1 - xi * xi);
    const std::vector<double> d = LogDecrements(u);
    REQUIRE(d.size() >= 4);
    for (double di : d) CHECK_THAT(di, Catch::Matchers::WithinRel(expected, 5e-4));
    // The energy balance holds with the dissipation D (the undamped column stays 0),
    // and D is the energy lost: 1/2 k u0^2 - (kinetic + strain).
    const StepRecord& last = s.records.back();
    CHECK(std::abs(s.energy_balance_error) < 1e-9 * 0.5 * k * 1e-6);
    CHECK(last.friction_dissipation == 0.0);
    CHECK_THAT(
        last.damping_dissipation,
        Catch::Matchers::WithinRel(0.5 * k * 1e-6 - last.kinetic - last.strain, 1e-3));
    CHECK(last.damping_dissipation > 0.5 * 0.5 * k * 1e-6);  // most of it after 6 periods
  }
}

TEST_CASE("Rayleigh damping: the damped critical step (2/omega)(sqrt(1 + xi^2) - xi)",
          "[scene-features][damping]") {
  const double k = 4e4, m = 1.0, omega = 200.0, xi = 0.5;
  const RayleighDamping damping{2 * xi * omega, 0.0};
  const double dt_crit = (2 / omega) * (std::sqrt(1 + xi * xi) - xi);  // 6.18e-3 s
  DynamicSummary below =
      RunDynamics(Oscillator(k, m, damping), Released(0.99 * dt_crit, 0.1));
  CHECK(below.status == DynamicStatus::kCompleted);
  CHECK_THAT(below.critical_time_step, Catch::Matchers::WithinRel(dt_crit, 1e-6));
  DynamicSummary above =
      RunDynamics(Oscillator(k, m, damping), Released(1.01 * dt_crit, 0.1));
  CHECK(above.status == DynamicStatus::kRefusedUnstable);
  CHECK_THAT(above.message, Catch::Contains("material.damping"));
  // Undamped 2/omega would accept 1.01 dt_crit: the damped limit is the one that holds.
  DynamicOptions unstable = Released(1.01 * dt_crit, 10.0);
  unstable.allow_unstable_time_step = true;
  CHECK(RunDynamics(Oscillator(k, m, damping), unstable).status ==
        DynamicStatus::kEnergyBlowUp);
}

namespace {

// A block 1 m x 0.2 m on a clamped base, pressed by a rigid flat punch from above (plane
// strain, nu = 0, lumped mass, mass damping): the punch goes 1 mm down by t = 0.02 s,
// then 10 mm sideways by t = 0.06 s.
std::string PunchScene(const std::string& step, const std::string& extra = "") {
  return "[geometry]\ntype = \"rectangle\"\nsize = [1.0, 0.2]\ncells = [10, 2]\n"
         "fixed = [\"ymin\"]\ncontact = [\"ymax\"]\n"
         "[material]\nyoung_modulus = 2e8\npoisson_ratio = 0.0\ndensity = 7800\n"
         "mass = \"lumped\"\ndamping = {mass = 500.0}\n"
         "[obstacle]\ntype = \"plane\"\nnormal = [0.0, -1.0]\noffset = -0.2\n"
         "normal_source = \"obstacle\"\n"
         "motion = {time = [0.0, 0.02, 0.06], x = [0.0, 0.0, 0.01], y = [0.0, -1e-3, "
         "-1e-3]}\n"
         "[friction]\ncoefficient = 0.3\n"
         "[time]\ndt = 5e-5\nend_time = 0.06\n"
         "[solver]\nstep = \"" +
         step + "\"\n" + extra;
}

}  // namespace

TEST_CASE("obstacle.motion: a punch pressed then slid pulls mu times its normal force",
          "[scene-features][motion]") {
  const Scene scene = LoadScene(WriteFile("punch.toml", PunchScene("explicit")));
  Simulation sim(scene);
  double pressed_normal = 0.0, pressed_friction = 0.0;
  while (sim.state() == SimulationState::kRunning) {
    sim.Step(1);
    if (sim.step_index() == 400) {  // t = 0.02 s: pressed, not yet slid
      pressed_normal = sim.records().back().normal_force_sum;
      pressed_friction = sim.records().back().tangent_force_sum;
    }
  }
  REQUIRE(sim.summary().status == DynamicStatus::kCompleted);
  CHECK(sim.obstacle_translation().isApprox(Eigen::Vector2d(0.01, -1e-3)));
  // Pressing: 1 mm into 0.2 m of the block, uniaxial (nu = 0): N = E (delta / h) * 1 m
  // * 1 m = 1e6 N (to the few per cent the ramp's vibration leaves at t = 0.02 s).
  CHECK_THAT(pressed_normal, Catch::Matchers::WithinRel(1e6, 0.03));
  CHECK(pressed_friction < 1e-3 * pressed_normal);
  // Sliding: every contact node slips, |tau_c| = mu lambda_c (lagged by one step).
  const StepRecord& last = sim.records().back();
  CHECK_THAT(last.tangent_force_sum,
             Catch::Matchers::WithinRel(0.3 * last.normal_force_sum, 1e-5));
  CHECK_THAT(last.normal_force_sum, Catch::Matchers::WithinRel(1e6, 1e-3));  // settled
  CHECK(std::abs(sim.summary().energy_balance_error) < 1e-6 * last.strain);
}

TEST_CASE("The damped, moving punch resumes from a checkpoint bit for bit; steps.csv",
          "[scene-features][checkpoint]") {
  const Scene scene = LoadScene(WriteFile("punch_resume.toml", PunchScene("explicit")));
  const std::string path = WriteFile("punch.ckpt", "");
  Simulation whole(scene);
  whole.Step(600);  // while sliding
  whole.SaveCheckpoint(path);
  whole.Step(1 << 20);
  REQUIRE(whole.state() == SimulationState::kFinished);
  const std::unique_ptr<Simulation> resumed = Simulation::Load(path, scene);
  CHECK(resumed->step_index() == 600);
  resumed->Step(1 << 20);
  const StepRecord &a = whole.records().back(), &b = resumed->records().back();
  CHECK(a.damping_dissipation > 0.0);
  CHECK(b.damping_dissipation == a.damping_dissipation);
  CHECK(b.energy_balance_error == a.energy_balance_error);
  CHECK(resumed->displacement() == whole.displacement());

  // steps.csv ends with the damping_dissipation column.
  Scene written = scene;
  written.output_directory =
      (fs::temp_directory_path() / "contact_punch_output").string();
  written.dynamics.end_time = 0.005;
  const SceneResult run = RunScene(written, false);
  REQUIRE(run.summary.status == DynamicStatus::kCompleted);
  std::ifstream csv(fs::path(written.output_directory) / "steps.csv");
  std::string header, row, last;
  std::getline(csv, header);
  while (std::getline(csv, row)) last = row;
  CHECK(header.substr(header.rfind(',') + 1) == "damping_dissipation");
  CHECK_THAT(
      std::stod(last.substr(last.rfind(',') + 1)),
      Catch::Matchers::WithinRel(run.summary.records.back().damping_dissipation, 1e-5));
}

TEST_CASE("obstacle.motion with friction is refused for steps that take the body's slip",
          "[scene-features][motion]") {
  const std::string path = WriteFile("punch_condensed.toml",
                                     PunchScene("condensed", "ncp_function = \"fb\"\n"));
  CHECK_THROWS_WITH(LoadScene(path), Catch::Contains("obstacle.motion") &&
                                         Catch::Contains("solver.step = \"explicit\""));
  const std::string moved = WriteFile(
      "punch_start.toml",
      "[geometry]\ntype = \"rectangle\"\nsize = [1.0, 0.2]\ncells = [2, 1]\n"
      "contact = [\"ymin\"]\n[material]\nyoung_modulus = 2e8\npoisson_ratio = 0.3\n"
      "density = 7800\n[obstacle]\ntype = \"plane\"\nnormal = [0.0, 1.0]\noffset = 0.0\n"
      "motion = {time = [0.0, 1.0], x = [0.1, 0.1], y = [0.0, 0.0]}\n"
      "[time]\ndt = 1e-4\nend_time = 1e-3\n");
  CHECK_THROWS_WITH(LoadScene(moved), Catch::Contains("'obstacle.motion' must start"));
}

namespace {

// A gmsh mesh of a block 1 m x 0.2 m (tests/contact/data/named_groups.geo) whose groups
// carry the mesher's names: "Base line" (y = 0), "Clamp" (y = 0.2 m), "Right side".
std::string NamedSquareScene(const std::string& groups) {
  return "[geometry]\ntype = \"msh\"\nfile = \"" NCP_SOURCE_DIR
         "/tests/contact/data/named_groups.msh\"\ndimension = 2\n" +
         groups +
         "[material]\nyoung_modulus = 2e8\npoisson_ratio = 0.3\ndensity = 7800\n"
         "[obstacle]\ntype = \"plane\"\nnormal = [0.0, 1.0]\noffset = -1e-3\n"
         "[time]\ndt = 1e-5\nend_time = 1e-4\n";
}

}  // namespace

TEST_CASE("geometry.groups maps a mesh's own group names onto fixed, load and contact",
          "[scene-features][groups]") {
  const Scene scene = LoadScene(WriteFile(
      "named.toml", NamedSquareScene("groups = {contact = \"Base line\", fixed = "
                                     "[\"Clamp\"], load = [\"Right side\"]}\n")));
  const SceneModel built = BuildSceneModel(scene);
  const Mesh& mesh = built.body->mesh();
  REQUIRE(mesh.HasBoundaryGroup(kContactGroup));
  const std::vector<int> base = mesh.BoundaryGroup("Base line").Nodes();
  CHECK(mesh.BoundaryGroup(kContactGroup).Nodes() == base);
  CHECK(mesh.BoundaryGroup(kLoadGroup).Nodes() ==
        mesh.BoundaryGroup("Right side").Nodes());
  CHECK(mesh.BoundaryGroup(kFixedGroup).Nodes() == mesh.BoundaryGroup("Clamp").Nodes());
  // Every component of the clamp's nodes is fixed; every node of the base line (y = 0)
  // is a contact node.
  CHECK(built.dofs.NumConstrainedDofs() ==
        2 * static_cast<int>(mesh.BoundaryGroup("Clamp").Nodes().size()));
  REQUIRE(base.size() >= 11);  // (h = 0.1 m on 1 m)
  REQUIRE(built.frames.nodes.size() == base.size());
  for (const ContactNode& node : built.frames.nodes)
    CHECK(mesh.nodes(1, node.node) == 0.0);
  // Without the mapping the mesh has no "contact" group; a name it lacks is refused with
  // the names it has.
  CHECK_THROWS(
      BuildSceneModel(LoadScene(WriteFile("unnamed.toml", NamedSquareScene("")))));
  CHECK_THROWS_WITH(
      BuildSceneModel(LoadScene(WriteFile(
          "misnamed.toml", NamedSquareScene("groups = {contact = \"base\"}\n")))),
      Catch::Contains("'geometry.groups.contact' names \"base\"") &&
          Catch::Contains("\"Base line\", \"Clamp\", \"Right side\""));
}

TEST_CASE("geometry.fixed_displacement: a block pressed by its top, N = E A delta / h",
          "[scene-features][fixed]") {
  // A block 1 m x 0.2 m (plane stress, nu = 0, thickness 1 m) on a floor y >= 0, its
  // top ("fixed") lowered by delta = 0.1 mm over 0.5 s and held (damped to rest): a
  // uniform strain delta / h, the floor's force E (delta / h) * 1 m * 1 m = 1e5 N.
  const std::string text =
      "[geometry]\ntype = \"rectangle\"\nsize = [1.0, 0.2]\ncells = [10, 2]\n"
      "fixed = [\"ymax\"]\ncontact = [\"ymin\"]\n"
      "fixed_displacement = {time = [0.0, 0.5], x = [0.0, 0.0], y = [0.0, -1e-4]}\n"
      "[material]\nyoung_modulus = 2e8\npoisson_ratio = 0.0\ndensity = 7800\nmass = "
      "\"lumped\"\nplane = \"stress\"\ndamping = {mass = 2000.0}\n"
      "[obstacle]\ntype = \"plane\"\nnormal = [0.0, 1.0]\noffset = 0.0\n"
      "normal_source = \"obstacle\"\n"
      "[time]\ndt = 1e-4\nend_time = 1.0\n[solver]\nstep = \"explicit\"\n";
  const Scene scene = LoadScene(WriteFile("pressed_block.toml", text));
  SceneModel built = BuildSceneModel(scene);
  const DynamicSummary s = RunDynamics(built.model, built.options);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  CHECK_THAT(s.records.back().normal_force_sum, Catch::Matchers::WithinRel(1e5, 1e-3));
  CHECK(s.records[2000].normal_force_sum < 0.45 * 1e5);  // t = 0.2 s: 40 % lowered
  // A consistent mass is refused (it would couple the fixed nodes' acceleration).
  std::string consistent = text;
  consistent.replace(consistent.find("\"lumped\""), 8, "\"consistent\"");
  consistent.erase(consistent.find("[solver]"));  // (explicit needs a lumped mass too)
  CHECK_THROWS_WITH(LoadScene(WriteFile("pressed_consistent.toml", consistent)),
                    Catch::Contains("'geometry.fixed_displacement' needs material.mass"));
}

TEST_CASE("The features are refused on MPI ranks with a message naming the key",
          "[scene-features][mpi]") {
  Scene plain = LoadScene(
      WriteFile("plain.toml", NamedSquareScene("groups = {contact = \"Base line\"}\n")));
  CHECK(internal::SerialOnlySceneFeature(plain).empty());
  Scene damped = plain;
  damped.damping.stiffness = 1e-4;
  CHECK_THAT(internal::SerialOnlySceneFeature(damped),
             Catch::Contains("'material.damping' is not available on MPI ranks"));
  Scene moving = plain;
  moving.obstacle_motion.time = {0.0, 1.0};
  moving.obstacle_motion.value = {Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1e-3)};
  CHECK_THAT(internal::SerialOnlySceneFeature(moving),
             Catch::Contains("'obstacle.motion'"));
  Scene supported = plain;
  supported.fixed_displacement = moving.obstacle_motion;
  CHECK_THAT(internal::SerialOnlySceneFeature(supported),
             Catch::Contains("'geometry.fixed_displacement'"));
  // The history itself: linear between the knots, constant outside them.
  CHECK(moving.obstacle_motion.At(-1.0) == Eigen::Vector2d::Zero());
  CHECK(moving.obstacle_motion.At(0.25).isApprox(Eigen::Vector2d(0.0, 0.25e-3)));
  CHECK(moving.obstacle_motion.At(2.0) == Eigen::Vector2d(0.0, 1e-3));
}
