// The files a scene run writes into scene.output_directory (examples/scenes/README.md):
// the mesh once (mesh_nodes.csv, mesh_elements.csv), one row per step (steps.csv), the
// marked node's history (node_history.csv), the contact stresses and the displacement of
// every node at the stress times and the end (contact_stress.csv, displacement.csv), and
// VTK snapshots. Every write is checked (ncp::OutputFile): a failed one throws
// ncp::OutputError naming the file. The CSVs grow by whole rows, committed after each
// step, so after a failure or an interrupt they hold complete rows up to the last step
// written; the mesh files and the snapshots are written atomically (NAME.partial renamed
// when complete). A resumed run (OutputPositions from its checkpoint) cuts each CSV back
// to its size at the checkpoint's step and appends, and continues the VTK series.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "contact/kinematics.hpp"
#include "contact/scene.hpp"
#include "contact/vtk_writer.hpp"
#include "ncp/output_file.hpp"

namespace contact::internal {

/// steps.csv: its header line (without the newline) and one row per step.
extern const char* const kStepsCsvHeader;
void WriteStepsCsvRow(const StepRecord& r, std::ostream* out);

/// contact_stress.csv, node_history.csv and displacement.csv: headers and rows, shared by
/// SceneOutput and the run on MPI ranks (contact/petsc/). Stresses [Pa] are forces over
/// the node's area (ContactNode::area); contact in system units (times force_scale [N]).
std::string ContactStressCsvHeader(int dim);
extern const char* const kNodeHistoryCsvHeader;
std::string DisplacementCsvHeader(int dim);
/// Rows of every contact node at `time`.
void WriteContactStressRows(double time, const Mesh& mesh,
                            const std::vector<ContactNode>& nodes,
                            const ContactSystem::Result& contact, double force_scale,
                            std::ostream* out);
/// The row of contact node k at `time`.
void WriteNodeHistoryRow(double time, int dim, const std::vector<ContactNode>& nodes,
                         size_t k, const ContactSystem::Result& contact,
                         double force_scale, std::ostream* out);
/// Rows of every mesh node at `time` [m] (u_free on the free dofs, 0 where fixed).
void WriteDisplacementRows(double time, const Mesh& mesh, const DofMap& dofs,
                           const Eigen::VectorXd& u_free, std::ostream* out);
/// The contact node nearest to `point` (index into nodes; the first one if every distance
/// compares equal, e.g. overflows to inf): output.marked_point's node. nodes is not empty
/// (BuildSceneModel checks).
int NearestContactNode(const Mesh& mesh, const std::vector<ContactNode>& nodes,
                       const Eigen::VectorXd& point);
/// True once per stress time reached by `time` (within dt / 2), consuming it (*pending
/// ascending).
bool ConsumeStressTimes(double time, double dt, std::vector<double>* pending);

/// Where the outputs stand after a step: what a checkpoint keeps to continue them.
struct OutputPositions {
  int step = 0;       ///< the step they end with
  double time = 0.0;  ///< its time [s]
  std::vector<std::pair<std::string, long long>>
      csv_bytes;                                          ///< file name, committed bytes
  std::vector<std::pair<double, std::string>> snapshots;  ///< the .pvd's (time, file)
  /// As bytes (BinaryWriter; the checkpoint's application data) and back. Decode throws
  /// CheckpointError naming `checkpoint` on bytes it cannot read.
  std::string Encode() const;
  static OutputPositions Decode(const std::string& bytes, const std::string& checkpoint);
};

class SceneOutput {
 public:
  /// Opens the files, writes the mesh and, for a prescribed initial state, the snapshot
  /// of the start (step 0; a static initial state is known only once the run starts);
  /// adds each path to *files_written; writes nothing without scene.output_directory.
  /// marked: index into built.frames.nodes of the node_history.csv node, -1 for none.
  /// `built` must outlive this. With `resume`: continues the files of a run stopped after
  /// resume->step instead (the mesh rewritten, no start snapshot; CheckpointError if a
  /// CSV is missing from it, ncp::OutputError if a CSV is shorter than recorded).
  SceneOutput(const Scene& scene, const SceneModel& built, int marked,
              std::vector<std::string>* files_written,
              const OutputPositions* resume = nullptr);

  /// The positions after the last WriteStep (of `step` at `time`).
  OutputPositions Positions(int step, double time) const;

  /// After each step (DynamicOptions::on_step): u = u^{k+1} on the free dofs [m], contact
  /// forces in system units (times force_scale for newtons).
  void WriteStep(const StepRecord& record, const Eigen::VectorXd& u,
                 const ContactSystem::Result& contact, double force_scale);

  /// Closes the CSVs (checked). Call once the run has ended, however it ended.
  void Finish();

 private:
  /// Opens directory/name (atomically for a file written whole at once) with its header.
  ncp::OutputFile Open(const std::string& name, const std::string& header, bool atomic);
  /// A CSV: opened with its header, or with `resume` continued at its recorded size.
  ncp::OutputFile OpenCsv(const std::string& name, const std::string& header,
                          const OutputPositions* resume);
  /// Nodes with the number of fixed components and the contact flag (a node of Gamma_c
  /// that keeps a free dof), and the connectivity.
  void WriteMesh();
  void WriteStepRow(const StepRecord& r);
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
  bool finite_strain_ = false;  // snapshots with the Cauchy stress of finite strain
  // The body's kinematics under "auto" (null otherwise): a snapshot where small strain is
  // valid writes the linear stress, the model the run uses there.
  std::shared_ptr<const BodyKinematics> auto_kinematics_;
  MaterialModel finite_strain_model_ = MaterialModel::kSaintVenantKirchhoff;
  ncp::OutputFile steps_csv_, stress_csv_, history_csv_, displacement_csv_;
};

}  // namespace contact::internal
