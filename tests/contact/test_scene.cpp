// Scene files: every error names its key; a 3D slab with plane-strain conditions follows
// the 2D plane-strain model; f_c = 0 reproduces the frictionless run.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>

#include "contact/scene.hpp"

using namespace contact;
namespace fs = std::filesystem;

namespace {

std::string WriteScene(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "contact_scene_tests";
  fs::create_directories(dir);
  const fs::path p = dir / (name + ".toml");
  std::ofstream(p) << text;
  return p.string();
}

// A block falling onto a floor y >= -gap: 2D rectangle or 3D slab of depth 0.1 m with
// u_z = 0 on both z faces (plane strain). Body force pushes it down and sideways.
std::string Block(int dim, double friction, const std::string& extra = "") {
  std::string geometry = dim == 2
                             ? "[geometry]\ntype = \"rectangle\"\nsize = [1.0, "
                               "0.2]\ncells = [5, 2]\ncontact = [\"ymin\"]\n"
                             : "[geometry]\ntype = \"box\"\nsize = [1.0, 0.2, "
                               "0.1]\ncells = [5, 2, 1]\ncontact = [\"ymin\"]\n"
                               "fixed = [\"zmin\", \"zmax\"]\nfixed_components = [2]\n";
  return geometry +
         "[material]\nyoung_modulus = 2e8\npoisson_ratio = 0.3\ndensity = 7800\nmass = "
         "\"lumped\"\n" +
         "[loads]\nbody_force = " +
         (dim == 2 ? "[30000.0, -400000.0]" : "[30000.0, -400000.0, 0.0]") + "\n" +
         "[obstacle]\ntype = \"plane\"\nnormal = " +
         (dim == 2 ? "[0.0, 1.0]" : "[0.0, 1.0, 0.0]") + "\noffset = -0.0001\n" +
         (friction >= 0 ? "[friction]\ncoefficient = " + std::to_string(friction) + "\n"
                        : "") +
         "[time]\ndt = 2e-5\nend_time = 0.004\ninitial_state = "
         "\"velocity\"\ninitial_velocity = " +
         (dim == 2 ? "[0.0, 0.0]" : "[0.0, 0.0, 0.0]") + "\n" + extra;
}

// Full displacement at the end of a run, keyed by the node's (x, y) rounded to 1e-9 m.
std::map<std::pair<long, long>, Eigen::Vector2d> FinalDisplacements(const Scene& scene) {
  SceneModel built = BuildSceneModel(scene);
  const DynamicSummary s = RunDynamics(built.model, built.options);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  // The exact discrete energy balance closes (it includes the contact work at nodes with
  // constrained components in 3D).
  CHECK(s.energy_balance_error <= 1e-8 * std::abs(s.records.back().external_work));
  CHECK(s.records.back().friction_dissipation >=
        -1e-12 * std::abs(s.records.back().external_work));
  const Eigen::VectorXd u = built.dofs.Expand(s.u);
  const Mesh& mesh = built.body->mesh();
  std::map<std::pair<long, long>, Eigen::Vector2d> out;
  for (int i = 0; i < mesh.NumNodes(); ++i) {
    const auto key = std::make_pair(std::lround(mesh.nodes(0, i) * 1e9),
                                    std::lround(mesh.nodes(1, i) * 1e9));
    out[key] = u.segment(mesh.dim * i, 2);
  }
  return out;
}

// u after every step of a run (which must complete); *newton gets the Newton iterations.
std::vector<Eigen::VectorXd> Trajectory(const Scene& scene, long* newton = nullptr) {
  std::vector<Eigen::VectorXd> out;
  SceneModel built = BuildSceneModel(scene);
  built.options.on_step = [&](const StepRecord&, const Eigen::VectorXd& u,
                              const ContactSystem::Result&, double) { out.push_back(u); };
  const DynamicSummary s = RunDynamics(built.model, built.options);
  INFO(s.message);
  REQUIRE(s.status == DynamicStatus::kCompleted);
  if (newton) *newton = s.newton_iterations;
  return out;
}

// Checks that two trajectories agree to 1e-9 of the largest displacement.
void CheckSameTrajectory(const std::vector<Eigen::VectorXd>& a,
                         const std::vector<Eigen::VectorXd>& b) {
  REQUIRE(a.size() == b.size());
  double scale = 0.0, difference = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    scale = std::max(scale, a[k].lpNorm<Eigen::Infinity>());
    difference = std::max(difference, (a[k] - b[k]).lpNorm<Eigen::Infinity>());
  }
  INFO("scale " << scale << " m, difference " << difference << " m");
  CHECK(scale > 0.0);
  CHECK(difference <= 1e-9 * scale);
}

}  // namespace

namespace {
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}
}  // namespace

// Values that crashed, exhausted memory or ran to a silently wrong result before the
// range checks: each is refused by LoadScene with the key, the value, the range and the
// unit.
TEST_CASE("Scene values outside their range are refused before any work",
          "[scene][errors][limits]") {
  const std::string good = Block(2, 0.0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {Replace(good, "end_time = 0.004", "end_time = 1e300"),
       "'time.end_time' = 1e+300 s is outside the accepted range (0, 1000000000] s"},
      {Replace(good, "dt = 2e-5", "dt = 1e-300"),
       "gives 4e+297 time steps; at most 1000000 are accepted"},
      {Replace(good, "end_time = 0.004", "end_time = 1e5"),
       "'time.dt' = 2e-05 s with time.end_time = 100000 s"},
      {good + "[solver]\nmax_iterations = 4294967297\n",
       "'solver.max_iterations' = 4294967297 is outside the accepted range [1, 1000000]"},
      {Replace(good, "density = 7800", "density = 99999999999999999999999"),
       "'material.density' is an integer literal beyond the 64-bit range"},
      {Replace(good, "density = 7800", "density = 1e-300"),
       "'material.density' = 1e-300 kg/m^3 is outside the accepted range [1e-15, "
       "1000000000000] kg/m^3"},
      {Replace(good, "young_modulus = 2e8", "young_modulus = 1e300"),
       "'material.young_modulus' = 1e+300 Pa is outside the accepted range [1e-12, "
       "1e+18] Pa"},
      {Replace(good, "size = [1.0, 0.2]", "size = [1e300, 1e300]"),
       "'geometry.size' entry 0 = 1e+300 m is outside the accepted range [1e-09, "
       "1000000000] m"},
      {Replace(good, "size = [1.0, 0.2]", "size = [1000.0, 1e-5]"),
       "'geometry.size' and 'cells': cells of aspect ratio 4e+07 (edges 200 m and 5e-06 "
       "m) exceed the limit of 10000"},
      {Replace(good, "cells = [5, 2]", "cells = [1000000, 1000]"),
       "'geometry.size' and 'cells': 1e+09 cells exceed the limit of 4e+06"},
      {good + "[output]\nmarked_point = [1e300, 0.0]\n",
       "'output.marked_point' entry 0 = 1e+300 m"},
      {Replace(good, "cells = [5, 2]",
               "cells = " + std::string(100000, '[') + std::string(100000, ']')),
       "bad.toml:4: arrays or inline tables nested 100000 deep; at most 32 levels are "
       "accepted"},
      {Replace(good, "cells = [5, 2]",
               "cells = {a = " + std::string(50, '{') + std::string(50, '}') + "}"),
       "nested 51 deep; at most 32"},
      {Replace(good, "cells = [5, 2]", "cells = [5.5, 2]"),
       "'geometry.cells' entries must be integers, got 5.5"},
  };
  for (const auto& [text, message] : cases) {
    CAPTURE(message);
    CHECK_THROWS_WITH(LoadScene(WriteScene("bad", text)), Catch::Contains(message));
  }
  // Not a file; the nesting scan skips brackets inside strings and comments.
  CHECK_THROWS_WITH(LoadScene(fs::temp_directory_path().string()),
                    Catch::Contains("not a regular file"));
  CHECK_NOTHROW(
      LoadScene(WriteScene("strings", "# [[[[ " + std::string(40, '[') + "\nname = \"" +
                                          std::string(40, '{') + "\"\n" + good)));
}

// Found by the fuzz test (seed 2, case 211): errors of the mesh and the model named no
// file.
TEST_CASE("Errors while building a scene's model name the scene file",
          "[scene][errors]") {
  const std::string path =
      WriteScene("no_contact", Replace(Block(2, 0.0), "contact = [\"ymin\"]\n", ""));
  const Scene scene = LoadScene(path);
  CHECK_THROWS_AS(BuildSceneModel(scene), SceneError);
  CHECK_THROWS_WITH(BuildSceneModel(scene),
                    Catch::Contains(path + ": mesh has no boundary group 'contact'"));
}

TEST_CASE("Scene overrides are validated like values of the file", "[scene][errors]") {
  const std::string path = WriteScene("good", Block(2, 0.0));
  CHECK(LoadScene(path, {{"time.dt", "1e-5"}}).dynamics.dt == 1e-5);
  CHECK(LoadScene(path, {{"friction.coefficient", "0.25"}}).friction_coefficient == 0.25);
  CHECK_THROWS_WITH(
      LoadScene(path, {{"time.dt", "-3"}}),
      Catch::Contains(
          "command line (time.dt):1: 'time.dt' = -3 s is outside the accepted range"));
  CHECK_THROWS_WITH(LoadScene(path, {{"time.dt", "abc"}}),
                    Catch::Contains("'time.dt' = abc is not a TOML value"));
  CHECK_THROWS_WITH(LoadScene(path, {{"solver.ncp_function", "\"newton\""}}),
                    Catch::Contains("'solver.ncp_function' must be one of"));
  // solver.friction: the default (implicit Coulomb on ncp::fc), the lagged bound (eq.
  // 94), and only with the condensed step.
  CHECK(LoadScene(path).dynamics.friction_formulation == FrictionFormulation::kCoulombFc);
  CHECK(LoadScene(path, {{"solver.friction", "\"lagged-bound\""}})
            .dynamics.friction_formulation == FrictionFormulation::kLaggedBound);
  CHECK_THROWS_WITH(
      LoadScene(path,
                {{"solver.friction", "\"coulomb-fc\""}, {"solver.step", "\"full\""}}),
      Catch::Contains("needs solver.step = \"auto\", \"condensed\" or \"sparse\""));
  // solver.step: auto by default; the sparse step refuses the lagged bound
  CHECK(LoadScene(path).dynamics.step_method == StepMethod::kAuto);
  CHECK(LoadScene(path, {{"solver.step", "\"sparse\""}}).dynamics.step_method ==
        StepMethod::kSparse);
  CHECK_THROWS_WITH(LoadScene(path, {{"solver.friction", "\"lagged-bound\""},
                                     {"solver.step", "\"sparse\""}}),
                    Catch::Contains("solves implicit Coulomb only"));
  CHECK_THROWS_WITH(LoadScene(path, {{"solver.friction", "\"coulomb\""}}),
                    Catch::Contains("'solver.friction' must be one of"));
}

TEST_CASE("Scene: one choice of the step solver; the NCP function of the Newton steps",
          "[scene]") {
  const std::string path = WriteScene("good", Block(2, 0.0));
  // The default: semismooth Newton with Fischer-Burmeister.
  CHECK(LoadScene(path).dynamics.ncp.ncp_function ==
        ncp::NcpFunction::kFischerBurmeister);
  CHECK(LoadScene(path, {{"solver.ncp_function", "\"min\""}}).dynamics.ncp.ncp_function ==
        ncp::NcpFunction::kMin);
  CHECK(LoadScene(path, {{"solver.ncp_function", "\"penalized-fb\""}})
            .dynamics.ncp.ncp_function == ncp::NcpFunction::kPenalizedFischerBurmeister);
  // Ipopt is a step method of its own, frictionless only.
  CHECK(LoadScene(path, {{"solver.step", "\"ipopt\""}}).dynamics.step_method ==
        StepMethod::kIpopt);
  CHECK_THROWS_WITH(
      LoadScene(path, {{"solver.step", "\"ipopt\""}, {"friction.coefficient", "0.3"}}),
      Catch::Contains("'solver.step' = \"ipopt\" solves frictionless steps only"));
}

TEST_CASE("Scene: renamed solver keys and values fail naming what to write",
          "[scene][errors]") {
  const std::string path = WriteScene("good", Block(2, 0.0));
  CHECK_THROWS_WITH(
      LoadScene(path, {{"solver.method", "\"min\""}}),
      Catch::Contains(
          "'solver.method' was renamed: write solver.ncp_function = \"min\""));
  CHECK_THROWS_WITH(LoadScene(path, {{"solver.method", "\"ipopt\""}}),
                    Catch::Contains("write solver.step = \"ipopt\""));
  CHECK_THROWS_WITH(LoadScene(path, {{"solver.method", "3"}}),
                    Catch::Contains("write solver.ncp_function = \"fb\""));
  CHECK_THROWS_WITH(
      LoadScene(path, {{"solver.friction", "\"eq94\""}}),
      Catch::Contains("'solver.friction' = \"eq94\" was renamed: write solver.friction = "
                      "\"lagged-bound\""));
  // A thesis scene file of the old form: both renames in one message.
  CHECK_THROWS_WITH(
      LoadScene(path, {{"solver.method", "\"fb\""}, {"solver.friction", "\"eq94\""}}),
      Catch::Contains("write solver.ncp_function = \"fb\"") &&
          Catch::Contains("write solver.friction = \"lagged-bound\""));
}

TEST_CASE("Scene errors name the key", "[scene][errors]") {
  const std::string good = Block(2, 0.0);
  REQUIRE_NOTHROW(LoadScene(WriteScene("good", good)));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {good + "[solver]\nmethd = \"fb\"\n", "unknown key 'solver.methd'"},
      {good + "colour = 3\n", "unknown key 'time.colour'"},
      {"colour = 3\n" + good, "unknown key 'colour'"},
      {Block(2, 0.0, "[output]\nsnapshot_every = -1\n"),
       "'output.snapshot_every' = -1 is outside the accepted range [0, 1000000]"},
      {std::string(good).replace(good.find("dt = 2e-5"), 9, "dt = \"x\""),
       "'time.dt' must be a number"},
      {std::string(good).replace(good.find("dt = 2e-5"), 9, "dt = -1.0"),
       "'time.dt' = -1 s is outside the accepted range (0, 1000000000] s"},
      {std::string(good).replace(good.find("poisson_ratio = 0.3"), 19,
                                 "poisson_ratio = 0.6"),
       "'material.poisson_ratio' = 0.6 is outside the accepted range (-1, 0.5)"},
      {std::string(good).replace(good.find("density = 7800"), 14, ""),
       "'material.density' is missing"},
      {std::string(good).replace(good.find("\"ymin\""), 6, "\"top\""),
       "unknown side \"top\""},
      {std::string(good).replace(good.find("\"plane\""), 7, "\"cone\""),
       "'obstacle.type' must be one of"},
      {Block(2, 0.5, "[solver]\nstep = \"ipopt\"\n"), "solves frictionless steps only"},
      {std::string(good).replace(good.find("normal = [0.0, 1.0]"), 19,
                                 "normal = [0.0, 0.0]"),
       "'obstacle.normal' must be a unit vector"},
      {std::string(good).replace(good.find("normal = [0.0, 1.0]"), 19,
                                 "normal = [0.0, 2.0]"),
       "'obstacle.normal' must be a unit vector (|n| = 1 within 0.001), got |n| = 2"},
      {"[geometry\n", "cannot read scene file"},
  };
  for (const auto& [text, message] : cases) {
    CAPTURE(message);
    CHECK_THROWS_WITH(LoadScene(WriteScene("bad", text)), Catch::Contains(message));
  }
}

TEST_CASE("A plane-strain 3D slab follows the 2D plane-strain model",
          "[scene][dynamics]") {
  const double friction = GENERATE(0.0, 0.4);
  CAPTURE(friction);
  const auto u2 =
      FinalDisplacements(LoadScene(WriteScene("block2d", Block(2, friction))));
  const auto u3 =
      FinalDisplacements(LoadScene(WriteScene("block3d", Block(3, friction))));
  REQUIRE(u2.size() == 18);
  double scale = 0.0, error = 0.0;
  for (const auto& [key, v2] : u2) {
    REQUIRE(u3.count(key) == 1);
    scale = std::max(scale, v2.lpNorm<Eigen::Infinity>());
    error = std::max(error, (u3.at(key) - v2).lpNorm<Eigen::Infinity>());
  }
  CHECK(scale > 1e-5);  // it moved: fell onto the floor and slid
  CHECK(error <= 1e-8 * scale);
}

TEST_CASE("Friction coefficient 0 reproduces the frictionless run", "[scene][dynamics]") {
  const auto with_zero = FinalDisplacements(LoadScene(WriteScene("fc0", Block(2, 0.0))));
  const auto frictionless =
      FinalDisplacements(LoadScene(WriteScene("nofriction", Block(2, -1.0))));
  for (const auto& [key, v] : frictionless)
    CHECK((with_zero.at(key) - v).lpNorm<Eigen::Infinity>() == 0.0);
  // And friction changes the answer (the block is pushed sideways while pressed down).
  const auto with_friction =
      FinalDisplacements(LoadScene(WriteScene("fc04", Block(2, 0.4))));
  double difference = 0.0;
  for (const auto& [key, v] : frictionless)
    difference = std::max(difference, std::abs(with_friction.at(key)(0) - v(0)));
  CHECK(difference > 1e-7);
}

TEST_CASE("The condensed step follows the full thesis system on the thesis scenes",
          "[scene][dynamics][condensed]") {
  // Four variants: 2D and 3D, frictionless and with friction (thesis section 6 scenes,
  // shortened). Both step methods solve the same complementarity problem, the condensed
  // one after eliminating the non-contact dofs exactly; with a tight tolerance the
  // trajectories agree to round-off.
  struct Case {
    const char* file;
    double friction, end_time, tolerance;  // tolerance [m]: ~1e-11 of the displacements
  };
  const Case c = GENERATE(Case{"friction_2d_curved.toml", 0.0, 0.1, 1e-14},
                          Case{"friction_2d_flat.toml", 0.5, 0.1, 1e-14},
                          Case{"frictionless_3d.toml", 0.0, 0.01, 1e-14},
                          Case{"friction_3d.toml", 0.5, 0.025, 1e-17});
  CAPTURE(c.file, c.friction);
  Scene scene = LoadScene(std::string(NCP_SOURCE_DIR) + "/examples/thesis/" + c.file);
  scene.friction_coefficient = c.friction;
  scene.dynamics.end_time = c.end_time;
  scene.dynamics.dt = std::max(scene.dynamics.dt, c.end_time / 100);
  scene.dynamics.ncp.tolerance = c.tolerance;
  scene.dynamics.step_method = StepMethod::kFull;
  const auto full = Trajectory(scene);
  scene.dynamics.step_method = StepMethod::kCondensed;
  CheckSameTrajectory(full, Trajectory(scene));
}

TEST_CASE(
    "The sparse step follows the condensed step (implicit Coulomb) on every scene both "
    "run",
    "[scene][dynamics][sparse]") {
  // The thesis scenes (2D and 3D, frictionless and with friction, consistent mass;
  // friction as implicit Coulomb, the one formulation of the sparse step) and the
  // falling, sliding block (lumped mass; in 3D a plane-strain slab whose contact nodes
  // have a constrained component), with default tolerance. The condensed step solves the
  // Delassus problem on W formed, the sparse one with W applied by solves with M (GMRES):
  // same trajectories.
  struct Case {
    std::string file;
    double friction, end_time;
  };
  const std::string thesis = std::string(NCP_SOURCE_DIR) + "/examples/thesis/";
  const Case c = GENERATE_COPY(Case{thesis + "friction_2d_curved.toml", 0.0, 0.1},
                               Case{thesis + "friction_2d_flat.toml", 0.5, 0.1},
                               Case{thesis + "frictionless_3d.toml", 0.0, 0.01},
                               Case{thesis + "friction_3d.toml", 0.5, 0.025},
                               Case{"block2", 0.4, -1.0}, Case{"block3", 0.4, -1.0},
                               Case{"block3", 0.0, -1.0});
  CAPTURE(c.file, c.friction);
  Scene scene = c.file.rfind("block", 0) == 0
                    ? LoadScene(WriteScene("sparse" + c.file,
                                           Block(c.file.back() - '0', c.friction)))
                    : LoadScene(c.file);
  scene.friction_coefficient = c.friction;
  if (c.end_time > 0) {
    scene.dynamics.end_time = c.end_time;
    scene.dynamics.dt = std::max(scene.dynamics.dt, c.end_time / 100);
  }
  scene.dynamics.friction_formulation = FrictionFormulation::kCoulombFc;
  scene.dynamics.step_method = StepMethod::kCondensed;
  const auto condensed = Trajectory(scene);
  scene.dynamics.step_method = StepMethod::kSparse;
  CheckSameTrajectory(condensed, Trajectory(scene));
  // auto: the method its cost model predicts cheapest (explicit only for a lumped mass)
  scene.dynamics.step_method = StepMethod::kAuto;
  SceneModel built = BuildSceneModel(scene);
  built.options.end_time = built.options.start_time + built.options.dt;
  const DynamicSummary chosen = RunDynamics(built.model, built.options);
  CHECK(chosen.step_method == chosen.predicted_cost.choice);
  CHECK((chosen.step_method == StepMethod::kCondensed ||
         chosen.step_method == StepMethod::kSparse ||
         chosen.step_method == StepMethod::kExplicit));
}

TEST_CASE(
    "The explicit step equals the semismooth Newton solution of the lumped-mass step",
    "[scene][dynamics][explicit]") {
  // The falling and sliding block (lumped mass): 2D and the 3D plane-strain slab (contact
  // nodes with a constrained component), frictionless and with friction. The explicit
  // step solves each node in closed form; the full system is solved by FB to 1e-14 m.
  const int dim = GENERATE(2, 3);
  const double friction = GENERATE(0.0, 0.4);
  CAPTURE(dim, friction);
  Scene scene =
      LoadScene(WriteScene("explicit" + std::to_string(dim), Block(dim, friction)));
  scene.dynamics.ncp.tolerance = 1e-14;
  scene.dynamics.step_method = StepMethod::kFull;
  const auto full = Trajectory(scene);
  scene.dynamics.step_method = StepMethod::kExplicit;
  long newton = -1;
  const auto explicit_trajectory = Trajectory(scene, &newton);
  CHECK(newton == 0);
  CheckSameTrajectory(full, explicit_trajectory);
  CHECK(full.back().lpNorm<Eigen::Infinity>() > 1e-5);  // it fell and slid
}

TEST_CASE("The explicit step refuses a consistent mass", "[scene][errors]") {
  std::string text = Block(2, 0.0);
  text.replace(text.find("mass = \"lumped\""), 15, "mass = \"consistent\"");
  CHECK_THROWS_WITH(LoadScene(WriteScene("explicit_consistent",
                                         text + "[solver]\nstep = \"explicit\"\n")),
                    Catch::Contains("needs material.mass = \"lumped\""));
  Scene scene = LoadScene(WriteScene("explicit_consistent_api", text));
  scene.dynamics.step_method = StepMethod::kExplicit;
  SceneModel built = BuildSceneModel(scene);
  CHECK_THROWS_WITH(RunDynamics(built.model, built.options),
                    Catch::Contains("lumped (diagonal) mass"));
}

TEST_CASE(
    "Table 3 with f_c = 0.5 completes with both step methods, a failed frictional "
    "solve is retried once from the neutral start",
    "[scene][dynamics][friction]") {
  // With a mass factor computed as LDL' (an earlier version) the condensed solve of step
  // 29 stalled next to the degenerate point of eq. (94) when started from the previous
  // friction forces (a force of 0.7% of its bound at one node); the restart from the
  // neutral start solved it. Round-off decides whether that happens, so the run is
  // checked to complete with at most that one restart, and the restart itself is forced
  // below.
  const StepMethod method = GENERATE(StepMethod::kCondensed, StepMethod::kFull);
  CAPTURE(ToString(method));
  Scene scene =
      LoadScene(std::string(NCP_SOURCE_DIR) + "/examples/thesis/friction_3d.toml");
  scene.friction_coefficient = 0.5;
  scene.dynamics.step_method = method;
  SceneModel built = BuildSceneModel(scene);
  DynamicSummary s = RunDynamics(built.model, built.options);
  INFO(s.message);
  CHECK(s.status == DynamicStatus::kCompleted);
  CHECK(s.steps == 50);
  CHECK(s.friction_restarts <= 1);

  // One Newton iteration is too few once the block slides: the first frictional step
  // fails, is tried once more (counted, iterations of both attempts summed), and the run
  // stops there with the solver's message.
  built.options.ncp.max_iterations = 1;
  s = RunDynamics(built.model, built.options);
  CHECK(s.status == DynamicStatus::kSolverFailure);
  CHECK(s.friction_restarts == 1);
  CHECK_THAT(s.message, Catch::Contains("max_iterations = 1"));
  CHECK(s.newton_iterations >= 2);
}
