// Scene features beyond the basic tables (scene_features.cpp): Rayleigh damping
// (material.damping), the obstacle's prescribed motion (obstacle.motion), the mesh's own
// group names for the roles (geometry.groups) and a prescribed displacement history of
// the fixed group (geometry.fixed_displacement).
#pragma once

#include <functional>
#include <string>

#include "contact/scene.hpp"
#include "scene/toml_table.hpp"

namespace contact::internal {

/// material.damping = {mass = a [1/s], stiffness = b [s]} into scene->damping.
void ReadDamping(const Table& material, Scene* scene);

/// A history table {time = [...] [s], x = [...], y = [...] (, z = [...]) [m]} of `key`
/// in `table` (empty if absent): equal lengths, times strictly increasing and >= 0.
PiecewiseLinearHistory ReadHistory(const Table& table, const std::string& key, int dim);

/// geometry.groups = {fixed = "name" or [...], load = ..., contact = ...} (.msh only).
void ReadGroupNames(const Table& geometry, Scene* scene);

/// The checks across tables once the scene is read: obstacle.motion starts at the
/// obstacle's place (0 at its first time) and, with friction, needs the explicit step;
/// geometry.fixed_displacement needs a lumped mass. Throws SceneError naming the keys.
void CheckSceneFeatures(const Scene& scene);

/// The mesh with the groups of scene.group_names merged into their roles; SceneError for
/// a name the mesh does not have (listing the names it has).
Mesh MapMeshGroups(const Scene& scene, Mesh mesh);

/// The prescribed values of `dofs` set to u_D(t) of geometry.fixed_displacement (what
/// the outputs show at the fixed nodes); nothing without it.
void SetFixedDisplacement(const Scene& scene, double t, DofMap* dofs);

/// The load f(t) with the equivalent nodal force of the fixed group's displacement
/// u_D(t) (geometry.fixed_displacement): f(t) - K_FD u_D(t) (a lumped M has no M_FD).
std::function<void(double, Eigen::VectorXd*)> WithFixedDisplacement(
    const Scene& scene, const SceneModel& built,
    std::function<void(double, Eigen::VectorXd*)> load);

}  // namespace contact::internal
