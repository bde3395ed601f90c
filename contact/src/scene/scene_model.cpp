// Building the model of a scene (BuildSceneModel, contact/scene.hpp): the mesh, the
// Dirichlet map and the contact frames, K, M and the load on the free dofs, and the run's
// options.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "contact/gmsh_reader.hpp"
#include "contact/scene.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_features.hpp"
#include "scene/scene_load.hpp"

namespace contact {
namespace {

/// The Dirichlet map (the "fixed" group, scene.fixed_components), the contact boundary
/// and its frames; refuses a contact set that the Dirichlet conditions empty.
void MakeConstraints(const Scene& scene, SceneModel* out) {
  const Mesh& mesh = out->body->mesh();
  std::vector<DirichletCondition> conditions;
  if (mesh.HasBoundaryGroup(kFixedGroup)) {
    DirichletCondition fixed;
    fixed.components = scene.fixed_components;
    conditions.push_back(fixed);
  }
  out->dofs = MakeDofMap(mesh, conditions);
  out->boundary = MakeContactBoundary(*out->body);
  out->frames = MakeContactFrames(mesh, out->boundary, out->dofs, *scene.obstacle,
                                  scene.normal_source);
  if (out->frames.nodes.empty())
    throw SceneError(scene.source + ": no contact node is left after removing the " +
                     std::to_string(out->frames.excluded_mesh_nodes.size()) +
                     " nodes constrained by the 'fixed' group");
}

/// The lumped mass M_FF [kg] on the free dofs, diagonal.
SparseMatrix LumpedMassOnFreeDofs(const ElasticBody& body, const DofMap& dofs) {
  const Vector lumped = body.LumpedMass();
  SparseMatrix L(lumped.size(), lumped.size());
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < lumped.size(); ++i)
    t.emplace_back(static_cast<int>(i), static_cast<int>(i), lumped(i));
  L.setFromTriplets(t.begin(), t.end());
  return dofs.RestrictMatrix(L);
}

/// K [N/m] and M [kg] (consistent or lumped) on the free dofs into *model, and the load
/// vector f_F - K_FC u_C [N] of the body force and traction.
Vector AssembleOnFreeDofs(const Scene& scene, const ElasticBody& body, const DofMap& dofs,
                          DynamicModel* model) {
  // Without constrained dofs A_FF = A: no copies (K is the largest object of the model).
  const bool all_free = dofs.NumConstrainedDofs() == 0;
  SparseMatrix K_full = body.StiffnessMatrix();
  if (scene.mass == MassKind::kLumped) {
    model->M = LumpedMassOnFreeDofs(body, dofs);
  } else {
    SparseMatrix M_full = body.ConsistentMassMatrix();
    if (all_free)
      model->M.swap(M_full);
    else
      model->M = dofs.RestrictMatrix(M_full);
  }
  Vector f_full = body.BodyForceLoad(scene.body_force);
  if (scene.traction.size()) f_full += body.TractionLoad(scene.traction);
  const Vector f_free = dofs.RestrictLoad(K_full, f_full);
  if (all_free)
    model->K.swap(K_full);  // (swap: Eigen 3.4's SparseMatrix has no move constructor)
  else
    model->K = dofs.RestrictMatrix(K_full);
  return f_free;
}

/// f(t) = factor(t) f_free with the scene's load history (constant, step at t0, ramp).
std::function<void(double, Eigen::VectorXd*)> LoadHistoryOf(const Scene& scene,
                                                            const Vector& f_free) {
  const double t0 = scene.dynamics.start_time;
  const LoadHistory history = scene.load_history;
  const double ramp = scene.ramp_time;
  return [f_free, t0, history, ramp](double t, Eigen::VectorXd* f) {
    *f = internal::LoadHistoryFactor(history, t0, ramp, t) * f_free;
  };
}

/// scene.dynamics with the friction coefficient, and for a prescribed start u0 = 0 and
/// the uniform initial velocity on the free dofs.
DynamicOptions RunOptions(const Scene& scene, const SceneModel& built) {
  DynamicOptions options = scene.dynamics;
  options.friction_coefficient = scene.friction_coefficient;
  if (options.initial_state == InitialState::kPrescribed) {
    const Mesh& mesh = built.body->mesh();
    options.u0 = Eigen::VectorXd::Zero(built.dofs.NumFreeDofs());
    Vector v_full = Vector::Zero(mesh.NumDofs());
    for (int i = 0; i < mesh.NumNodes(); ++i)
      v_full.segment(mesh.dim * i, mesh.dim) = scene.initial_velocity;
    options.v0 = built.dofs.RestrictVector(v_full);
  }
  return options;
}

// The mesh, its Dirichlet map and contact frames (BuildModel's first phases).
SceneModel BuildGeometry(const Scene& scene, Mesh mesh) {
  if (mesh.dim != scene.dim)
    throw SceneError(scene.source + ": the mesh is " + std::to_string(mesh.dim) +
                     "D but the scene is " + std::to_string(scene.dim) + "D");
  SceneModel out;
  out.body = std::make_unique<ElasticBody>(std::move(mesh), scene.material, scene.plane);
  MakeConstraints(scene, &out);
  out.model.dim = scene.dim;
  out.model.contact_nodes = out.frames.nodes;
  return out;
}

SceneModel BuildModel(const Scene& scene, Mesh mesh) {
  SceneModel out = BuildGeometry(scene, std::move(mesh));
  const Vector f_free = AssembleOnFreeDofs(scene, *out.body, out.dofs, &out.model);
  out.model.load =
      internal::WithFixedDisplacement(scene, out, LoadHistoryOf(scene, f_free));
  internal::SetFixedDisplacement(scene, scene.dynamics.start_time, &out.dofs);
  out.model.damping = scene.damping;
  // (the body is on the heap: the pointer stays valid when the SceneModel moves)
  out.model.kinematics =
      std::make_shared<const BodyKinematics>(*out.body, out.dofs, scene.kinematics);
  out.options = RunOptions(scene, out);
  return out;
}

Mesh SceneMesh(const Scene& scene) {
  return !scene.msh_file.empty()
             ? internal::MapMeshGroups(scene, ReadGmshMesh(scene.msh_file))
         : scene.rectangle ? MakeRectangleMesh(*scene.rectangle)
                           : MakeBoxMesh(*scene.box);
}

}  // namespace

double internal::LoadHistoryFactor(LoadHistory history, double t0, double ramp_time,
                                   double t) {
  if (history == LoadHistory::kStep)
    return t > t0 + 1e-12 * std::max(1.0, std::abs(t0)) ? 1.0 : 0.0;
  if (history == LoadHistory::kRamp)
    return std::min(std::max((t - t0) / ramp_time, 0.0), 1.0);
  return 1.0;
}

Vector internal::SceneLoadVector(const Scene& scene, const SceneModel& built) {
  Vector f_full = built.body->BodyForceLoad(scene.body_force);
  if (scene.traction.size()) f_full += built.body->TractionLoad(scene.traction);
  return built.dofs.RestrictVector(f_full);
}

std::function<void(double, Eigen::VectorXd*)> SceneLoad(
    const Scene& scene, const SceneModel& built, const Eigen::VectorXd& body_force) {
  Vector f_full = built.body->BodyForceLoad(body_force);
  if (scene.traction.size()) f_full += built.body->TractionLoad(scene.traction);
  return internal::WithFixedDisplacement(
      scene, built, LoadHistoryOf(scene, built.dofs.RestrictVector(f_full)));
}

SceneModel internal::BuildSceneModelWithoutMatrices(const Scene& scene) {
  return NamingTheScene(scene, [&] {
    SceneModel out = BuildGeometry(scene, SceneMesh(scene));
    const Eigen::Index n = out.dofs.NumFreeDofs();
    out.model.K.resize(n, n);  // (no entries)
    if (scene.mass == MassKind::kLumped)
      out.model.M = LumpedMassOnFreeDofs(*out.body, out.dofs);
    else
      out.model.M.resize(n, n);  // (no entries)
    out.model.load = LoadHistoryOf(scene, SceneLoadVector(scene, out));
    out.options = RunOptions(scene, out);
    return out;
  });
}

SceneModel BuildSceneModel(const Scene& scene) {
  return internal::NamingTheScene(scene,
                                  [&] { return BuildModel(scene, SceneMesh(scene)); });
}

SceneModel BuildSceneModel(const Scene& scene, Mesh mesh) {
  return internal::NamingTheScene(scene,
                                  [&] { return BuildModel(scene, std::move(mesh)); });
}

}  // namespace contact
