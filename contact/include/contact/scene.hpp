/// \file scene.hpp
/// A dynamic contact scene read from a TOML file: geometry (generated rectangle/box or a
/// gmsh .msh file), material, loads, obstacle, friction, time stepping, solver and
/// outputs. See examples/scenes/README.md for every key with its unit. Errors in a scene
/// (unknown keys, missing values, values out of range) throw SceneError naming the key.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_boundary.hpp"
#include "contact/contact_frames.hpp"
#include "contact/dof_map.hpp"
#include "contact/dynamics.hpp"
#include "contact/elastic_body.hpp"
#include "contact/kinematics.hpp"
#include "contact/material.hpp"
#include "contact/mesh_generation.hpp"
#include "contact/obstacle.hpp"

namespace contact {

/// Limits of a scene file, checked before it is parsed (they protect the machine: toml11
/// parses nested values recursively and would overflow the stack).
inline constexpr std::size_t kMaxSceneFileBytes = 1 << 20;  ///< 1 MiB
inline constexpr int kMaxSceneNesting =
    32;  ///< arrays and inline tables inside each other

class SceneError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

enum class LoadHistory {
  kConstant,  ///< f(t) = f for all t (also at t0)
  kStep,  ///< f(t0) = 0, f(t) = f for t > t0 (a load applied suddenly to a body at rest)
  kRamp,  ///< f(t) = min((t - t0) / ramp_time, 1) f
};
enum class MassKind { kConsistent, kLumped };

/// A prescribed history x(t) in dim components, linear between the knots (time[i],
/// value[i]) and constant before the first and after the last knot; its velocity is the
/// slope of the piece. Empty = none.
struct PiecewiseLinearHistory {
  std::vector<double> time;            ///< strictly increasing [s]
  std::vector<Eigen::VectorXd> value;  ///< one per time, dim components [m]
  bool empty() const { return time.empty(); }
  Eigen::VectorXd At(double t) const;  ///< x(t) [m]
};

/// output.checkpoint_every when the scene does not set it [steps].
inline constexpr int kDefaultCheckpointEvery = 100;

struct Scene {
  std::string name;
  std::string source;  ///< the file it was read from
  /// The file's text as read, with one line "# override: table.key = literal" per
  /// command-line override: what a checkpoint is compared with.
  std::string text;

  // Geometry: exactly one of rectangle / box / msh_file.
  int dim = 0;
  std::optional<RectangleMeshOptions> rectangle;
  std::optional<BoxMeshOptions> box;
  std::string msh_file;
  std::vector<int> fixed_components;  ///< components fixed on "fixed" (empty = all)
  /// geometry.groups: the mesh's own physical-group names merged into each role
  /// ("fixed", "load", "contact"); a role not listed keeps its own name.
  std::map<std::string, std::vector<std::string>> group_names;
  /// geometry.fixed_displacement: u_D(t) of the fixed components of "fixed" [m] (empty =
  /// held at 0).
  PiecewiseLinearHistory fixed_displacement;

  IsotropicMaterial material;
  RayleighDamping damping;  ///< material.damping: C = mass M + stiffness K
  PlaneSettings plane;
  MassKind mass = MassKind::kConsistent;
  /// material.model, material.kinematics, material.kinematics_tolerance.
  KinematicsOptions kinematics;

  Eigen::VectorXd body_force;  ///< [N/m^3], size dim
  Eigen::VectorXd traction;    ///< [N/m^2] on "load", size dim (empty = none)
  LoadHistory load_history = LoadHistory::kConstant;
  double ramp_time = 0.0;  ///< [s]

  std::shared_ptr<RigidObstacle> obstacle;
  /// obstacle.motion: its translation d(t) from its place in the scene [m] (empty = at
  /// rest); d(t_{k+1}) sets the gaps of step k -> k+1.
  PiecewiseLinearHistory obstacle_motion;
  NormalSource normal_source = NormalSource::kBody;
  double friction_coefficient = 0.0;

  DynamicOptions dynamics;  ///< dt, end_time, solver, ncp options, initial state ...
  Eigen::VectorXd initial_velocity;  ///< uniform [m/s] for initial_state = "velocity"

  std::string output_directory;  ///< empty = no files
  std::vector<double>
      stress_times;  ///< times at which the contact stresses are written [s]
  /// What LoadScene accepted but a user probably did not mean (a stress time past the
  /// end, end_time < dt), one sentence each naming the key; contact-sim prints them.
  std::vector<std::string> warnings;
  int snapshot_every = 0;  ///< VTK snapshot every n steps (0 = first and last only)
  /// contact-sim writes output_directory/checkpoint.bin every n steps (0 = only when
  /// interrupted) and on SIGINT / SIGTERM; RunScene with SceneRunOptions::resume
  /// continues from it.
  int checkpoint_every = kDefaultCheckpointEvery;
  std::optional<Eigen::VectorXd>
      marked_point;  ///< history of the contact node nearest to it
};

/// Values that replace those of the file: "table.key" -> a TOML literal, e.g.
/// {"time.dt", "1e-5"}, {"solver.ncp_function", "\"min\""} (contact-sim's --dt,
/// --ncp-function ...).
using SceneOverrides = std::vector<std::pair<std::string, std::string>>;

/// Reads and validates a scene file; relative paths inside are relative to the file.
/// Every number is range-checked (with its unit) before any conversion; the file itself
/// is refused beyond kMaxSceneFileBytes or kMaxSceneNesting. Throws SceneError with
/// "file:line: 'table.key' ..." on the first bad value.
Scene LoadScene(const std::string& path, const SceneOverrides& overrides = {});

/// The discretized scene: body, Dirichlet map, contact boundary and frames, and the model
/// on the free dofs that RunDynamics integrates (loads with their time history).
struct SceneModel {
  std::unique_ptr<ElasticBody> body;
  DofMap dofs;
  ContactBoundary boundary;
  ContactFrames frames;
  DynamicModel model;
  DynamicOptions
      options;  ///< scene.dynamics with friction and initial velocity filled in
};
SceneModel BuildSceneModel(const Scene& scene);
/// The same on a given mesh (the scene's geometry section is ignored), e.g. one from
/// MakeStructuredBoxMesh for millions of dofs.
SceneModel BuildSceneModel(const Scene& scene, Mesh mesh);

/// The load f(t) [N] on the free dofs of a built scene for the body force `body_force`
/// [N/m^3] (size dim) with the scene's traction and load history: what BuildSceneModel
/// puts into model.load for scene.body_force (the 'fixed' group holds its components at
/// 0).
std::function<void(double, Eigen::VectorXd*)> SceneLoad(
    const Scene& scene, const SceneModel& built, const Eigen::VectorXd& body_force);

/// What a run produced.
struct SceneResult {
  DynamicSummary summary;
  int num_dofs = 0, num_free_dofs = 0, num_contact_nodes = 0, num_elements = 0;
  int marked_node = -1;  ///< mesh node of the history output, -1 if none
  int resumed_from_step =
      -1;  ///< the checkpoint's step of a resumed run, -1 if not resumed
  int checkpoint_step =
      -1;  ///< the step of the last checkpoint this run wrote, -1 if none
  std::vector<std::string> files_written;
};

/// How RunScene runs.
struct SceneRunOptions {
  bool progress = false;  ///< progress lines on stderr
  /// Continue from output_directory/checkpoint.bin (kCheckpointFile): the state of its
  /// step, the CSVs cut back to their rows up to that step and appended to, the VTK
  /// series continued. Throws CheckpointError (contact/simulation.hpp) when there is no
  /// checkpoint, it is corrupt or truncated, or it is of another scene (text with
  /// overrides, mesh file) or model, and when an output file is shorter than the
  /// checkpoint recorded.
  bool resume = false;
};

/// The checkpoint's name in the output directory.
inline constexpr const char* kCheckpointFile = "checkpoint.bin";

/// Builds the model (mesh, K, M, loads, contact frames), runs the time loop and writes
/// the outputs into scene.output_directory: steps.csv (one row per step),
/// contact_stress.csv (per contact node at the stress times and the end),
/// node_history.csv (marked node), VTK snapshots, and checkpoint.bin every
/// scene.checkpoint_every steps and when the run is interrupted
/// (DynamicOptions::stop_requested).
SceneResult RunScene(const Scene& scene, const SceneRunOptions& options);
/// RunScene(scene, {progress}).
SceneResult RunScene(const Scene& scene, bool progress);

}  // namespace contact
