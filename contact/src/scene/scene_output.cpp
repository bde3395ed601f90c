#include "scene/scene_output.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "checkpoint.hpp"
#include "contact/simulation.hpp"
#include "contact/vtk_writer.hpp"

namespace contact::internal {

std::string OutputPositions::Encode() const {
  BinaryWriter out;
  out.Int(step);
  out.Double(time);
  out.Unsigned(csv_bytes.size());
  for (const auto& [name, bytes] : csv_bytes) out.String(name), out.Int(bytes);
  out.Unsigned(snapshots.size());
  for (const auto& [t, name] : snapshots) out.Double(t), out.String(name);
  return out.bytes();
}

OutputPositions OutputPositions::Decode(const std::string& bytes,
                                        const std::string& checkpoint) {
  BinaryReader in(bytes, checkpoint);
  OutputPositions p;
  p.step = static_cast<int>(in.Int("output step"));
  p.time = in.Double("output time");
  for (std::uint64_t i = 0, n = in.Count("output files", 16); i < n; ++i) {
    std::string name = in.String("output file name");
    p.csv_bytes.emplace_back(std::move(name), in.Int("output file size"));
  }
  for (std::uint64_t i = 0, n = in.Count("snapshots", 16); i < n; ++i) {
    const double t = in.Double("snapshot time");
    p.snapshots.emplace_back(t, in.String("snapshot name"));
  }
  if (in.left() != 0)
    in.Fail("output positions: " + std::to_string(in.left()) +
            " bytes after the last field");
  return p;
}

SceneOutput::SceneOutput(const Scene& scene, const SceneModel& built, int marked,
                         std::vector<std::string>* files_written,
                         const OutputPositions* resume)
    : scene_(scene),
      mesh_(built.body->mesh()),
      dofs_(built.dofs),
      frames_(built.frames),
      dim_(built.body->mesh().dim),
      marked_(marked),
      dt_(built.options.dt),
      end_time_(built.options.end_time),
      directory_(scene.output_directory),
      pending_stress_times_(scene.stress_times),
      files_written_(files_written),
      series_(scene.output_directory, *built.body) {
  // The Cauchy stress of finite strain unless the scene is forced to small strain.
  if (built.model.kinematics &&
      built.model.kinematics->options().kinematics != Kinematics::kSmall) {
    finite_strain_ = true;
    finite_strain_model_ = built.model.kinematics->FiniteModel();
    if (built.model.kinematics->options().kinematics == Kinematics::kAuto)
      auto_kinematics_ = built.model.kinematics;
  }
  std::sort(pending_stress_times_.begin(), pending_stress_times_.end());
  if (scene_.output_directory.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error)
    throw ncp::OutputError("cannot create directory", directory_.string(), error.value());
  steps_csv_ = OpenCsv("steps.csv", kStepsCsvHeader, resume);
  stress_csv_ = OpenCsv("contact_stress.csv", ContactStressCsvHeader(dim_), resume);
  if (marked_ >= 0)
    history_csv_ = OpenCsv("node_history.csv", kNodeHistoryCsvHeader, resume);
  WriteMesh();
  displacement_csv_ = OpenCsv("displacement.csv", DisplacementCsvHeader(dim_), resume);
  if (resume) {  // the stress times the steps up to resume->step consumed, the series so
                 // far
    if (resume->step > 0) ReachedStressTime(resume->time);
    series_.Continue(resume->snapshots);
    return;
  }
  const DynamicOptions& options = built.options;
  if (options.initial_state ==
      InitialState::kPrescribed)  // u^0, v^0 known before the run
    WriteSnapshot(
        0, InitialContactSnapshot(dim_, options.start_time, dofs_.Expand(options.u0),
                                  dofs_.Expand(options.v0), dt_, frames_.nodes));
}

void SceneOutput::WriteStep(const StepRecord& record, const Eigen::VectorXd& u,
                            const ContactSystem::Result& contact, double force_scale) {
  if (scene_.output_directory.empty()) return;
  WriteStepRow(record);
  if (marked_ >= 0)
    WriteNodeHistoryRow(record.time, dim_, frames_.nodes, static_cast<size_t>(marked_),
                        contact, force_scale, &history_csv_.stream());
  const bool last = record.time >= end_time_ - 1e-9 * dt_;
  if (ReachedStressTime(record.time) || last) {
    WriteDisplacementRows(record.time, mesh_, dofs_, u, &displacement_csv_.stream());
    WriteContactStressRows(record.time, mesh_, frames_.nodes, contact, force_scale,
                           &stress_csv_.stream());
  }
  if ((scene_.snapshot_every > 0 && record.step % scene_.snapshot_every == 0) || last) {
    // Under "auto", the Cauchy stress where small strain is not valid at u; where it is,
    // the linear stress (they agree to the kinematics tolerance there).
    const bool finite =
        finite_strain_ && !(auto_kinematics_ && auto_kinematics_->SmallStrainValid(
                                                    auto_kinematics_->Measure(u)));
    // u^k = u^{k+1} - du, du = contact.x
    WriteSnapshot(record.step, {record.time, dofs_.Expand(u), dofs_.Expand(u - contact.x),
                                dt_, &frames_.nodes, force_scale * contact.normal_force,
                                force_scale * contact.tangent_force, contact.gap,
                                record.force_accuracy, record.displacement_accuracy,
                                finite, finite_strain_model_});
  }
  // The step's rows go to the files together, so each file ends at a whole step.
  for (ncp::OutputFile* csv :
       {&steps_csv_, &history_csv_, &stress_csv_, &displacement_csv_})
    if (csv->is_open()) csv->Commit();
}

OutputPositions SceneOutput::Positions(int step, double time) const {
  OutputPositions p;
  p.step = step;
  p.time = time;
  for (const ncp::OutputFile* csv :
       {&steps_csv_, &history_csv_, &stress_csv_, &displacement_csv_})
    if (csv->is_open())
      p.csv_bytes.emplace_back(std::filesystem::path(csv->path()).filename().string(),
                               csv->committed_bytes());
  p.snapshots = series_.snapshots();
  return p;
}

ncp::OutputFile SceneOutput::OpenCsv(const std::string& name, const std::string& header,
                                     const OutputPositions* resume) {
  if (!resume) return Open(name, header, false);
  for (const auto& [file, bytes] : resume->csv_bytes)
    if (file == name) {
      const std::string path = (directory_ / name).string();
      ncp::OutputFile csv = ncp::OutputFile::OpenAppend(path, bytes);
      csv.stream().precision(10);
      files_written_->push_back(path);
      return csv;
    }
  throw CheckpointError("the checkpoint has no position of " + name +
                        " (written by another version?)");
}

void SceneOutput::Finish() {
  for (ncp::OutputFile* csv :
       {&steps_csv_, &history_csv_, &stress_csv_, &displacement_csv_})
    if (csv->is_open()) csv->Close();
}

ncp::OutputFile SceneOutput::Open(const std::string& name, const std::string& header,
                                  bool atomic) {
  const std::string path = (directory_ / name).string();
  ncp::OutputFile file =
      atomic ? ncp::OutputFile::OpenAtomic(path) : ncp::OutputFile::Open(path);
  file.stream() << header << "\n";
  file.stream().precision(10);
  file.Commit();
  files_written_->push_back(path);
  return file;
}

void SceneOutput::WriteMesh() {
  const std::string coords = dim_ == 2 ? "x,y" : "x,y,z";
  ncp::OutputFile nodes_file =
      Open("mesh_nodes.csv", "node," + coords + ",fixed_components,contact", true);
  std::ostream& nodes_csv = nodes_file.stream();
  std::vector<char> is_contact(static_cast<size_t>(mesh_.NumNodes()), 0);
  for (const ContactNode& c : frames_.nodes) is_contact[static_cast<size_t>(c.node)] = 1;
  for (int i = 0; i < mesh_.NumNodes(); ++i) {
    int fixed = 0;
    for (int a = 0; a < dim_; ++a) fixed += dofs_.IsConstrained(dim_ * i + a) ? 1 : 0;
    nodes_csv << i;
    for (int a = 0; a < dim_; ++a) nodes_csv << ',' << mesh_.nodes(a, i);
    nodes_csv << ',' << fixed << ',' << int(is_contact[static_cast<size_t>(i)]) << '\n';
  }
  std::string element_header = "element,type";
  for (int a = 0; a < mesh_.elements.rows(); ++a)
    element_header += ",n" + std::to_string(a);
  nodes_file.Close();
  ncp::OutputFile elements_file = Open("mesh_elements.csv", element_header, true);
  std::ostream& elements_csv = elements_file.stream();
  for (int e = 0; e < mesh_.NumElements(); ++e) {
    elements_csv << e << ',' << ToString(mesh_.element_type);
    for (int a = 0; a < mesh_.elements.rows(); ++a)
      elements_csv << ',' << mesh_.elements(a, e);
    elements_csv << '\n';
  }
  elements_file.Close();
}

void SceneOutput::WriteStepRow(const StepRecord& r) {
  WriteStepsCsvRow(r, &steps_csv_.stream());
}

const char* const kStepsCsvHeader =
    "step,time,newton_iterations,jacobian_evaluations,residual_evaluations,seconds,"
    "kinetic_energy,"
    "strain_energy,external_work,normal_contact_work,friction_dissipation,energy_balance_"
    "error,"
    "normal_force_sum,friction_force_sum,max_penetration,active_nodes,equilibrium_"
    "residual,"
    "complementarity_residual,friction_residual,force_accuracy,displacement_accuracy,"
    "damping_dissipation";

void WriteStepsCsvRow(const StepRecord& r, std::ostream* out) {
  *out << r.step << ',' << r.time << ',' << r.newton_iterations << ','
       << r.jacobian_evaluations << ',' << r.residual_evaluations << ',' << r.seconds
       << ',' << r.kinetic << ',' << r.strain << ',' << r.external_work << ','
       << r.normal_contact_work << ',' << r.friction_dissipation << ','
       << r.energy_balance_error << ',' << r.normal_force_sum << ','
       << r.tangent_force_sum << ',' << r.max_penetration << ',' << r.active_nodes << ','
       << r.equilibrium_residual << ',' << r.complementarity_residual << ','
       << r.friction_residual << ',' << r.force_accuracy << ',' << r.displacement_accuracy
       << ',' << r.damping_dissipation << '\n';
}

namespace {

// Normal stress p = lambda_c / A_c and friction stress tau_c / A_c [Pa] of contact node
// k.
std::pair<double, Eigen::VectorXd> Stress(const std::vector<ContactNode>& nodes, size_t k,
                                          const ContactSystem::Result& contact,
                                          double force_scale) {
  const double area = nodes[k].area;
  const auto c = static_cast<Eigen::Index>(k);
  return {force_scale * contact.normal_force(c) / area,
          force_scale * contact.tangent_force.col(c) / area};
}

}  // namespace

std::string ContactStressCsvHeader(int dim) {
  return std::string("time,node,") + (dim == 2 ? "x,y" : "x,y,z") + ",normal_stress," +
         (dim == 2 ? "friction_stress" : "friction_stress_1,friction_stress_2") +
         ",gap,normal_force";
}

const char* const kNodeHistoryCsvHeader = "time,normal_stress,friction_stress";

std::string DisplacementCsvHeader(int dim) {
  return dim == 2 ? "time,node,ux,uy" : "time,node,ux,uy,uz";
}

void WriteContactStressRows(double time, const Mesh& mesh,
                            const std::vector<ContactNode>& nodes,
                            const ContactSystem::Result& contact, double force_scale,
                            std::ostream* out) {
  for (size_t k = 0; k < nodes.size(); ++k) {
    const auto [p, tau] = Stress(nodes, k, contact, force_scale);
    const int node = nodes[k].node;
    *out << time << ',' << node;
    for (int a = 0; a < mesh.dim; ++a) *out << ',' << mesh.nodes(a, node);
    *out << ',' << p;
    for (Eigen::Index a = 0; a < tau.size(); ++a) *out << ',' << tau(a);
    *out << ',' << contact.gap(static_cast<Eigen::Index>(k)) << ','
         << force_scale * contact.normal_force(static_cast<Eigen::Index>(k)) << '\n';
  }
}

void WriteNodeHistoryRow(double time, int dim, const std::vector<ContactNode>& nodes,
                         size_t k, const ContactSystem::Result& contact,
                         double force_scale, std::ostream* out) {
  const auto [p, tau] = Stress(nodes, k, contact, force_scale);
  *out << time << ',' << p << ',' << (dim == 2 ? tau(0) : tau.norm()) << '\n';
}

void WriteDisplacementRows(double time, const Mesh& mesh, const DofMap& dofs,
                           const Eigen::VectorXd& u_free, std::ostream* out) {
  const Eigen::VectorXd u_full = dofs.Expand(u_free);
  for (int i = 0; i < mesh.NumNodes(); ++i) {
    *out << time << ',' << i;
    for (int a = 0; a < mesh.dim; ++a) *out << ',' << u_full(mesh.dim * i + a);
    *out << '\n';
  }
}

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

bool ConsumeStressTimes(double time, double dt, std::vector<double>* pending) {
  bool reached = false;
  while (!pending->empty() && time >= pending->front() - 0.5 * dt) {
    pending->erase(pending->begin());
    reached = true;
  }
  return reached;
}

void SceneOutput::WriteSnapshot(int step, const ContactSnapshot& snapshot) {
  files_written_->push_back(series_.Write(step, snapshot));
}

bool SceneOutput::ReachedStressTime(double time) {
  return ConsumeStressTimes(time, dt_, &pending_stress_times_);
}

}  // namespace contact::internal
