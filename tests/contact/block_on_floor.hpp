// A scene shared by the dynamics tests: a 2 x 1 m steel block (E = 210 GPa, nu = 0.3,
// rho = 7850 kg/m^3) of 8 x 4 Q4 under gravity, its bottom side y = 0 touching the floor
// y >= 0 (gap 0), friction coefficient 0.3, dt = 2e-6 s (below its dt_crit).
#pragma once

#include <memory>

#include "contact/scene.hpp"

namespace contact::testing {

inline Scene SteelBlockOnFloor(MassKind mass) {
  Scene scene;
  scene.dim = 2;
  RectangleMeshOptions o;
  o.size = {2.0, 1.0};
  o.cells = {8, 4};
  o.side_roles = {{Side::kYMin, BoundaryRole::kContact}};
  scene.rectangle = o;
  scene.material = IsotropicMaterial{210e9, 0.3, 7850.0};
  scene.mass = mass;
  scene.body_force = Eigen::Vector2d(0.0, -9.81 * 7850.0);
  scene.obstacle = std::make_shared<HalfSpace>(HalfSpace::ObstacleBelow(2, 1, 0.0));
  scene.friction_coefficient = 0.3;
  scene.dynamics.dt = 2e-6;
  scene.dynamics.end_time = scene.dynamics.dt;
  return scene;
}

}  // namespace contact::testing
