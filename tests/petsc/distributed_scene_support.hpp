// What the tests of contact::petsc's scene runs share: the scene text as a file of this
// rank, and the comparison of a distributed run's step records with the serial run's.
#pragma once

#include <petscsys.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "catch_on_ranks.hpp"
#include "contact/dynamics.hpp"
#include "contact/petsc/distributed_scene.hpp"
#include "contact/scene.hpp"

namespace contact::test {

inline int Rank() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

// The scene text as a file of this rank (no rank reads another's file while it is
// written); prefix names the test executable.
inline Scene LoadSceneText(const std::string& text, const std::string& prefix,
                           const std::string& name) {
  const std::string path =
      prefix + "_" + name + "_rank" + std::to_string(Rank()) + ".toml";
  std::ofstream(path) << text;
  return LoadScene(path);
}

inline double MaxAbs(const std::vector<StepRecord>& records, double StepRecord::*field) {
  double m = 0.0;
  for (const StepRecord& r : records) m = std::max(m, std::abs(r.*field));
  return m;
}

// The accuracy and energy measures of every step (steps.csv's columns) and the summary's
// maxima: the same definitions as in one process, so equal up to the difference of the
// trajectories - within `same` of the quantity's scale: the energy columns of the
// largest energy of the run [J]; the residuals of the step's force scale F =
// force_accuracy / tolerance [N] (the residuals themselves are round-off of the explicit
// step's closed form, or what the contact solver left within its tolerance, so their own
// size is no scale); the penetration of D = displacement_accuracy / tolerance [m];
// active_nodes, accurate and the count of inaccurate steps equal. Returns the worst
// relative differences {energy, residuals, penetration, accuracies} (printed by the
// caller for the docs).
inline std::vector<double> CheckSameMeasures(const Scene& scene,
                                             const DynamicSummary& serial,
                                             const DynamicSummary& parallel,
                                             double same) {
  using R = StepRecord;
  double energy_scale = 0.0;
  for (double R::*field : {&R::kinetic, &R::strain, &R::external_work,
                           &R::normal_contact_work, &R::friction_dissipation})
    energy_scale = std::max(energy_scale, MaxAbs(serial.records, field));
  REQUIRE(energy_scale > 0.0);
  REQUIRE(parallel.records.size() == serial.records.size());
  const double tolerance = scene.dynamics.ncp.tolerance;
  double worst_energy = 0.0, worst_force = 0.0, worst_penetration = 0.0,
         worst_accuracy = 0.0;
  for (size_t k = 0; k < serial.records.size(); ++k) {
    const R &s = serial.records[k], &p = parallel.records[k];
    INFO("step " << s.step);
    for (double R::*field :
         {&R::kinetic, &R::strain, &R::external_work, &R::normal_contact_work,
          &R::friction_dissipation, &R::energy_balance_error})
      worst_energy = std::max(worst_energy, std::abs(p.*field - s.*field) / energy_scale);
    const double F = s.force_accuracy / tolerance,
                 D = s.displacement_accuracy / tolerance;
    for (double R::*field :
         {&R::equilibrium_residual, &R::complementarity_residual, &R::friction_residual})
      worst_force = std::max(worst_force, std::abs(p.*field - s.*field) / F);
    worst_penetration =
        std::max(worst_penetration, std::abs(p.max_penetration - s.max_penetration) / D);
    worst_accuracy = std::max(
        {worst_accuracy, std::abs(p.force_accuracy - s.force_accuracy) / s.force_accuracy,
         std::abs(p.displacement_accuracy - s.displacement_accuracy) /
             s.displacement_accuracy});
    CHECK(p.active_nodes == s.active_nodes);
    CHECK(p.accurate == s.accurate);
  }
  INFO("worst differences: energy "
       << worst_energy << " of " << energy_scale << " J, residuals " << worst_force
       << " F, penetration " << worst_penetration << " D, accuracies " << worst_accuracy);
  CHECK(worst_energy <= same);
  CHECK(worst_force <= same);
  CHECK(worst_penetration <= same);
  CHECK(worst_accuracy <= same);
  CHECK(parallel.inaccurate_steps == serial.inaccurate_steps);
  CHECK(std::abs(parallel.energy_balance_error - serial.energy_balance_error) <=
        same * energy_scale);
  for (double DynamicSummary::*field :
       {&DynamicSummary::max_equilibrium_residual,
        &DynamicSummary::max_complementarity_residual,
        &DynamicSummary::max_friction_residual, &DynamicSummary::energy_balance_error})
    CHECK(std::isfinite(parallel.*field));
  return {worst_energy, worst_force, worst_penetration, worst_accuracy};
}

// Lanczos stops when its Ritz value omega_max^2 moved by at most 1e-9 relative over two
// checks (kCriticalStepTolerance); dt_crit ~ 1 / omega_max is then within about half
// that of the exact value, checked with a margin of 20.
constexpr double kCriticalStepAccuracy = 1e-8;

// dt_crit estimated on the ranks (rank 0 has no serial K, nor a serial consistent M):
// the serial Lanczos estimate within `same` relative (the round-off of the reordered
// sums and of the other solver of M), and 2 / omega_max with omega_max^2 the largest
// eigenvalue of the pencil (K, M) of the serial model by Eigen's dense generalized
// eigensolver, within kCriticalStepAccuracy. Returns both relative differences (printed
// by the caller for the docs).
inline std::pair<double, double> CheckCriticalStep(const Scene& scene,
                                                   const DynamicSummary& serial,
                                                   const DynamicSummary& parallel,
                                                   double same) {
  const double dt_serial = serial.critical_time_step,
               dt_ranks = parallel.critical_time_step;
  REQUIRE(std::isfinite(dt_serial));
  const double to_serial = std::abs(dt_ranks - dt_serial) / dt_serial;
  const SceneModel built = BuildSceneModel(scene);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> pencil(
      Eigen::MatrixXd(built.model.K), Eigen::MatrixXd(built.model.M),
      Eigen::EigenvaluesOnly);
  REQUIRE(pencil.info() == Eigen::Success);
  const double dt_exact = 2.0 / std::sqrt(pencil.eigenvalues().maxCoeff());
  const double to_exact = std::abs(dt_ranks - dt_exact) / dt_exact;
  INFO("dt_crit on the ranks " << dt_ranks << " s, serial " << dt_serial << " s, dense "
                               << dt_exact << " s");
  CHECK(to_serial <= same);
  CHECK(to_exact <= kCriticalStepAccuracy);
  return {to_serial, to_exact};
}

/// Runs `scene` (its dt above dt_crit, not allowed) on the ranks and in one process
/// (rank 0): refused on every rank before any step, with the serial message.
inline void CheckRefusedAsSerial(const Scene& scene) {
  const SceneResult parallel = petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, false);
  CHECK(parallel.summary.status == DynamicStatus::kRefusedUnstable);
  CHECK(parallel.summary.records.empty());
  if (Rank() != 0) return;
  const SceneResult serial = RunScene(scene, false);
  REQUIRE(serial.summary.status == DynamicStatus::kRefusedUnstable);
  CHECK(parallel.summary.message == serial.summary.message);
  CHECK_THAT(parallel.summary.message, Catch::Matchers::Contains("time.allow_unstable"));
}

}  // namespace contact::test
