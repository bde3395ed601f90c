// Errors of a scene run in the scene's own terms (contact/scene.hpp).
#pragma once

#include <cctype>
#include <stdexcept>
#include <string>

#include "contact/scene.hpp"

namespace contact::internal {

/// A library message without its leading C++ function name ("contact::RunDynamics: x" ->
/// "x"): the name helps a C++ caller, a scene-file user needs only what to change.
inline std::string WithoutFunctionName(const std::string& message) {
  const size_t colon = message.find(": ");
  if (colon == std::string::npos || colon == 0) return message;
  const std::string name = message.substr(0, colon);
  const size_t last = name.rfind("::");
  const size_t start = last == std::string::npos ? 0 : last + 2;
  if (start >= name.size() || !std::isupper(static_cast<unsigned char>(name[start])))
    return message;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != ':')
      return message;
  return message.substr(colon + 2);
}

/// Runs `build`; a std::invalid_argument from the mesh or the model (a missing group, an
/// empty contact set ...) becomes a SceneError that names the scene file and the mesh
/// file.
template <typename Build>
auto NamingTheScene(const Scene& scene, Build build) {
  try {
    return build();
  } catch (const SceneError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    const std::string mesh =
        scene.msh_file.empty() ? "" : " (mesh " + scene.msh_file + ")";
    throw SceneError(scene.source + mesh + ": " + WithoutFunctionName(e.what()));
  }
}

}  // namespace contact::internal
