// The per-body tables of a scene with several bodies, read by the one-body readers of
// scene_file.cpp.
#pragma once

#include <string>

#include "contact/scene.hpp"
#include "scene/toml_table.hpp"

namespace contact::internal {

/// The scene file parsed with the checks of LoadScene (size, nesting depth, TOML syntax),
/// without overrides.
toml::value ParseSceneFile(const std::string& path);

/// Reads the `geometry`, `material` and (optional) `loads` tables of `body` into *s, with
/// the checks of a one-body scene; `base` is the scene file's directory.
void ReadBodyTables(const Table& body, const std::string& base, Scene* s);

}  // namespace contact::internal
