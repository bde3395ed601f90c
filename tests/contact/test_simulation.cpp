// contact::Simulation (contact/simulation.hpp): stepping by hand is RunDynamics bit for
// bit for every step method; the body force and the obstacle's place change between steps
// and are recomputed exactly as the scene builds them; misuse throws naming the value.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "block_on_floor.hpp"
#include "contact/simulation.hpp"

namespace contact {
namespace {

// The steel block sliding at 1 m/s and falling at 0.1 m/s onto its floor 1 um below.
Scene SlidingBlock(StepMethod method) {
  Scene scene = testing::SteelBlockOnFloor(MassKind::kLumped);
  scene.obstacle = std::make_shared<HalfSpace>(HalfSpace::ObstacleBelow(2, 1, -1e-6));
  scene.dynamics.step_method = method;
  scene.dynamics.initial_state = InitialState::kPrescribed;
  scene.initial_velocity = Eigen::Vector2d(1.0, -0.1);
  scene.dynamics.end_time = 40 * scene.dynamics.dt;
  return scene;
}

void RequireSameRecords(const DynamicSummary& a, const DynamicSummary& b) {
  REQUIRE(a.records.size() == b.records.size());
  for (size_t k = 0; k < a.records.size(); ++k) {
    const StepRecord &r = a.records[k], &s = b.records[k];
    CAPTURE(k);
    CHECK(r.time == s.time);
    CHECK(r.newton_iterations == s.newton_iterations);
    CHECK(r.kinetic == s.kinetic);
    CHECK(r.strain == s.strain);
    CHECK(r.normal_contact_work == s.normal_contact_work);
    CHECK(r.friction_dissipation == s.friction_dissipation);
    CHECK(r.energy_balance_error == s.energy_balance_error);
    CHECK(r.normal_force_sum == s.normal_force_sum);
    CHECK(r.tangent_force_sum == s.tangent_force_sum);
    CHECK(r.max_penetration == s.max_penetration);
    CHECK(r.equilibrium_residual == s.equilibrium_residual);
    CHECK(r.active_nodes == s.active_nodes);
  }
  CHECK(a.status == b.status);
  CHECK(a.steps == b.steps);
  CHECK(a.u == b.u);
}

TEST_CASE("Simulation stepped in chunks is RunDynamics bit for bit", "[simulation]") {
  const StepMethod method = GENERATE(StepMethod::kFull, StepMethod::kCondensed,
                                     StepMethod::kExplicit, StepMethod::kSparse);
  CAPTURE(ToString(method));
  const SceneModel built = BuildSceneModel(SlidingBlock(method));
  const DynamicSummary run = RunDynamics(built.model, built.options);
  REQUIRE(run.status == DynamicStatus::kCompleted);
  REQUIRE(run.records.back().tangent_force_sum > 0.0);  // it slides on the floor

  Simulation sim(built.model, built.options);
  CHECK(sim.state() == SimulationState::kRunning);
  CHECK(sim.num_steps() == 40);
  long chunk = 0;
  while (sim.Step(chunk++ % 5) == SimulationState::kRunning) {
  }
  CHECK(sim.state() == SimulationState::kFinished);
  CHECK(sim.step_index() == 40);
  CHECK(sim.time() == Approx(40 * built.options.dt));
  RequireSameRecords(sim.summary(), run);
  CHECK(sim.displacement() == run.u);
  CHECK(sim.Step(3) == SimulationState::kFinished);  // nothing past end_time
  CHECK(sim.step_index() == 40);
}

TEST_CASE("A scene Simulation: the body force and the obstacle as the scene builds them",
          "[simulation]") {
  Scene scene = SlidingBlock(StepMethod::kCondensed);
  scene.normal_source = NormalSource::kBody;
  const DynamicSummary run =
      RunDynamics(BuildSceneModel(scene).model, BuildSceneModel(scene).options);

  Simulation sim(scene);
  const ContactFrames& frames = sim.scene_model().frames;
  Eigen::VectorXd s0(static_cast<Eigen::Index>(frames.nodes.size()));
  for (size_t c = 0; c < frames.nodes.size(); ++c)
    s0(static_cast<Eigen::Index>(c)) = frames.nodes[c].gap;
  CHECK(sim.contact_gaps() == s0);
  // The scene's own body force and place: the same run, bit for bit.
  sim.SetBodyForce(scene.body_force);
  sim.MoveObstacle(Eigen::Vector2d::Zero());
  CHECK(sim.contact_gaps() == s0);
  sim.Step(1000);
  RequireSameRecords(sim.summary(), run);

  // The floor 0.4 um up, then 1 mm sideways (no change for a plane), then back.
  Simulation moved(scene);
  moved.MoveObstacle(Eigen::Vector2d(0.0, 0.4e-6));
  CHECK((moved.contact_gaps().array() - (s0.array() - 0.4e-6)).abs().maxCoeff() < 1e-18);
  const ContactNodeStates before = moved.contact();
  CHECK((before.gap.array() - (s0.array() - 0.4e-6)).abs().maxCoeff() <
        1e-18);  // u^0 = 0
  CHECK(
      std::isnan(before.normal_force(0)));  // a prescribed start: not known before a step
  moved.MoveObstacle(Eigen::Vector2d(1e-3, 0.4e-6));
  CHECK((moved.contact_gaps().array() - (s0.array() - 0.4e-6)).abs().maxCoeff() < 1e-18);
  CHECK(moved.obstacle_translation() == Eigen::Vector2d(1e-3, 0.4e-6));
  moved.MoveObstacle(Eigen::Vector2d::Zero());
  CHECK(moved.contact_gaps() == s0);

  // Without gravity and with the floor 2 um up after a step, the impact comes sooner.
  Simulation pushed(scene);
  pushed.SetBodyForce(Eigen::Vector2d::Zero());
  CHECK(pushed.body_force() == Eigen::Vector2d::Zero());
  pushed.Step(1);
  pushed.MoveObstacle(Eigen::Vector2d(0.0, 2e-6));  // into the body: 1.8 um of overlap
  pushed.Step(1);
  const ContactNodeStates after = pushed.contact();
  CHECK(after.normal_force.minCoeff() > 0.0);
  CHECK(after.gap.cwiseAbs().maxCoeff() < 1e-15);
  for (const ContactState state : after.state) CHECK(state != ContactState::kOpen);
}

TEST_CASE("Simulation rejects misuse naming the value", "[simulation][errors]") {
  const SceneModel built = BuildSceneModel(SlidingBlock(StepMethod::kExplicit));
  Simulation sim(built.model, built.options);
  CHECK_THROWS_WITH(sim.Step(-1), Catch::Contains("n must be >= 0, got -1"));
  const auto N = static_cast<Eigen::Index>(built.model.contact_nodes.size());
  CHECK_THROWS_WITH(
      sim.SetContactGaps(Eigen::VectorXd::Zero(N + 1)),
      Catch::Contains("one gap per contact node (" + std::to_string(N) + ")"));
  Eigen::VectorXd gaps = Eigen::VectorXd::Zero(N);
  gaps(1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(sim.SetContactGaps(gaps),
                    Catch::Contains("contact node 1 is not finite"));
  CHECK_THROWS_AS(sim.SetLoad(nullptr), std::invalid_argument);
  CHECK_THROWS_WITH(sim.MoveObstacle(Eigen::Vector2d::Zero()),
                    Catch::Contains("only a Simulation of a scene"));
  CHECK(sim.step_index() == 0);

  Simulation scene_sim(SlidingBlock(StepMethod::kExplicit));
  CHECK_THROWS_WITH(scene_sim.MoveObstacle(Eigen::Vector3d::Zero()),
                    Catch::Contains("must be 2 finite numbers [m]"));
  CHECK_THROWS_WITH(scene_sim.SetBodyForce(Eigen::Vector2d(0.0, std::nan(""))),
                    Catch::Contains("body force must be 2 finite numbers [N/m^3]"));

  Scene unstable = SlidingBlock(StepMethod::kExplicit);
  unstable.dynamics.dt = 1e-3;
  unstable.dynamics.end_time = 1e-2;
  Simulation refused(unstable);
  CHECK(refused.state() == SimulationState::kFailed);
  CHECK(refused.summary().status == DynamicStatus::kRefusedUnstable);
  CHECK(refused.Step(5) == SimulationState::kFailed);
  CHECK_THROWS_WITH(refused.displacement(), Catch::Contains("no state"));
}

}  // namespace
}  // namespace contact

namespace contact {
namespace {

// A checkpoint after k steps, loaded into a new Simulation of the same model and stepped
// to the end, is the uninterrupted run bit for bit - for every step method (the warm
// start of the Newton and ncp::fc steps included: the block slides, so friction forces
// are carried).
TEST_CASE(
    "Simulation checkpoint: loaded and stepped on is the uninterrupted run bit for bit",
    "[simulation][checkpoint]") {
  const StepMethod method = GENERATE(StepMethod::kFull, StepMethod::kCondensed,
                                     StepMethod::kExplicit, StepMethod::kSparse);
  CAPTURE(ToString(method));
  const SceneModel built = BuildSceneModel(SlidingBlock(method));
  const DynamicSummary run = RunDynamics(built.model, built.options);
  REQUIRE(run.status == DynamicStatus::kCompleted);
  const std::string path =
      "test_simulation_checkpoint_" + std::string(ToString(method)) + ".ckpt";
  {
    Simulation first(built.model, built.options);
    first.Step(17);
    first.SaveCheckpoint(path, "app data");
  }
  Simulation second(built.model, built.options);
  CHECK(second.LoadCheckpoint(path) == "app data");
  CHECK(second.step_index() == 17);
  CHECK(second.time() == run.records[16].time);
  second.Step(1000);
  RequireSameRecords(run, second.summary());
  CHECK(second.summary().newton_iterations == run.newton_iterations);
  CHECK(second.summary().friction_restarts == run.friction_restarts);
  CHECK(second.summary().max_friction_residual == run.max_friction_residual);
  std::remove(path.c_str());
}

TEST_CASE("Simulation checkpoint: another model, a truncated or corrupt file is refused",
          "[simulation][checkpoint]") {
  const SceneModel built = BuildSceneModel(SlidingBlock(StepMethod::kCondensed));
  const std::string path = "test_simulation_checkpoint_refused.ckpt";
  Simulation sim(built.model, built.options);
  sim.Step(3);
  sim.SaveCheckpoint(path);
  DynamicOptions other_dt = built.options;
  other_dt.dt *= 0.5;
  Simulation other(built.model, other_dt);
  CHECK_THROWS_WITH(other.LoadCheckpoint(path),
                    Catch::Contains("of another run") && Catch::Contains("time steps"));
  CHECK(other.step_index() == 0);  // unchanged
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto write = [&](const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
  };
  write(bytes.substr(0, bytes.size() - 1));
  CHECK_THROWS_AS(sim.LoadCheckpoint(path), CheckpointError);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 1;
  write(flipped);
  CHECK_THROWS_WITH(sim.LoadCheckpoint(path), Catch::Contains("checksum"));
  std::remove(path.c_str());
  CHECK_THROWS_WITH(sim.LoadCheckpoint(path), Catch::Contains("cannot read checkpoint"));
}

}  // namespace
}  // namespace contact
