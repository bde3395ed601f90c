// contact::petsc::RunSceneDistributed against the serial contact::RunScene on the same
// scene: the final displacement (gathered on rank 0) and the per-step sums of the normal
// and friction forces agree to 1e-12 of their largest value, on 1, 2 and 4 ranks (ctest
// runs this executable under mpiexec -n 1, 2, 4). The scenes: a Hex8 box and a 2D Quad4
// block (with a roller side: Dirichlet components) dropped onto a plane with friction,
// and two cells (on 4 ranks: ranks without a cell or a contact node).
#define CATCH_CONFIG_RUNNER
#include <petscsys.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>

#include "contact/petsc/distributed_scene.hpp"
#include "contact/scene.hpp"
#include "distributed_scene_support.hpp"

namespace {

using contact::test::MaxAbs;
using contact::test::Rank;

constexpr double kSameTrajectory =
    1e-12;  // relative to the largest value of the quantity

// A Hex8 box 0.2 m wide falling at 0.5 m/s onto a plane 1 mm below it, with friction and
// a sideways body force (so that it slides).
const char* const kBox3d = R"(
name = "box-drop-3d"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [0.2, 0.2, 0.1]
cells = [6, 5, 3]
element = "hex8"
contact = ["zmin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
mass = "lumped"
[loads]
body_force = [20000.0, 5000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = -0.001
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = 2e-5
end_time = 0.005
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[solver]
step = "explicit"
)";

// The 2D block of examples/scenes/block_drop_2d.toml, its side xmin on a roller (x
// fixed).
const char* const kBlock2d = R"(
name = "block-drop-2d"
[geometry]
type = "rectangle"
origin = [0.0, 0.0]
size = [1.0, 0.2]
cells = [20, 4]
element = "quad4"
contact = ["ymin"]
fixed = ["xmin"]
fixed_components = [0]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
plane = "strain"
thickness = 1.0
mass = "lumped"
[loads]
body_force = [-20000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 1.0]
offset = -0.001
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = 5e-5
end_time = 0.01
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[solver]
step = "explicit"
)";

// Two Quad4 cells: on 4 ranks two ranks have no cell and no contact node.
const char* const kTwoCells2d = R"(
name = "two-cells-2d"
[geometry]
type = "rectangle"
origin = [0.0, 0.0]
size = [1.0, 0.2]
cells = [2, 1]
element = "quad4"
contact = ["ymin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
mass = "lumped"
[loads]
body_force = [20000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 1.0]
offset = -0.001
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = 5e-5
end_time = 0.005
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[solver]
step = "explicit"
)";

contact::Scene LoadSceneText(const std::string& text, const std::string& name) {
  return contact::test::LoadSceneText(text, "distributed_scene", name);
}

}  // namespace

TEST_CASE("the explicit step on MPI ranks follows the serial trajectory") {
  const auto [name, text] =
      GENERATE(std::make_pair("box3d", kBox3d), std::make_pair("block2d", kBlock2d),
               std::make_pair("two_cells", kTwoCells2d));
  const contact::Scene scene = LoadSceneText(text, name);
  REQUIRE(contact::petsc::WhyNotDistributed(scene).empty());
  const contact::SceneResult parallel =
      contact::petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, false);
  REQUIRE(parallel.summary.status == contact::DynamicStatus::kCompleted);
  if (Rank() != 0) return;
  const contact::SceneResult serial = contact::RunScene(scene, false);
  INFO(name << ": " << serial.summary.message << " / " << parallel.summary.message);
  REQUIRE(serial.summary.status == contact::DynamicStatus::kCompleted);
  REQUIRE(parallel.summary.steps == serial.summary.steps);
  REQUIRE(parallel.summary.records.size() == serial.summary.records.size());

  // The final displacement, every free dof.
  const Eigen::VectorXd& u = serial.summary.u;
  REQUIRE(parallel.summary.u.size() == u.size());
  const double u_max = u.lpNorm<Eigen::Infinity>();
  REQUIRE(u_max > 1e-4);  // it moved (m)
  CHECK((parallel.summary.u - u).lpNorm<Eigen::Infinity>() <= kSameTrajectory * u_max);

  // The contact forces of every step; the scene has contact and sliding.
  const double normal_max =
      MaxAbs(serial.summary.records, &contact::StepRecord::normal_force_sum);
  const double friction_max =
      MaxAbs(serial.summary.records, &contact::StepRecord::tangent_force_sum);
  REQUIRE(normal_max > 0.0);
  REQUIRE(friction_max > 0.0);
  double normal_difference = 0.0, friction_difference = 0.0;
  for (size_t k = 0; k < serial.summary.records.size(); ++k) {
    const contact::StepRecord &s = serial.summary.records[k],
                              &p = parallel.summary.records[k];
    REQUIRE(p.time == s.time);
    normal_difference =
        std::max(normal_difference, std::abs(p.normal_force_sum - s.normal_force_sum));
    friction_difference = std::max(friction_difference,
                                   std::abs(p.tangent_force_sum - s.tangent_force_sum));
  }
  CHECK(normal_difference <= kSameTrajectory * normal_max);
  CHECK(friction_difference <= kSameTrajectory * friction_max);
  contact::test::CheckSameMeasures(scene, serial.summary, parallel.summary,
                                   kSameTrajectory);

  // dt_crit, estimated on the ranks' K and lumped mass.
  contact::test::CheckCriticalStep(scene, serial.summary, parallel.summary,
                                   kSameTrajectory);
}

TEST_CASE("an unstable explicit step blows up on MPI ranks as in one process") {
  // kBox3d with dt = 4e-4 s, above its dt_crit = 1.74e-4 s, allowed: the energy guard
  // must stop the run at the same step with the same status.
  std::string text = kBox3d;
  text.replace(text.find("dt = 2e-5"), 9, "dt = 4e-4");
  text.replace(text.find("end_time = 0.005"), 16,
               "end_time = 0.2\nallow_unstable = true");
  const contact::Scene scene = LoadSceneText(text, "unstable");
  const contact::SceneResult parallel =
      contact::petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, false);
  CHECK(parallel.summary.status == contact::DynamicStatus::kEnergyBlowUp);
  if (Rank() != 0) return;
  const contact::SceneResult serial = contact::RunScene(scene, false);
  INFO(serial.summary.message << " / " << parallel.summary.message);
  REQUIRE(serial.summary.status == contact::DynamicStatus::kEnergyBlowUp);
  CHECK(parallel.summary.steps == serial.summary.steps);
  CHECK(parallel.summary.steps < 500);  // stopped before end_time
  // (the energies in the messages differ: under material.kinematics = "auto" one process
  // switches to finite strain as the blow-up rotates the elements, ranks run small
  // strain)
  CHECK(parallel.summary.message.substr(0, 30) == serial.summary.message.substr(0, 30));
}

TEST_CASE("dt above dt_crit estimated on MPI ranks is refused as in one process") {
  // kBox3d with dt = 4e-4 s > dt_crit = 1.74e-4 s, not allowed: refused on every rank
  // before any step, with the serial message (dt_crit to its 6 printed digits).
  std::string text = kBox3d;
  text.replace(text.find("dt = 2e-5"), 9, "dt = 4e-4");
  const contact::Scene scene = LoadSceneText(text, "refused");
  contact::test::CheckRefusedAsSerial(scene);
}

TEST_CASE(
    "a scene whose step is neither explicit nor condensed is refused on every rank") {
  std::string text = kBlock2d;
  text.replace(text.find("step = \"explicit\""), 17, "step = \"full\"");
  const contact::Scene scene = LoadSceneText(text, "full");
  const std::string why = contact::petsc::WhyNotDistributed(scene);
  CHECK_THAT(
      why, Catch::Matchers::Contains("'full'") && Catch::Matchers::Contains("explicit"));
  CHECK_THROWS_WITH(contact::petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, false),
                    Catch::Matchers::Contains("'full'"));
}

int main(int argc, char** argv) { return RunTestsOnRanks(argc, argv); }
