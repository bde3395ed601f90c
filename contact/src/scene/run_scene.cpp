// A scene run (RunScene, contact/scene.hpp): build the model, open the outputs, run the time
// loop with one output call per step.
#include <limits>

#include "contact/scene.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_output.hpp"

namespace contact {
namespace {

/// The contact node nearest to `point` (index into nodes; the first one if every distance
/// compares equal, e.g. overflows to inf). nodes is not empty (BuildSceneModel checks).
int NearestContactNode(const Mesh& mesh, const std::vector<ContactNode>& nodes,
                       const Eigen::VectorXd& point) {
  double best = std::numeric_limits<double>::infinity();
  int nearest = 0;
  for (size_t c = 0; c < nodes.size(); ++c) {
    const double d = (mesh.nodes.col(nodes[c].node) - point).norm();
    if (d < best) best = d, nearest = static_cast<int>(c);
  }
  return nearest;
}

}  // namespace

SceneResult RunScene(const Scene& scene, bool progress) {
  SceneResult result;
  SceneModel built = BuildSceneModel(scene);
  const Mesh& mesh = built.body->mesh();
  result.num_dofs = mesh.NumDofs();
  result.num_free_dofs = built.dofs.NumFreeDofs();
  result.num_contact_nodes = static_cast<int>(built.frames.nodes.size());
  result.num_elements = mesh.NumElements();
  int marked = -1;
  if (scene.marked_point) {
    marked = NearestContactNode(mesh, built.frames.nodes, *scene.marked_point);
    result.marked_node = built.frames.nodes[static_cast<size_t>(marked)].node;
  }

  internal::SceneOutput output(scene, built, marked, &result.files_written);
  DynamicOptions& options = built.options;
  options.progress = progress;
  options.on_step = [&output](const StepRecord& record, const Eigen::VectorXd& u,
                              const ContactSystem::Result& contact, double force_scale) {
    output.WriteStep(record, u, contact, force_scale);
  };
  result.summary = internal::NamingTheScene(scene, [&] { return RunDynamics(built.model, options); });
  output.Finish();  // however the run ended: the rows of every finished step are in the files
  return result;
}

}  // namespace contact
