// Scene features beyond the basic tables (scene_features.hpp).
#include "scene/scene_features.hpp"

#include <algorithm>
#include <cmath>

#include "scene/scene_load.hpp"

namespace contact {

Eigen::VectorXd PiecewiseLinearHistory::At(double t) const {
  if (time.empty()) return {};
  if (t <= time.front()) return value.front();
  if (t >= time.back()) return value.back();
  const size_t i = static_cast<size_t>(std::upper_bound(time.begin(), time.end(), t) -
                                       time.begin());  // time[i-1] < t
  const double s = (t - time[i - 1]) / (time[i] - time[i - 1]);
  return (1.0 - s) * value[i - 1] + s * value[i];
}

namespace internal {
namespace {

const Range kDampingMass{0.0, 1e12, "1/s"};
const Range kDampingStiffness{0.0, 1e3, "s"};
const Range kHistoryTime{0.0, 1e9, "s"};
const Range kHistoryValue{-1e9, 1e9, "m"};

}  // namespace

void ReadDamping(const Table& material, Scene* scene) {
  const Table d = material.Sub("damping", false);
  scene->damping.mass = d.Number("mass", kDampingMass, 0.0);
  scene->damping.stiffness = d.Number("stiffness", kDampingStiffness, 0.0);
  d.RejectUnknownKeys();
}

PiecewiseLinearHistory ReadHistory(const Table& table, const std::string& key, int dim) {
  PiecewiseLinearHistory h;
  const Table t = table.Sub(key, false);
  if (!t.present()) return h;
  h.time = t.Numbers("time", kHistoryTime);
  if (h.time.empty()) t.Fail("time", "must list at least one time");
  for (size_t i = 1; i < h.time.size(); ++i)
    if (!(h.time[i] > h.time[i - 1]))
      t.Fail("time", "must increase strictly, but entry " + std::to_string(i) + " = " +
                         Str(h.time[i]) + " s follows " + Str(h.time[i - 1]) + " s");
  const char* const names[] = {"x", "y", "z"};
  const int n = static_cast<int>(h.time.size());
  h.value.assign(h.time.size(), Eigen::VectorXd::Zero(dim));
  for (int a = 0; a < dim; ++a) {
    const std::vector<double> v = t.Numbers(names[a], kHistoryValue, n);
    for (size_t i = 0; i < v.size(); ++i) h.value[i](a) = v[i];
  }
  t.RejectUnknownKeys();
  return h;
}

void ReadGroupNames(const Table& geometry, Scene* scene) {
  const Table g = geometry.Sub("groups", false);
  for (const char* role : {kFixedGroup, kLoadGroup, kContactGroup}) {
    if (!g.Has(role)) continue;
    const toml::value& v = g.Get(role);
    std::vector<std::string> names =
        v.is_string() ? std::vector<std::string>{v.as_string().str} : g.Strings(role);
    if (names.empty()) g.Fail(role, "must name at least one physical group of the mesh");
    scene->group_names[role] = names;
  }
  g.RejectUnknownKeys();
}

void CheckSceneFeatures(const Scene& s) {
  const std::string at = s.source + ": ";
  if (!s.obstacle_motion.empty()) {
    if (s.obstacle_motion.At(s.dynamics.start_time).norm() != 0.0)
      throw SceneError(
          at +
          "'obstacle.motion' must start at the obstacle's place in the scene "
          "(all components 0 at t = 0); give the start position with the "
          "obstacle's own keys");
    if (s.friction_coefficient > 0.0 && s.dynamics.step_method != StepMethod::kExplicit)
      throw SceneError(
          at +
          "'obstacle.motion' with friction.coefficient = " + Str(s.friction_coefficient) +
          " needs solver.step = \"explicit\" (and material.mass = \"lumped\"): only the "
          "explicit step takes the slip relative to the moving obstacle; the others "
          "would take the body's own slip");
  }
  if (!s.fixed_displacement.empty() && s.mass != MassKind::kLumped)
    throw SceneError(at +
                     "'geometry.fixed_displacement' needs material.mass = \"lumped\" (a "
                     "consistent mass couples the fixed nodes' acceleration into the "
                     "free ones, which is not modelled)");
}

Mesh MapMeshGroups(const Scene& scene, Mesh mesh) {
  for (const auto& [role, names] : scene.group_names) {
    BoundaryFacets merged;
    for (const std::string& name : names) {
      if (!mesh.HasBoundaryGroup(name)) {
        std::string have;
        for (const auto& [n, facets] : mesh.boundary_groups)
          have += (have.empty() ? "\"" : ", \"") + n + "\"";
        throw SceneError(scene.source + ": 'geometry.groups." + role + "' names \"" +
                         name + "\", which " + scene.msh_file +
                         " does not have (its boundary groups: " + have + ")");
      }
      const BoundaryFacets& g = mesh.BoundaryGroup(name);
      const Eigen::Index old = merged.connectivity.cols();
      merged.type = g.type;
      merged.connectivity.conservativeResize(g.connectivity.rows(),
                                             old + g.connectivity.cols());
      merged.connectivity.rightCols(g.connectivity.cols()) = g.connectivity;
    }
    mesh.boundary_groups[role] = merged;
  }
  return mesh;
}

void SetFixedDisplacement(const Scene& scene, double t, DofMap* dofs) {
  if (scene.fixed_displacement.empty()) return;
  const Eigen::VectorXd u = scene.fixed_displacement.At(t);
  Vector u_full = Vector::Zero(dofs->NumDofs());
  for (int dof = 0; dof < dofs->NumDofs(); ++dof)
    if (dofs->IsConstrained(dof)) u_full(dof) = u(dof % scene.dim);
  dofs->SetPrescribedValues(u_full);
}

std::function<void(double, Eigen::VectorXd*)> WithFixedDisplacement(
    const Scene& scene, const SceneModel& built,
    std::function<void(double, Eigen::VectorXd*)> load) {
  if (scene.fixed_displacement.empty()) return load;
  // h_a = K_FD e_a, e_a = 1 at the constrained dofs of component a: K_FD u_D(t) =
  // sum_a u_D,a(t) h_a for the uniform u_D of the fixed group.
  const int dim = scene.dim;
  const SparseMatrix K = built.body->StiffnessMatrix();
  std::vector<Vector> h;
  for (int a = 0; a < dim; ++a) {
    Vector e = Vector::Zero(built.dofs.NumDofs());
    for (int dof = a; dof < built.dofs.NumDofs(); dof += dim)
      if (built.dofs.IsConstrained(dof)) e(dof) = 1.0;
    h.push_back(built.dofs.RestrictVector(K * e));
  }
  const PiecewiseLinearHistory history = scene.fixed_displacement;
  return [load, h, history, dim](double t, Eigen::VectorXd* f) {
    load(t, f);
    const Eigen::VectorXd u = history.At(t);
    for (int a = 0; a < dim; ++a) *f -= u(a) * h[static_cast<size_t>(a)];
  };
}

std::string SerialOnlySceneFeature(const Scene& s) {
  const char* key = s.damping.active()              ? "material.damping"
                    : !s.obstacle_motion.empty()    ? "obstacle.motion"
                    : !s.fixed_displacement.empty() ? "geometry.fixed_displacement"
                                                    : nullptr;
  if (!key) return "";
  return s.source + ": '" + key + "' is not available on MPI ranks yet; run the scene " +
         "in one process (without mpiexec)";
}

}  // namespace internal
}  // namespace contact
