/// \file bodies_scene.hpp
/// Scene files with several bodies: `[[bodies]]` tables (each with the `geometry`,
/// `material` and `loads` tables of a one-body scene, plus `name`, `velocity` and
/// `fixed_displacement`) and `[[contact]]` pairs of body surfaces, run statically or by
/// central differences (docs/several-bodies.md has the keys and units).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace contact {

struct BodiesSceneSummary {
  std::string status = "not-run";  ///< "completed" or "solver-failure"
  std::string message = "not run yet";
  std::string analysis;  ///< "static" or "dynamic"
  int steps = 0;         ///< time steps (0 for static)
  long newton_iterations = 0;
  int constraints = 0;                  ///< mortar constraints (covered slave nodes)
  std::vector<std::string> pair_names;  ///< "slave/group -> master/group"
  std::vector<double> pair_force;       ///< force of each pair at the end [N]
  double max_penetration = 0.0;         ///< [m]
};

/// True if the TOML file at `path` has a top-level `bodies` array of tables. Throws
/// SceneError if the file cannot be read or parsed.
bool IsBodiesScene(const std::string& path);

/// Reads and runs the scene. Writes into `output_directory` if given (none if empty),
/// else into the scene's [output] directory (relative to the scene file; none if unset):
/// pairs.csv (one row per constraint at the end: pair, body, node, x, y, gap [m], force
/// [N], pressure [Pa]), steps.csv (dynamic: time and force of each pair per step,
/// energy [J], Newton iterations) and solution.pvd with one .vtu per body and snapshot.
/// Throws SceneError naming the key for invalid or unsupported input (friction > 0,
/// rigid obstacles, 3D bodies, overlapping bodies, missing bodies or groups).
BodiesSceneSummary RunBodiesScene(
    const std::string& path,
    const std::optional<std::string>& output_directory = std::nullopt);

}  // namespace contact
