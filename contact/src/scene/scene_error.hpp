// Errors of a scene run in the scene's own terms (contact/scene.hpp).
#pragma once

#include <stdexcept>
#include <string>

#include "contact/scene.hpp"

namespace contact::internal {

/// Runs `build`; a std::invalid_argument from the mesh or the model (a missing group, an
/// empty contact set ...) becomes a SceneError that names the scene file and the mesh file.
template <typename Build>
auto NamingTheScene(const Scene& scene, Build build) {
  try {
    return build();
  } catch (const SceneError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    const std::string mesh = scene.msh_file.empty() ? "" : " (mesh " + scene.msh_file + ")";
    throw SceneError(scene.source + mesh + ": " + e.what());
  }
}

}  // namespace contact::internal
