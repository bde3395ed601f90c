// The scene side of contact::Simulation (contact/simulation.hpp): the built scene it owns,
// the body force and the obstacle's translation that may change between steps.
#include <cmath>
#include <stdexcept>

#include "contact/scene.hpp"
#include "contact/simulation.hpp"
#include "scene/scene_error.hpp"

namespace contact {

struct Simulation::SceneData {
  Scene scene;
  SceneModel built;
  Eigen::VectorXd body_force;   // [N/m^3]
  Eigen::VectorXd translation;  // of the obstacle from its place in the scene [m]
};

std::shared_ptr<Simulation::SceneData> Simulation::BuildSceneData(const Scene& scene) {
  auto data = std::make_shared<Simulation::SceneData>();
  data->scene = scene;
  data->built = BuildSceneModel(scene);
  data->body_force = scene.body_force;
  data->translation = Eigen::VectorXd::Zero(scene.dim);
  return data;
}

namespace {

/// Throws std::invalid_argument unless v has `size` finite entries.
void CheckVector(const char* what, const char* unit, const Eigen::VectorXd& v, int size) {
  if (v.size() != size || !v.allFinite())
    throw std::invalid_argument(std::string("contact::Simulation: ") + what + " must be " +
                                std::to_string(size) + " finite numbers [" + unit + "], got " +
                                std::to_string(v.size()) + (v.allFinite() ? "" : " with a NaN or inf"));
}

}  // namespace

Simulation::Simulation(const Scene& scene) : Simulation(BuildSceneData(scene)) {}

// (A std::invalid_argument of the model or the options, e.g. the explicit step without a
// lumped mass, names the scene as RunScene's does.)
Simulation::Simulation(std::shared_ptr<SceneData> scene) try
    : Simulation(scene, scene->built.model, scene->built.options) {
} catch (const SceneError&) {
  throw;
} catch (const std::invalid_argument&) {
  internal::NamingTheScene(scene->scene, []() -> int { throw; });  // rethrown with the scene's name
}

Simulation::SceneData& Simulation::RequireScene(const char* what) const {
  if (!scene_)
    throw std::logic_error(std::string("contact::Simulation::") + what +
                           ": only a Simulation of a scene has one (use SetLoad / SetContactGaps)");
  return *scene_;
}

const SceneModel& Simulation::scene_model() const { return RequireScene("scene_model").built; }

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

const Eigen::VectorXd& Simulation::body_force() const { return RequireScene("body_force").body_force; }

const Eigen::VectorXd& Simulation::obstacle_translation() const {
  return RequireScene("obstacle_translation").translation;
}

Eigen::VectorXd Simulation::nodal_displacement() const {
  return RequireScene("nodal_displacement").built.dofs.Expand(displacement());
}

Eigen::VectorXd Simulation::nodal_velocity() const {
  return RequireScene("nodal_velocity").built.dofs.ExpandHomogeneous(velocity());
}

}  // namespace contact
