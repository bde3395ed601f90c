// A scene run (RunScene, contact/scene.hpp): build the model, open the outputs, run the
// time loop with one output call per step.
#include <filesystem>
#include <optional>

#include "contact/scene.hpp"
#include "contact/simulation.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_output.hpp"

namespace contact {

SceneResult RunScene(const Scene& scene, bool progress) {
  SceneRunOptions options;
  options.progress = progress;
  return RunScene(scene, options);
}

SceneResult RunScene(const Scene& scene, const SceneRunOptions& run) {
  SceneResult result;
  const std::filesystem::path checkpoint =
      scene.output_directory.empty()
          ? std::filesystem::path()
          : std::filesystem::path(scene.output_directory) / kCheckpointFile;
  if (run.resume && checkpoint.empty())
    throw CheckpointError(
        "the scene has no output directory (output.directory or --output) "
        "to hold a checkpoint");
  if (run.resume && !std::filesystem::exists(checkpoint))
    throw CheckpointError(
        "there is no checkpoint " + checkpoint.string() +
        " (a run writes it every output.checkpoint_every steps and when interrupted)");
  // The output callback is set before the Simulation builds the model, the writer after.
  Scene stepped = scene;
  internal::SceneOutput* output = nullptr;
  stepped.dynamics.progress = run.progress;
  stepped.dynamics.on_step = [&output](const StepRecord& record, const Eigen::VectorXd& u,
                                       const ContactSystem::Result& contact,
                                       double force_scale) {
    output->WriteStep(record, u, contact, force_scale);
  };
  Simulation simulation(stepped);
  std::optional<internal::OutputPositions> positions;
  if (run.resume) {
    positions = internal::OutputPositions::Decode(
        simulation.LoadCheckpoint(checkpoint.string()), checkpoint.string());
    result.resumed_from_step = simulation.step_index();
  }

  const SceneModel& built = simulation.scene_model();
  const Mesh& mesh = built.body->mesh();
  result.num_dofs = mesh.NumDofs();
  result.num_free_dofs = built.dofs.NumFreeDofs();
  result.num_contact_nodes = static_cast<int>(built.frames.nodes.size());
  result.num_elements = mesh.NumElements();
  int marked = -1;
  if (scene.marked_point) {
    marked = internal::NearestContactNode(mesh, built.frames.nodes, *scene.marked_point);
    result.marked_node = built.frames.nodes[static_cast<size_t>(marked)].node;
  }
  // Refused before the first step (dt above the critical step, an initial state that does
  // not fit): nothing was run, so nothing is written - no directory, no file.
  if (simulation.state() == SimulationState::kFailed) {
    result.summary = simulation.summary();
    return result;
  }
  // A fresh run's files are new: an older run's checkpoint does not describe them.
  if (!run.resume && !checkpoint.empty()) {
    std::error_code ignored;
    std::filesystem::remove(checkpoint, ignored);
  }
  internal::SceneOutput writer(scene, built, marked, &result.files_written,
                               positions ? &*positions : nullptr);
  output = &writer;
  const auto save_checkpoint = [&] {
    simulation.SaveCheckpoint(
        checkpoint.string(),
        writer.Positions(simulation.step_index(), simulation.time()).Encode());
    result.checkpoint_step = simulation.step_index();
  };
  while (simulation.state() == SimulationState::kRunning) {
    simulation.Step(1);
    if (checkpoint.empty()) continue;
    const bool interrupted = simulation.summary().status == DynamicStatus::kInterrupted;
    if (interrupted ||
        (simulation.state() == SimulationState::kRunning && scene.checkpoint_every > 0 &&
         simulation.step_index() % scene.checkpoint_every == 0))
      save_checkpoint();
  }
  writer.Finish();  // however the run ended: the rows of every finished step are in the
                    // files
  if (!checkpoint.empty() && std::filesystem::exists(checkpoint))
    result.files_written.push_back(checkpoint.string());
  result.summary = simulation.summary();
  return result;
}

}  // namespace contact
