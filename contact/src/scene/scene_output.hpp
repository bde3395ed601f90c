// The files a scene run writes into scene.output_directory (examples/scenes/README.md): the
// mesh once (mesh_nodes.csv, mesh_elements.csv), one row per step (steps.csv), the marked
// node's history (node_history.csv), the contact stresses and the displacement of every node
// at the stress times and the end (contact_stress.csv, displacement.csv), and VTK snapshots.
// Every write is checked (ncp::OutputFile): a failed one throws ncp::OutputError naming the
// file. The CSVs grow by whole rows, committed after each step, so after a failure or an
// interrupt they hold complete rows up to the last step written; the mesh files and the
// snapshots are written atomically (NAME.partial renamed when complete).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "contact/scene.hpp"
#include "contact/vtk_writer.hpp"
#include "ncp/output_file.hpp"

namespace contact::internal {

/// steps.csv: its header line (without the newline) and one row per step.
extern const char* const kStepsCsvHeader;
void WriteStepsCsvRow(const StepRecord& r, std::ostream* out);

class SceneOutput {
 public:
  /// Opens the files, writes the mesh and, for a prescribed initial state, the snapshot of
  /// the start (step 0; a static initial state is known only once the run starts); adds each
  /// path to *files_written; writes nothing without scene.output_directory. marked: index
  /// into built.frames.nodes of the node_history.csv node, -1 for none. `built` must
  /// outlive this.
  SceneOutput(const Scene& scene, const SceneModel& built, int marked,
              std::vector<std::string>* files_written);

  /// After each step (DynamicOptions::on_step): u = u^{k+1} on the free dofs [m], contact
  /// forces in system units (times force_scale for newtons).
  void WriteStep(const StepRecord& record, const Eigen::VectorXd& u,
                 const ContactSystem::Result& contact, double force_scale);

  /// Closes the CSVs (checked). Call once the run has ended, however it ended.
  void Finish();

 private:
  /// Opens directory/name (atomically for a file written whole at once) with its header.
  ncp::OutputFile Open(const std::string& name, const std::string& header, bool atomic);
  /// Nodes with the number of fixed components and the contact flag (a node of Gamma_c that
  /// keeps a free dof), and the connectivity.
  void WriteMesh();
  void WriteStepRow(const StepRecord& r);
  /// Normal stress p = lambda_c / A_c and friction stress tau_c / A_c [Pa] of contact node k.
  std::pair<double, Eigen::VectorXd> Stress(size_t k, const ContactSystem::Result& contact,
                                            double force_scale) const;
  void WriteContactStress(double time, const ContactSystem::Result& contact, double force_scale);
  /// Full displacement of every node [m].
  void WriteDisplacement(double time, const Eigen::VectorXd& u_free);
  /// snapshot_NNNNN.vtu for `step` and solution.pvd (ParaView output, vtk_writer.hpp).
  void WriteSnapshot(int step, const ContactSnapshot& snapshot);
  /// True once per stress time reached by `time` (within dt / 2), consuming it.
  bool ReachedStressTime(double time);

  const Scene& scene_;
  const Mesh& mesh_;
  const DofMap& dofs_;
  const ContactFrames& frames_;
  const int dim_;
  const int marked_;
  const double dt_, end_time_;
  const std::filesystem::path directory_;
  std::vector<double> pending_stress_times_;  // ascending
  std::vector<std::string>* files_written_;
  VtuSeriesWriter series_;
  ncp::OutputFile steps_csv_, stress_csv_, history_csv_, displacement_csv_;
};

}  // namespace contact::internal
