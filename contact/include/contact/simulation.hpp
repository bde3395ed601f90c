/// \file simulation.hpp
/// The central-difference integrator of contact/dynamics.hpp, one step at a time:
/// construct it from a model (or a scene), call Step(n), look at the state, change the
/// load or move the obstacle, step again. RunDynamics is a loop over Step, so a run
/// stepped by hand gives the same numbers bit for bit.
///
/// The state between steps k-1 -> k and k -> k+1 (what the next step reads; what a
/// checkpoint would have to save, docs/python.md "Step by step"): u^k, u^{k-1} [m], the
/// normal forces lambda^k [N] (Tresca bounds of the lagged friction), the carried
/// products K u^k [N] and M (u^k - u^{k-1}) [kg m], the previous contact force |r^k|_inf
/// [N] (a scale of the next step), the start guess du = u^k - u^{k-1} [m], the step
/// method's warm start (the previous friction forces), the energy accumulators (external
/// and contact work), the summary so far, the contact gaps s_c [m] and the load function.
///
/// Checkpoints: SaveCheckpoint writes all of this but the load function (a scene
/// Simulation's load is rebuilt from the saved body force; a model's must be set again
/// with SetLoad) to one binary file, and LoadCheckpoint / Load continue from it: the
/// steps after it are the same as those of the run that was never stopped, bit for bit
/// (the state is stored to the bit and every step method is deterministic). The file
/// (format in contact/src/checkpoint.hpp, version 1): magic "NCPCKPT\n", format version,
/// byte-order mark, payload length, payload, FNV-1a 64 checksum of the payload. The
/// payload holds the run's identity (the scene file's text with its command-line
/// overrides and its hash, the gmsh mesh file's name and hash, a fingerprint of K, M, the
/// contact nodes and the options that shape the trajectory, the sizes), the step index k,
/// u^k, u^{k-1}, lambda^k, K u^k, M (u^k - u^{k-1}), the start guess, |r^k|_inf, the last
/// step's contact result, s_c, the energy accumulators, the step method's warm start, the
/// summary with every step's record, the body force and obstacle translation, and the
/// caller's application data.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/dynamics.hpp"
#include "contact/vtk_writer.hpp"

namespace contact {

struct Scene;
struct SceneModel;
namespace internal {
struct CheckpointData;
}

/// A checkpoint that cannot be used: missing, unreadable, truncated, corrupt (checksum),
/// of another format version, or of another run (another scene text, mesh file, model or
/// step method: the message names what differs, with both hashes).
class CheckpointError : public std::runtime_error {
 public:
  explicit CheckpointError(const std::string& message);
};

/// Where a Simulation stands.
enum class SimulationState {
  kRunning,   ///< steps are left before end_time
  kFinished,  ///< end_time reached; summary().status is kCompleted or kAccuracyNotReached
  kFailed,    ///< stopped early (solver failure, energy blow-up, refused unstable dt,
              ///< static initial state not solved): summary().status and message say why
};
const char* ToString(SimulationState s);

/// The contact state of every contact node after the last step (before the first: the
/// initial state - the static equilibrium's normal forces, or NaN forces for a prescribed
/// start, whose contact forces are known only after a step). Per contact node c, in the
/// order of DynamicModel::contact_nodes.
struct ContactNodeStates {
  Eigen::VectorXd normal_force;    ///< lambda_c >= 0 [N] (on the body, against n_c)
  Eigen::MatrixXd friction_force;  ///< (dim - 1) x N_c along t1 (, t2) [N]
  Eigen::VectorXd gap;             ///< gap_c = s_c - n_c . u_c [m] (< 0: penetration)
  std::vector<ContactState>
      state;  ///< open, stick or slip (ClassifyContact, as the .vtu)
};

class Simulation {
 public:
  /// Validates as RunDynamics (std::invalid_argument on inconsistent input), estimates
  /// the critical step and sets the initial state. A refused dt or a failed static
  /// initial state leaves state() == kFailed with the summary saying why. `model` must
  /// outlive the Simulation (it is not copied: K and M are the largest objects of a run).
  Simulation(const DynamicModel& model, DynamicOptions options);
  /// The scene's model built as BuildSceneModel does (owned by the Simulation); its
  /// DynamicOptions are the scene's. Throws SceneError / std::invalid_argument.
  explicit Simulation(const Scene& scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Takes up to n steps (n >= 0; std::invalid_argument otherwise), stopping at end_time
  /// or at the first failure. Returns state().
  SimulationState Step(long n = 1);

  SimulationState state() const;
  double time()
      const;  ///< t_k [s] of the current state (records().back().time after a step)
  int step_index() const;  ///< k: steps taken
  int num_steps() const;   ///< steps from start_time to end_time
  /// u^k on the free dofs [m].
  const Eigen::VectorXd& displacement() const;
  /// (u^k - u^{k-1}) / dt on the free dofs [m/s]: the mean velocity of the last step (as
  /// the .vtu's velocity); before the first step the one of u^{-1}.
  Eigen::VectorXd velocity() const;
  /// Forces [N], gaps [m] and open/stick/slip per contact node (see ContactNodeStates).
  ContactNodeStates contact() const;
  /// The summary so far: records, counts, maxima; status kNotRun while running.
  const DynamicSummary& summary() const;
  const std::vector<StepRecord>& records() const;
  const DynamicModel& model() const;
  const DynamicOptions& options() const;

  /// Replaces the load f(t) [N] on the free dofs used from the next step on (the step
  /// k -> k+1 evaluates f(t_k)).
  void SetLoad(std::function<void(double t, Eigen::VectorXd* f)> load);
  /// Replaces the initial gaps s_c [m] of the contact nodes (one per node, finite), e.g.
  /// for a moved obstacle; the next step's non-penetration is gap_c = s_c - n_c . u_c >=
  /// 0. The frames (normals, tangents) are kept: the small-displacement setting of
  /// contact_frames.hpp. Throws std::invalid_argument on bad input.
  void SetContactGaps(const Eigen::VectorXd& gaps);
  const Eigen::VectorXd& contact_gaps() const;  ///< s_c [m]

  /// Writes the state after step k (step_index()) to `path`, atomically (path.partial
  /// renamed when complete; a failed write throws ncp::OutputError and leaves an older
  /// checkpoint at `path` as it was). application_data: bytes stored with it and returned
  /// by LoadCheckpoint (contact-sim keeps the positions of its output files there).
  /// Throws std::logic_error for a refused run (no state) or one that failed (its state
  /// is not a state to continue from).
  void SaveCheckpoint(const std::string& path,
                      const std::string& application_data = {}) const;
  /// Replaces the state with the one of the checkpoint at `path` and returns its
  /// application data. The checkpoint must be of the same run: for a scene Simulation the
  /// same scene text (with the same overrides) and mesh file bytes, for every Simulation
  /// the same model fingerprint, sizes and step method - otherwise CheckpointError says
  /// what differs and the state is unchanged. A scene Simulation gets the saved body
  /// force and obstacle translation; a model Simulation keeps its load function (set it
  /// with SetLoad).
  std::string LoadCheckpoint(const std::string& path);
  /// A Simulation of `scene` continued from the checkpoint at `path` (Simulation(scene),
  /// then LoadCheckpoint). Throws CheckpointError, SceneError, std::invalid_argument.
  static std::unique_ptr<Simulation> Load(const std::string& path, const Scene& scene);

  /// Scene simulations only (std::logic_error otherwise):
  /// the built scene (mesh, dofs, frames);
  const SceneModel& scene_model() const;
  /// the body force b [N/m^3] (size dim, finite) with the scene's traction and load
  /// history from the next step on;
  void SetBodyForce(const Eigen::VectorXd& body_force);
  const Eigen::VectorXd& body_force() const;  ///< [N/m^3]
  /// the obstacle translated rigidly to `translation` [m] from its position in the scene
  /// file (size dim, finite; absolute, not an increment): the gaps are recomputed from
  /// the translated obstacle as MakeContactFrames computes them (ObstacleGaps). The
  /// friction slip stays the body's own; a scene's obstacle.motion (Scene::
  /// obstacle_motion) moves it before every step with the slip relative to it.
  void MoveObstacle(const Eigen::VectorXd& translation);
  const Eigen::VectorXd& obstacle_translation() const;  ///< [m]
  /// u^k of every dof (constrained ones at their values) [m], node-major.
  Eigen::VectorXd nodal_displacement() const;
  /// velocity() on every dof (0 at constrained ones) [m/s], node-major.
  Eigen::VectorXd nodal_velocity() const;

 private:
  /// (Moves the summary out at the end instead of copying its records.)
  friend DynamicSummary RunDynamics(const DynamicModel& model,
                                    const DynamicOptions& options);
  struct Impl;
  struct SceneData;  // scene/scene_simulation.cpp
  static std::shared_ptr<SceneData> BuildSceneData(const Scene& scene);
  explicit Simulation(std::shared_ptr<SceneData> scene);
  Simulation(std::shared_ptr<SceneData> scene, const DynamicModel& model,
             DynamicOptions options);
  SceneData& RequireScene(const char* what) const;
  /// The scene's prescribed obstacle.motion at the time of the next step, before it is
  /// taken (scene_simulation.cpp).
  void ApplySceneHistories();
  /// Adds to the obstacle's translation over the coming step [m] (dynamics.cpp).
  void AddObstacleStep(const Eigen::VectorXd& increment);
  /// The scene's part of a checkpoint (identity, body force, translation):
  /// scene_simulation.cpp.
  void SaveScene(internal::CheckpointData* data) const;
  /// Checks the scene's identity against the checkpoint's (CheckpointError naming what
  /// differs) without changing anything.
  void CheckScene(const internal::CheckpointData& data) const;
  void RestoreScene(const internal::CheckpointData& data);
  std::shared_ptr<SceneData> scene_;  // before impl_: impl_ refers to its model
  std::unique_ptr<Impl> impl_;
};

}  // namespace contact
