// The load of a scene as f(t) = factor(t) f_F (scene_model.cpp), in parts that the
// distributed run (contact/petsc/) evaluates per rank.
#pragma once

#include "contact/scene.hpp"

namespace contact::internal {

/// factor(t) of a load history: 1 (constant); 0 at t0 and 1 after it (step, t > t0 +
/// 1e-12 max(1, |t0|)); min(max((t - t0) / ramp_time, 0), 1) (ramp). t, t0, ramp_time
/// [s].
double LoadHistoryFactor(LoadHistory history, double t0, double ramp_time, double t);

/// f_F [N]: the scene's body force and traction on the free dofs of `built` (factor 1).
Vector SceneLoadVector(const Scene& scene, const SceneModel& built);

}  // namespace contact::internal
