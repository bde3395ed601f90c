/// \file simulation.hpp
/// The central-difference integrator of contact/dynamics.hpp, one step at a time: construct
/// it from a model (or a scene), call Step(n), look at the state, change the load or move
/// the obstacle, step again. RunDynamics is a loop over Step, so a run stepped by hand
/// gives the same numbers bit for bit.
///
/// The state between steps k-1 -> k and k -> k+1 (what the next step reads; what a
/// checkpoint would have to save, docs/python.md "Step by step"): u^k, u^{k-1} [m], the
/// normal forces lambda^k [N] (Tresca bounds of the lagged friction), the carried products
/// K u^k [N] and M (u^k - u^{k-1}) [kg m], the previous contact force |r^k|_inf [N] (a scale
/// of the next step), the start guess du = u^k - u^{k-1} [m], the step method's warm start
/// (the previous friction forces), the energy accumulators (external and contact work), the
/// summary so far, the contact gaps s_c [m] and the load function.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "contact/dynamics.hpp"
#include "contact/vtk_writer.hpp"

namespace contact {

struct Scene;
struct SceneModel;

/// Where a Simulation stands.
enum class SimulationState {
  kRunning,   ///< steps are left before end_time
  kFinished,  ///< end_time reached; summary().status is kCompleted or kAccuracyNotReached
  kFailed,    ///< stopped early (solver failure, energy blow-up, refused unstable dt, static
              ///< initial state not solved): summary().status and message say why
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
  std::vector<ContactState> state;  ///< open, stick or slip (ClassifyContact, as the .vtu)
};

class Simulation {
 public:
  /// Validates as RunDynamics (std::invalid_argument on inconsistent input), estimates the
  /// critical step and sets the initial state. A refused dt or a failed static initial
  /// state leaves state() == kFailed with the summary saying why. `model` must outlive the
  /// Simulation (it is not copied: K and M are the largest objects of a run).
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
  double time() const;    ///< t_k [s] of the current state (records().back().time after a step)
  int step_index() const;  ///< k: steps taken
  int num_steps() const;  ///< steps from start_time to end_time
  /// u^k on the free dofs [m].
  const Eigen::VectorXd& displacement() const;
  /// (u^k - u^{k-1}) / dt on the free dofs [m/s]: the mean velocity of the last step (as the
  /// .vtu's velocity); before the first step the one of u^{-1}.
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
  /// for a moved obstacle; the next step's non-penetration is gap_c = s_c - n_c . u_c >= 0.
  /// The frames (normals, tangents) are kept: the small-displacement setting of
  /// contact_frames.hpp. Throws std::invalid_argument on bad input.
  void SetContactGaps(const Eigen::VectorXd& gaps);
  const Eigen::VectorXd& contact_gaps() const;  ///< s_c [m]

  /// Scene simulations only (std::logic_error otherwise):
  /// the built scene (mesh, dofs, frames);
  const SceneModel& scene_model() const;
  /// the body force b [N/m^3] (size dim, finite) with the scene's traction and load history
  /// from the next step on;
  void SetBodyForce(const Eigen::VectorXd& body_force);
  const Eigen::VectorXd& body_force() const;  ///< [N/m^3]
  /// the obstacle translated rigidly to `translation` [m] from its position in the scene
  /// file (size dim, finite; absolute, not an increment): the gaps are recomputed from the
  /// translated obstacle as MakeContactFrames computes them (ObstacleGaps).
  void MoveObstacle(const Eigen::VectorXd& translation);
  const Eigen::VectorXd& obstacle_translation() const;  ///< [m]
  /// u^k of every dof (constrained ones at their values) [m], node-major.
  Eigen::VectorXd nodal_displacement() const;
  /// velocity() on every dof (0 at constrained ones) [m/s], node-major.
  Eigen::VectorXd nodal_velocity() const;

 private:
  /// (Moves the summary out at the end instead of copying its records.)
  friend DynamicSummary RunDynamics(const DynamicModel& model, const DynamicOptions& options);
  struct Impl;
  struct SceneData;  // scene/scene_simulation.cpp
  static std::shared_ptr<SceneData> BuildSceneData(const Scene& scene);
  explicit Simulation(std::shared_ptr<SceneData> scene);
  Simulation(std::shared_ptr<SceneData> scene, const DynamicModel& model, DynamicOptions options);
  SceneData& RequireScene(const char* what) const;
  std::shared_ptr<SceneData> scene_;  // before impl_: impl_ refers to its model
  std::unique_ptr<Impl> impl_;
};

}  // namespace contact
