// The same scene in SI and in mm-tonne-s (mm, t, s; forces in N, stresses in MPa,
// densities in t/mm^3) on MPI ranks gives the same answer (the developers' guide; the
// serial check is tests/contact/test_physical_accuracy.cpp). ctest runs this executable
// under mpiexec -n 2. A Tet4 box with friction, a traction ramp and a body force is
// written in SI; the test converts every numeric key of that text into mm-tonne-s by its
// dimension (a key without a declared dimension fails the test, so a new scene key cannot
// slip through unconverted) and runs both on the ranks with
//  * the explicit step (lumped mass: dt_crit by Lanczos on the distributed K),
//  * the condensed step (consistent mass: M factored by MUMPS, W gathered onto rank 0),
//  * the condensed step with the solves by CG + Jacobi (-mass_ksp_type cg: the stopping
//    test on the true residual in the step's force accuracy),
//  * the sparse step (W applied by distributed solves, GMRES in the contact Newton).
// On rank 0 the two runs must agree: status, step method and step count equal; per step
// the Newton and Jacobian counts (the sparse step: the run's Newton and GMRES totals
// within 2%, see Compare), active_nodes and the accuracy verdict equal;
// dt_crit, the final displacement (mm x 1e-3), the force sums (N), the energies (N mm x
// 1e-3) and both accuracies within kSameTrajectory of their scales, the residuals and the
// penetration within kSameMeasures of the step's force and displacement scales.
#define CATCH_CONFIG_RUNNER
#include <petscsys.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <toml.hpp>

#include "contact/dynamics.hpp"
#include "contact/petsc/distributed_scene.hpp"
#include "contact/scene.hpp"
#include "distributed_scene_support.hpp"

namespace {

using contact::test::MaxAbs;
using contact::test::Rank;

// What the two runs may differ by. Converting an input rounds it by at most half an ulp
// (1.1e-16 relative), which perturbs the trajectory as any round-off does (both runs
// have the same partition: -petscpartitioner_type simple, so the sums over ranks add in
// the same order). Each step's contact problem is solved to solver.tolerance = 1e-10 of
// the step's scales F [N] and D [m]; a stopping test or threshold with a hidden unit (a
// number that is absolute in SI) is 1e3 or 1e6 times looser or tighter in mm-tonne-s, so
// it moves the answer by the tolerance or more, or changes an iteration count. Hence:
// dt_crit, the final displacement, the force sums, the energies and both accuracies
// within a tenth of the tolerance of their scales; the measured residuals and the
// penetration - round-off, or what the solver left below its tolerance, so no quantity of
// their own size - within the tolerance of F and D, as the comparisons with one process
// do (CheckSameMeasures); every iteration count and verdict equal. (Measured:
// docs/petsc-contact.md, "The same scene in SI and in mm-tonne-s on ranks".)
constexpr double kTolerance = 1e-10;  // solver.tolerance (the default)
constexpr double kSameTrajectory = 0.1 * kTolerance;
constexpr double kSameMeasures = kTolerance;
// The sparse step's Newton and GMRES counts over the run (see Compare).
constexpr double kSameSparseCounts = 0.02;

/// Exponents of a quantity's dimension in length, mass and time.
struct Dimension {
  int length = 0, mass = 0, time = 0;
};

/// Every numeric key a scene file may have (contact/src/scene/scene_file.cpp) and its
/// dimension; the others are strings or booleans, which no unit system changes.
const std::map<std::string, Dimension>& KeyDimensions() {
  static const std::map<std::string, Dimension> dimensions = {
      {"geometry.origin", {1, 0, 0}},           // m
      {"geometry.size", {1, 0, 0}},             // m
      {"geometry.cells", {}},                   // count
      {"geometry.fixed_components", {}},        // component index
      {"geometry.dimension", {}},               // 2 or 3
      {"material.young_modulus", {-1, 1, -2}},  // Pa = kg m^-1 s^-2
      {"material.poisson_ratio", {}},           //
      {"material.density", {-3, 1, 0}},         // kg m^-3
      {"material.thickness", {1, 0, 0}},        // m
      {"loads.body_force", {-2, 1, -2}},        // N m^-3 = kg m^-2 s^-2
      {"loads.traction", {-1, 1, -2}},          // Pa
      {"loads.ramp_time", {0, 0, 1}},           // s
      {"obstacle.normal", {}},                  // direction
      {"obstacle.offset", {1, 0, 0}},           // m
      {"obstacle.vertex", {1, 0, 0}},           // m
      {"obstacle.coefficient", {-1, 0, 0}},     // curvature, 1/m
      {"obstacle.center", {1, 0, 0}},           // m
      {"obstacle.radius", {1, 0, 0}},           // m
      {"obstacle.axis_point", {1, 0, 0}},       // m
      {"obstacle.axis_direction", {}},          // direction
      {"friction.coefficient", {}},             //
      {"time.dt", {0, 0, 1}},                   // s
      {"time.end_time", {0, 0, 1}},             // s
      {"time.initial_velocity", {1, 0, -1}},    // m/s
      {"solver.tolerance", {}},                 // relative
      {"solver.max_iterations", {}},            // count
      {"output.stress_times", {0, 0, 1}},       // s
      {"output.snapshot_every", {}},            // count
      {"output.checkpoint_every", {}},          // count
      {"output.marked_point", {1, 0, 0}}};      // m
  return dimensions;
}

/// A unit system by the size of its units of length, mass and time in SI's.
struct UnitSystem {
  double length = 1.0, mass = 1.0, time = 1.0;  ///< [m], [kg], [s]
  const char* name = "SI";
  /// The number a quantity of dimension d has in this system when it is 1 in SI.
  double Of(const Dimension& d) const {
    return std::pow(length, -d.length) * std::pow(mass, -d.mass) *
           std::pow(time, -d.time);
  }
};
const UnitSystem kMmTonneS{1e-3, 1e3, 1.0, "mm-tonne-s"};
constexpr Dimension kDisplacement{1, 0, 0}, kForce{1, 1, -2}, kEnergy{2, 1, -2},
    kTime{0, 0, 1};

/// `value` (a number or an array of numbers) of `key` expressed in `units`.
toml::value Convert(const std::string& key, const toml::value& value,
                    const UnitSystem& units) {
  if (value.is_array()) {
    toml::array converted;
    for (const toml::value& v : value.as_array())
      converted.push_back(Convert(key, v, units));
    return converted;
  }
  if (!value.is_floating() && !value.is_integer()) return value;  // strings, booleans
  const auto it = KeyDimensions().find(key);
  INFO("the scene key '" << key << "' has no dimension in KeyDimensions()");
  REQUIRE(it != KeyDimensions().end());
  const double factor = units.Of(it->second);
  if (value.is_integer() && factor == 1.0) return value;
  const double number =
      value.is_integer() ? static_cast<double>(value.as_integer()) : value.as_floating();
  return number * factor;
}

/// The scene text `si` with every numeric key expressed in `units`.
std::string ConvertScene(const std::string& si, const UnitSystem& units) {
  std::istringstream in(si);
  toml::value root = toml::parse(in, "si_scene");
  for (auto& [table, content] : root.as_table()) {
    if (!content.is_table()) {  // a top-level key (name)
      content = Convert(table, content, units);
      continue;
    }
    for (auto& [key, value] : content.as_table())
      value = Convert(table + "." + key, value, units);
  }
  return toml::format(root);
}

// A Tet4 box 0.2 m x 0.15 m x 0.1 m (E = 2e8 Pa, rho = 7800 kg/m^3) thrown down at
// 0.5 m/s onto a plane 0.05 mm below it, f_c = 0.3, with its weight, a sideways body
// force and a traction on its xmax side ramped up over 0.4 ms: it lands, slides and
// rings. %s: the mass ("lumped" / "consistent") and the step.
const char* const kSceneSI = R"(
name = "units-tet-box"
[geometry]
type = "box"
origin = [0.01, -0.02, 0.0]
size = [0.2, 0.15, 0.1]
cells = [4, 3, 2]
element = "tet4"
contact = ["zmin"]
load = ["xmax"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
mass = "%s"
[loads]
body_force = [20000.0, 8000.0, -76518.0]
traction = [-2.5e4, 0.0, -1e4]
history = "ramp"
ramp_time = 4e-4
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = -0.00005
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = 2e-5
end_time = %s
initial_state = "velocity"
initial_velocity = [0.1, 0.0, -0.5]
[solver]
step = "%s"
[output]
stress_times = [4e-4]
marked_point = [0.11, 0.055, 0.0]
)";

std::string SceneSI(const std::string& mass, const std::string& end_time,
                    const std::string& step) {
  char text[2048];
  std::snprintf(text, sizeof text, kSceneSI, mass.c_str(), end_time.c_str(),
                step.c_str());
  return text;
}

/// The worst relative differences between the SI run `si` and the run `other` in
/// `units` (converted back to SI), each of its quantity's scale.
struct Differences {
  double dt_crit = 0, u = 0, forces = 0, energies = 0, residuals = 0, penetration = 0,
         accuracies = 0;
  double WorstOfTrajectory() const {
    return std::max({dt_crit, u, forces, energies, accuracies});
  }
  double WorstOfMeasures() const { return std::max(residuals, penetration); }
};

Differences Compare(const contact::DynamicSummary& si,
                    const contact::DynamicSummary& other, const UnitSystem& units,
                    double tolerance, bool inexact_newton) {
  using R = contact::StepRecord;
  Differences d;
  CHECK(other.status == si.status);
  CHECK(other.step_method == si.step_method);
  CHECK(other.steps == si.steps);
  CHECK(other.inaccurate_steps == si.inaccurate_steps);
  if (inexact_newton) {
    // GMRES stops at a relative residual eta (the forcing term): a round-off difference
    // that flips one such test near a tie changes that step's Newton direction below the
    // tolerance and its counts by a few. PETSc's parallel MUMPS is not reproducible to
    // the bit (the same scene on the same partition, three runs: 259, 258 and 259 Newton
    // iterations, 1216, 1214 and 1216 GMRES iterations), so the sparse step's counts are
    // held to kSameSparseCounts of the run's totals.
    CHECK(std::abs(other.newton_iterations - si.newton_iterations) <=
          kSameSparseCounts * static_cast<double>(si.newton_iterations));
    CHECK(std::abs(other.krylov_iterations - si.krylov_iterations) <=
          kSameSparseCounts * static_cast<double>(si.krylov_iterations));
  } else {
    CHECK(other.newton_iterations == si.newton_iterations);
    CHECK(other.jacobian_evaluations == si.jacobian_evaluations);
  }
  REQUIRE(other.records.size() == si.records.size());
  REQUIRE(other.u.size() == si.u.size());
  d.dt_crit =
      std::abs(other.critical_time_step / units.Of(kTime) - si.critical_time_step) /
      si.critical_time_step;
  const double u_max = si.u.lpNorm<Eigen::Infinity>();
  REQUIRE(u_max > 1e-4);  // it moved [m]
  d.u = (other.u / units.Of(kDisplacement) - si.u).lpNorm<Eigen::Infinity>() / u_max;
  const double force_max = std::max(MaxAbs(si.records, &R::normal_force_sum),
                                    MaxAbs(si.records, &R::tangent_force_sum));
  REQUIRE(MaxAbs(si.records, &R::tangent_force_sum) > 0.0);  // it slid
  double energy_max = 0.0;
  for (double R::*e : {&R::kinetic, &R::strain, &R::external_work,
                       &R::normal_contact_work, &R::friction_dissipation})
    energy_max = std::max(energy_max, MaxAbs(si.records, e));
  for (size_t k = 0; k < si.records.size(); ++k) {
    const R &s = si.records[k], &o = other.records[k];
    INFO("step " << s.step);
    if (!inexact_newton) {
      CHECK(o.newton_iterations == s.newton_iterations);
      CHECK(o.jacobian_evaluations == s.jacobian_evaluations);
    }
    CHECK(o.active_nodes == s.active_nodes);
    CHECK(o.accurate == s.accurate);
    CHECK(o.solver_status == s.solver_status);
    const double to_force = 1.0 / units.Of(kForce), to_energy = 1.0 / units.Of(kEnergy),
                 to_length = 1.0 / units.Of(kDisplacement);
    for (double R::*f : {&R::normal_force_sum, &R::tangent_force_sum})
      d.forces = std::max(d.forces, std::abs(o.*f * to_force - s.*f) / force_max);
    for (double R::*e :
         {&R::kinetic, &R::strain, &R::external_work, &R::normal_contact_work,
          &R::friction_dissipation, &R::energy_balance_error})
      d.energies = std::max(d.energies, std::abs(o.*e * to_energy - s.*e) / energy_max);
    // The residuals are what the solver left (round-off or within the tolerance): of the
    // step's force scale F = force_accuracy / tolerance; the penetration of D.
    const double F = s.force_accuracy / tolerance,
                 D = s.displacement_accuracy / tolerance;
    for (double R::*r :
         {&R::equilibrium_residual, &R::complementarity_residual, &R::friction_residual})
      d.residuals = std::max(d.residuals, std::abs(o.*r * to_force - s.*r) / F);
    d.penetration = std::max(
        d.penetration, std::abs(o.max_penetration * to_length - s.max_penetration) / D);
    d.accuracies = std::max(
        {d.accuracies,
         std::abs(o.force_accuracy * to_force - s.force_accuracy) / s.force_accuracy,
         std::abs(o.displacement_accuracy * to_length - s.displacement_accuracy) /
             s.displacement_accuracy});
  }
  return d;
}

/// Runs `text` on the ranks of PETSC_COMM_WORLD (a file per rank, no output files).
contact::DynamicSummary Run(const std::string& text, const std::string& name) {
  contact::Scene scene = contact::test::LoadSceneText(text, "distributed_units", name);
  REQUIRE(contact::petsc::WhyNotDistributed(scene).empty());
  REQUIRE(scene.dynamics.ncp.tolerance == kTolerance);
  scene.output_directory.clear();
  return contact::petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, false).summary;
}

/// Sets (or with value nullptr clears) a PETSc option of the global database.
void SetPetscOption(const char* name, const char* value) {
  if (value)
    REQUIRE(PetscOptionsSetValue(nullptr, name, value) == 0);
  else
    REQUIRE(PetscOptionsClearValue(nullptr, name) == 0);
}

}  // namespace

TEST_CASE("a scene in SI and in mm-tonne-s converts every key by its dimension") {
  const std::string mm = ConvertScene(SceneSI("lumped", "8e-4", "explicit"), kMmTonneS);
  std::istringstream in(mm);
  const toml::value root = toml::parse(in, "mm_scene");
  // Independent spot checks of the conversion: E 2e8 Pa = 200 MPa, 7800 kg/m^3 =
  // 7.8e-9 t/mm^3, 76518 N/m^3 = 7.6518e-5 N/mm^3, 2.5e4 Pa = 0.025 MPa, 0.5 m/s =
  // 500 mm/s, -5e-5 m = -0.05 mm; times and counts unchanged.
  using toml::find;
  CHECK_THAT(find<double>(root, "material", "young_modulus"),
             Catch::Matchers::WithinRel(200.0, 1e-15));
  CHECK_THAT(find<double>(root, "material", "density"),
             Catch::Matchers::WithinRel(7.8e-9, 1e-15));
  CHECK_THAT(find<std::vector<double>>(root, "loads", "body_force")[2],
             Catch::Matchers::WithinRel(-7.6518e-5, 1e-15));
  CHECK_THAT(find<std::vector<double>>(root, "loads", "traction")[0],
             Catch::Matchers::WithinRel(-2.5e-2, 1e-15));
  CHECK_THAT(find<std::vector<double>>(root, "time", "initial_velocity")[2],
             Catch::Matchers::WithinRel(-500.0, 1e-15));
  CHECK_THAT(find<double>(root, "obstacle", "offset"),
             Catch::Matchers::WithinRel(-0.05, 1e-15));
  CHECK(find<double>(root, "time", "dt") == 2e-5);
  CHECK(find<std::vector<int>>(root, "geometry", "cells") == std::vector<int>{4, 3, 2});
  CHECK(find<std::string>(root, "solver", "step") == "explicit");
}

TEST_CASE("the same scene in SI and in mm-tonne-s gives the same answer on MPI ranks") {
  struct Variant {
    const char *name, *mass, *end_time, *step;
    contact::StepMethod method;
    bool cg = false;  // the solves with M by CG + Jacobi (-mass_ksp_type cg)
  };
  // 40 steps of 2e-5 s; the sparse step 16 (each of its products with W is a solve with
  // MUMPS's factor on 2 ranks: about 15 ms on the 2 shared cores).
  const Variant v = GENERATE(
      Variant{"explicit", "lumped", "8e-4", "explicit", contact::StepMethod::kExplicit},
      Variant{"condensed", "consistent", "8e-4", "condensed",
              contact::StepMethod::kCondensed},
      Variant{"condensed, CG", "consistent", "8e-4", "condensed",
              contact::StepMethod::kCondensed, true},
      Variant{"sparse", "consistent", "3.2e-4", "sparse", contact::StepMethod::kSparse});
  if (v.cg)
    SetPetscOption("-mass_ksp_type", "cg"), SetPetscOption("-mass_pc_type", "jacobi");
  const std::string si_text = SceneSI(v.mass, v.end_time, v.step);
  const contact::DynamicSummary si = Run(si_text, std::string(v.step) + "_si");
  const contact::DynamicSummary mm =
      Run(ConvertScene(si_text, kMmTonneS), std::string(v.step) + "_mm");
  if (v.cg)
    SetPetscOption("-mass_ksp_type", nullptr), SetPetscOption("-mass_pc_type", nullptr);
  INFO(v.name << ": SI: " << si.message << "; mm-tonne-s: " << mm.message);
  REQUIRE(si.status == contact::DynamicStatus::kCompleted);
  REQUIRE(si.step_method == v.method);
  if (Rank() != 0) return;  // (the records are rank 0's)
  REQUIRE(si.critical_time_step > 0.0);
  const Differences d =
      Compare(si, mm, kMmTonneS, kTolerance, v.method == contact::StepMethod::kSparse);
  std::printf(
      "%s: SI vs mm-tonne-s on the ranks: dt_crit %.2g, u %.2g, forces %.2g, energies "
      "%.2g, residuals %.2g F, penetration %.2g D, accuracies %.2g; %ld Newton "
      "iterations (%ld), %ld GMRES (%ld), %d steps, dt_crit %.6g s; %.1f s + %.1f s\n",
      v.name, d.dt_crit, d.u, d.forces, d.energies, d.residuals, d.penetration,
      d.accuracies, si.newton_iterations, mm.newton_iterations, si.krylov_iterations,
      mm.krylov_iterations, si.steps, si.critical_time_step, si.seconds, mm.seconds);
  CHECK(d.WorstOfTrajectory() <= kSameTrajectory);
  CHECK(d.WorstOfMeasures() <= kSameMeasures);
}

int main(int argc, char** argv) {
  // The same partition for both runs of a scene (PT-Scotch's can change from run to run,
  // and with it the order of the sums over ranks).
  return RunTestsOnRanks(argc, argv, {{"-petscpartitioner_type", "simple"}});
}
