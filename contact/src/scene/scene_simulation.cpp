// The scene side of contact::Simulation (contact/simulation.hpp): the built scene it
// owns, the body force and the obstacle's translation that may change between steps.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "checkpoint.hpp"
#include "contact/scene.hpp"
#include "contact/simulation.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_features.hpp"

namespace contact {

struct Simulation::SceneData {
  Scene scene;
  SceneModel built;
  Eigen::VectorXd body_force;   // [N/m^3]
  Eigen::VectorXd translation;  // of the obstacle from its place in the scene [m]
  std::uint64_t mesh_hash =
      0;  // Fnv1a of the gmsh file's bytes as read (0: generated mesh)
};

std::shared_ptr<Simulation::SceneData> Simulation::BuildSceneData(const Scene& scene) {
  auto data = std::make_shared<Simulation::SceneData>();
  data->scene = scene;
  data->built = BuildSceneModel(scene);
  data->body_force = scene.body_force;
  data->translation = Eigen::VectorXd::Zero(scene.dim);
  if (!scene.msh_file.empty()) {
    std::ifstream mesh(scene.msh_file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(mesh)),
                            std::istreambuf_iterator<char>());
    data->mesh_hash = internal::Fnv1a(bytes);
  }
  return data;
}

namespace {

std::string Hex(std::uint64_t v) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(v));
  return buffer;
}

/// "line N: 'saved' in the checkpoint, 'now' now" for the first line that differs.
std::string FirstDifference(const std::string& saved, const std::string& now) {
  std::istringstream a(saved), b(now);
  std::string x, y;
  for (int line = 1;; ++line) {
    const bool more_a = static_cast<bool>(std::getline(a, x)),
               more_b = static_cast<bool>(std::getline(b, y));
    if (!more_a && !more_b) return "the texts differ";
    if (!more_a) x = "(end of file)";
    if (!more_b) y = "(end of file)";
    if (x != y || !more_a || !more_b)
      return "first difference at line " + std::to_string(line) + ": '" + x +
             "' in the checkpoint, '" + y + "' now";
  }
}

/// Throws std::invalid_argument unless v has `size` finite entries.
void CheckVector(const char* what, const char* unit, const Eigen::VectorXd& v, int size) {
  if (v.size() != size || !v.allFinite())
    throw std::invalid_argument(std::string("contact::Simulation: ") + what +
                                " must be " + std::to_string(size) + " finite numbers [" +
                                unit + "], got " + std::to_string(v.size()) +
                                (v.allFinite() ? "" : " with a NaN or inf"));
}

}  // namespace

void Simulation::SaveScene(internal::CheckpointData* data) const {
  internal::CheckpointIdentity& id = data->identity;
  id.scene_source = scene_->scene.source;
  id.scene_text = scene_->scene.text;
  id.scene_hash = internal::Fnv1a(id.scene_text);
  id.mesh_file = scene_->scene.msh_file;
  id.mesh_hash = scene_->mesh_hash;
  data->has_scene = true;
  data->body_force = scene_->body_force;
  data->obstacle_translation = scene_->translation;
}

void Simulation::CheckScene(const internal::CheckpointData& data) const {
  const internal::CheckpointIdentity& id = data.identity;
  const Scene& scene = scene_->scene;
  if (!data.has_scene)
    throw CheckpointError("it is of a Simulation of a model, not of a scene");
  const std::uint64_t scene_hash = internal::Fnv1a(scene.text);
  if (id.scene_hash != scene_hash || id.scene_text != scene.text)
    throw CheckpointError("the scene changed since the checkpoint: scene text hash " +
                          Hex(id.scene_hash) + " (" + id.scene_source +
                          " with its overrides, in the checkpoint) vs " +
                          Hex(scene_hash) + " (" + scene.source + " now); " +
                          FirstDifference(id.scene_text, scene.text));
  if (id.mesh_hash != scene_->mesh_hash)
    throw CheckpointError("the mesh file changed since the checkpoint: " + id.mesh_file +
                          " hash " + Hex(id.mesh_hash) + " in the checkpoint, " +
                          scene.msh_file + " hash " + Hex(scene_->mesh_hash) + " now");
  if (data.body_force.size() != scene.dim ||
      data.obstacle_translation.size() != scene.dim || !data.body_force.allFinite() ||
      !data.obstacle_translation.allFinite())
    throw CheckpointError("its body force or obstacle translation is not " +
                          std::to_string(scene.dim) + " finite numbers");
}

void Simulation::RestoreScene(const internal::CheckpointData& data) {
  if (data.body_force != scene_->body_force) SetBodyForce(data.body_force);
  scene_->translation =
      data.obstacle_translation;  // (the gaps it gave are in the checkpoint)
}

Simulation::Simulation(const Scene& scene) : Simulation(BuildSceneData(scene)) {}

// (A std::invalid_argument of the model or the options, e.g. the explicit step without a
// lumped mass, names the scene as RunScene's does.)
Simulation::Simulation(std::shared_ptr<SceneData> scene) try
    : Simulation(scene, scene->built.model, scene->built.options) {
} catch (const SceneError&) {
  throw;
} catch (const std::invalid_argument&) {
  internal::NamingTheScene(scene->scene,
                           []() -> int { throw; });  // rethrown with the scene's name
}

Simulation::SceneData& Simulation::RequireScene(const char* what) const {
  if (!scene_)
    throw std::logic_error(
        std::string("contact::Simulation::") + what +
        ": only a Simulation of a scene has one (use SetLoad / SetContactGaps)");
  return *scene_;
}

const SceneModel& Simulation::scene_model() const {
  return RequireScene("scene_model").built;
}

void Simulation::SetBodyForce(const Eigen::VectorXd& body_force) {
  SceneData& data = RequireScene("SetBodyForce");
  CheckVector("the body force", "N/m^3", body_force, data.scene.dim);
  SetLoad(SceneLoad(data.scene, data.built, body_force));
  data.body_force = body_force;
}

void Simulation::MoveObstacle(const Eigen::VectorXd& translation) {
  SceneData& data = RequireScene("MoveObstacle");
  CheckVector("the obstacle translation", "m", translation, data.scene.dim);
  const SceneModel& b = data.built;
  SetContactGaps(ObstacleGaps(b.body->mesh(), b.boundary, b.frames, *data.scene.obstacle,
                              data.scene.normal_source, translation));
  data.translation = translation;
}

const Eigen::VectorXd& Simulation::body_force() const {
  return RequireScene("body_force").body_force;
}

const Eigen::VectorXd& Simulation::obstacle_translation() const {
  return RequireScene("obstacle_translation").translation;
}

void Simulation::ApplySceneHistories() {
  const Scene& scene = scene_->scene;
  const double t_next = options().start_time + (step_index() + 1) * options().dt;
  // u_D(t_{k+1}) at the fixed nodes of the outputs (the load has it already).
  internal::SetFixedDisplacement(scene, t_next, &scene_->built.dofs);
  if (scene.obstacle_motion.empty()) return;
  // d(t_{k+1}): the gaps of step k -> k+1, and the obstacle's motion over that step.
  const Eigen::VectorXd d = scene.obstacle_motion.At(t_next);
  const Eigen::VectorXd increment = d - scene_->translation;
  MoveObstacle(d);
  AddObstacleStep(increment);
}

Eigen::VectorXd Simulation::nodal_displacement() const {
  return RequireScene("nodal_displacement").built.dofs.Expand(displacement());
}

Eigen::VectorXd Simulation::nodal_velocity() const {
  return RequireScene("nodal_velocity").built.dofs.ExpandHomogeneous(velocity());
}

}  // namespace contact
