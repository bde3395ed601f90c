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

/// BuildSceneModel without the matrices contact/petsc/ assembles on its ranks: the mesh,
/// the Dirichlet map, the contact frames, the load and the run's options; model.K is n x
/// n without entries, and so is model.M for a consistent mass (for a lumped mass M is the
/// lumped M_FF, diagonal). With a lumped M the prescribed start (u^0 = 0, so K u^0 = 0)
/// is the serial one to the bit; the critical step is not (dt_crit = infinity), and a
/// consistent M has neither (the ranks solve with their M).
SceneModel BuildSceneModelWithoutMatrices(const Scene& scene);

/// The first feature of the scene that the run on MPI ranks does not take (Rayleigh
/// damping, obstacle motion, fixed displacement history: scene_features.cpp), as a
/// message naming its key; empty if none.
std::string SerialOnlySceneFeature(const Scene& scene);

}  // namespace contact::internal
