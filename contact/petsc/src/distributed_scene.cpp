// A scene on MPI ranks with the explicit step (contact/petsc/distributed_scene.hpp).
//
// Set-up on rank 0 (not yet distributed): the scene's model as contact-sim builds it
// (BuildSceneModel), and contact::Simulation's critical time step and initial state; for
// a prescribed start the model without K (and without a consistent M), and the critical
// step by Lanczos on the ranks after the distribution (SetUpWithoutSerialMatrices; with
// a consistent mass the ranks also complete the start with their solver of M). Then
// the mesh and, per node, its Dirichlet components, u^0, u^{-1}, f_F and contact frame go
// to DMPlex and its ranks (DistributedBody), and each rank steps its own free dofs:
//   Q^k = K u^k - f^k - M (u^k - u^{k-1}) / dt^2,   q = Q^k dt^2 / m_max,
//   du = -q / (m / m_max) off contact, and per owned contact node the closed form of
//   SolveExplicitContactNode (the serial step's function) - dynamics.cpp and
//   explicit_step.cpp, with the same operations in the same order on every entry.
// The only sums over ranks are K u (MatMult: its rows of a partition-boundary vertex add
// contributions in another order than the serial product) and the energies; the per-step
// contact force sums are formed on rank 0 in the serial node order.
#include "contact/petsc/distributed_scene.hpp"

#include <petscdmplex.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>

#include "contact/simulation.hpp"
#include "contact/vtk_writer.hpp"
#include "critical_time_step.hpp"
#include "distributed_body.hpp"
#include "distributed_critical_step.hpp"
#include "distributed_implicit_step.hpp"
#include "distributed_snapshot.hpp"
#include "mass_inverse.hpp"
#include "ncp/output_file.hpp"
#include "parallel.hpp"
#include "petsc_check.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_load.hpp"
#include "scene/scene_output.hpp"
#include "step/explicit_contact_node.hpp"
#include "step_accuracy.hpp"
#include "step_record.hpp"

namespace contact::petsc {
namespace {

using internal::CondensedGatheredStep;
using internal::DistributedBody;
using internal::GatheredStep;
using internal::NodeData;
using internal::NodeResult;
using internal::RankStepPart;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

int RankOf(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}
int SizeOf(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

// This process's peak resident set size so far [MiB]: VmHWM of /proc/self/status (Linux;
// -1 where it cannot be read).
double PeakResidentMiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
  return -1.0;
}

// The scenes whose set-up needs no serial K, and no serial consistent M, on rank 0: a
// prescribed start (u^0 = 0, so K u^0 = 0); dt_crit is then estimated on the ranks
// (DistributedCriticalTimeStep). With a lumped mass rank 0 completes the start with its
// diagonal M (the serial start to the bit, StartCompletedOnRanks false); with a
// consistent mass rank 0 sends u^{-1} = u^0 - dt v^0 and the ranks add dt^2 / 2 M^-1
// (f(t_0) - K u^0) with their solver of M (CondensedGatheredStep's complete_start). The
// static initial state solves the static contact problem with K: set up on rank 0 with
// the serial model.
bool SetUpWithoutSerialMatrices(const Scene& scene) {
  return scene.dynamics.initial_state == InitialState::kPrescribed;
}
bool StartCompletedOnRanks(const Scene& scene) {
  return SetUpWithoutSerialMatrices(scene) && scene.mass == MassKind::kConsistent;
}

// The largest |A_ij| of a parallel matrix (m_max of the step scaling S = M / m_max:
// MaxAbsEntry of the serial M_FF, up to the round-off of the partition-boundary rows'
// sums).
double MaxAbsEntry(Mat A) {
  Vec row_max = nullptr;
  CONTACT_PETSC_CHECK(MatCreateVecs(A, nullptr, &row_max));
  CONTACT_PETSC_CHECK(MatGetRowMaxAbs(A, row_max, nullptr));
  PetscReal max = 0.0;
  CONTACT_PETSC_CHECK(VecMax(row_max, nullptr, &max));
  CONTACT_PETSC_CHECK(VecDestroy(&row_max));
  return max;
}

// What rank 0 has computed before the distributed steps, and tells every rank.
struct StartInfo {
  int refused = 0;  // the serial set-up refused the run (summary says why)
  double critical_time_step = 0.0;  // [s] (estimated later on the ranks if not known)
  int num_dofs = 0, num_free_dofs = 0, num_contact_nodes = 0, num_elements = 0;
  int method = static_cast<int>(StepMethod::kExplicit);  // the step on ranks
  double m_max = 0.0;  // the largest entry of the serial M_FF [kg]
};

// What rank 0's StepRecorder starts from: the initial normal forces lambda^0 [N] and the
// energy balance of u^0, u^{-1} (K and M are the serial ones, dropped after the set-up).
struct RecorderStart {
  Eigen::VectorXd lambda0;
  ::contact::internal::EnergyBalance energy;
};

// Rank 0: the model, the critical step and the initial state of the serial run, and the
// NodeData of every mesh node. Without the serial matrices (SetUpWithoutSerialMatrices)
// the critical step is left to the ranks (summary->critical_time_step = infinity here),
// and with a consistent mass the start's acceleration term, its energy and m_max too
// (StartCompletedOnRanks: u^{-1} = u^0 - dt v^0 here, info->m_max = 0).
std::vector<double> SerialSetUp(const Scene& scene, SceneModel* built,
                                DynamicSummary* summary, StartInfo* info,
                                RecorderStart* recorder) {
  *built = SetUpWithoutSerialMatrices(scene)
               ? ::contact::internal::BuildSceneModelWithoutMatrices(scene)
               : BuildSceneModel(scene);
  const Mesh& mesh = built->body->mesh();
  const int dim = mesh.dim;
  const StepMethod method = internal::ResolveDistributedStep(scene, *built);
  info->method = static_cast<int>(method);
  info->m_max = ::contact::internal::MaxAbsEntry(built->model.M);
  DynamicOptions options = built->options;
  options.progress = false;
  options.on_step = nullptr;
  info->num_dofs = mesh.NumDofs();
  info->num_free_dofs = built->dofs.NumFreeDofs();
  info->num_contact_nodes = static_cast<int>(built->frames.nodes.size());
  info->num_elements = mesh.NumElements();
  Eigen::VectorXd u0, u_previous;
  recorder->lambda0 = Eigen::VectorXd::Zero(info->num_contact_nodes);
  if (StartCompletedOnRanks(scene)) {
    summary->critical_time_step = std::numeric_limits<double>::infinity();
    info->critical_time_step = summary->critical_time_step;
    u0 = options.u0;
    u_previous = u0 - options.dt * options.v0;
  } else {
    // (The serial step is never taken here: for the condensed step on ranks the full
    // step, whose set-up is cheapest, stands in, so that rank 0 does not form W.)
    options.step_method =
        method == StepMethod::kExplicit ? StepMethod::kExplicit : StepMethod::kFull;
    const Simulation initial(built->model,
                             options);  // checks dt against dt_crit, u^0, u^{-1}
    *summary = initial.summary();
    info->critical_time_step = summary->critical_time_step;
    if (initial.state() == SimulationState::kFailed) {
      info->refused = 1;
      return {};
    }
    u0 = initial.displacement();
    u_previous = u0 - options.dt * initial.velocity();
    const Eigen::VectorXd du = u0 - u_previous;
    Eigen::VectorXd Ku(u0.size()), Mdu(u0.size());
    ::contact::internal::SymmetricMultiply(built->model.K, u0, &Ku);
    ::contact::internal::SymmetricMultiply(built->model.M, du, &Mdu);
    recorder->energy =
        ::contact::internal::EnergyBalance(u0, u_previous, Ku, Mdu, options.dt);
    recorder->lambda0 = initial.contact().normal_force.unaryExpr(
        [](double l) { return std::isfinite(l) ? l : 0.0; });
  }
  const Eigen::VectorXd f = ::contact::internal::SceneLoadVector(scene, *built);
  const int width = NodeData::Width(dim);
  std::vector<double> data(
      static_cast<size_t>(width) * static_cast<size_t>(mesh.NumNodes()), 0.0);
  for (int i = 0; i < mesh.NumNodes(); ++i) {
    double* d = &data[static_cast<size_t>(width) * static_cast<size_t>(i)];
    d[4 * dim] = -1.0;  // no contact node
    for (int a = 0; a < dim; ++a) {
      const int free = built->dofs.FreeIndex(dim * i + a);
      d[a] = free;
      if (free < 0) continue;
      d[dim + a] = u0(free);
      d[2 * dim + a] = u_previous(free);
      d[3 * dim + a] = f(free);
    }
  }
  for (size_t c = 0; c < built->frames.nodes.size(); ++c) {
    const ContactNode& node = built->frames.nodes[c];
    double* d = &data[static_cast<size_t>(width) * static_cast<size_t>(node.node)];
    d[4 * dim] = static_cast<double>(c);
    for (int a = 0; a < 3; ++a) {
      d[4 * dim + 1 + a] = node.normal(a);
      d[4 * dim + 4 + a] = node.tangent1(a);
      d[4 * dim + 7 + a] = node.tangent2(a);
    }
    d[4 * dim + 10] = node.gap;
    d[4 * dim + 11] = recorder->lambda0(static_cast<Eigen::Index>(c));
  }
  return data;
}

// A contact node owned by this rank: its frame with dofs = indices into the owned arrays.
struct OwnedContactNode {
  ContactNode node;   // node.node = the contact node's index in the serial order
  double lambda = 0;  // lambda^k [N]
  ::contact::internal::ExplicitNodeStep step;
};

// The owned free dofs of a global Vec on rank 0 in the serial free-dof numbering.
Eigen::VectorXd GatherFreeDofs(const DistributedBody& body, Vec v, int num_free_dofs) {
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(v));
  Vec serial_order = nullptr, root = nullptr;
  VecScatter to_zero = nullptr;
  CONTACT_PETSC_CHECK(VecCreateMPI(comm, PETSC_DECIDE, num_free_dofs, &serial_order));
  const PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(v, &x));
  for (int i = 0; i < body.NumLocalVertices(); ++i)
    for (int a = 0; a < body.dim(); ++a)
      if (body.OwnedIndex(i, a) >= 0)
        CONTACT_PETSC_CHECK(VecSetValue(serial_order,
                                        static_cast<PetscInt>(body.Data(i)[a]),
                                        x[body.OwnedIndex(i, a)], INSERT_VALUES));
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(v, &x));
  CONTACT_PETSC_CHECK(VecAssemblyBegin(serial_order));
  CONTACT_PETSC_CHECK(VecAssemblyEnd(serial_order));
  CONTACT_PETSC_CHECK(VecScatterCreateToZero(serial_order, &to_zero, &root));
  CONTACT_PETSC_CHECK(
      VecScatterBegin(to_zero, serial_order, root, INSERT_VALUES, SCATTER_FORWARD));
  CONTACT_PETSC_CHECK(
      VecScatterEnd(to_zero, serial_order, root, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt size = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(root, &size));
  Eigen::VectorXd out(size);
  const PetscScalar* r = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(root, &r));
  for (PetscInt i = 0; i < size; ++i) out(i) = r[i];
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(root, &r));
  VecScatterDestroy(&to_zero);
  VecDestroy(&root);
  VecDestroy(&serial_order);
  return out;
}

// The files of the run: on rank 0 the CSVs of one process (steps.csv, contact_stress.csv,
// node_history.csv, displacement.csv; not the mesh CSVs); per snapshot one .vtu
// piece per rank (its cells, the displacement of their vertices and the rank as a cell
// field), the .pvtu that joins them and solution.pvd listing the .pvtu files (rank 0).
class DistributedOutput {
 public:
  DistributedOutput(MPI_Comm comm, const Scene& scene,
                    std::vector<std::string>* files_written)
      : comm_(comm),
        scene_(scene),
        rank_(RankOf(comm)),
        size_(SizeOf(comm)),
        directory_(scene.output_directory),
        files_written_(files_written) {
    if (directory_.empty()) return;
    int created = 1;
    if (rank_ == 0) {
      std::error_code error;
      std::filesystem::create_directories(directory_, error);
      created = error ? 0 : 1;
      if (created) {
        namespace in = ::contact::internal;
        steps_ = Open("steps.csv", in::kStepsCsvHeader);
        stress_ = Open("contact_stress.csv", in::ContactStressCsvHeader(scene.dim));
        if (scene.marked_point)
          history_ = Open("node_history.csv", in::kNodeHistoryCsvHeader);
        displacement_ = Open("displacement.csv", in::DisplacementCsvHeader(scene.dim));
      }
    }
    MPI_Bcast(&created, 1, MPI_INT, 0, comm_);  // (the pieces go into the directory)
    if (!created)
      throw ncp::OutputError("cannot create directory", directory_.string(), 0);
  }

  bool enabled() const { return !directory_.empty(); }

  /// Rank 0, after each step: steps.csv's row, the marked node's node_history.csv row
  /// (marked >= 0: its index in nodes) and, with u_free (the free dofs in the serial
  /// numbering) at a stress time or the end, the displacement.csv and contact_stress.csv
  /// rows - as SceneOutput::WriteStep; contact in system units (times force_scale [N]).
  void WriteStep(const StepRecord& record, const Mesh& mesh, const DofMap& dofs,
                 const std::vector<ContactNode>& nodes, int marked,
                 const ContactSystem::Result& contact, double force_scale,
                 const Eigen::VectorXd* u_free) {
    if (directory_.empty() || rank_ != 0) return;
    namespace in = ::contact::internal;
    in::WriteStepsCsvRow(record, &steps_.stream());
    if (marked >= 0)
      in::WriteNodeHistoryRow(record.time, mesh.dim, nodes, static_cast<size_t>(marked),
                              contact, force_scale, &history_.stream());
    if (u_free) {
      in::WriteDisplacementRows(record.time, mesh, dofs, *u_free,
                                &displacement_.stream());
      in::WriteContactStressRows(record.time, mesh, nodes, contact, force_scale,
                                 &stress_.stream());
    }
    for (ncp::OutputFile* csv : {&steps_, &history_, &stress_, &displacement_})
      if (csv->is_open()) csv->Commit();
  }

  /// Collective: the snapshot of `step` at `time` with one process's fields
  /// (PieceFields: u, u_previous the global u^{k+1}, u^k, or null for the start) and the
  /// rank as a cell field.
  void WriteSnapshot(const DistributedBody& body, Vec u, Vec u_previous,
                     const internal::SnapshotContact& contact, int step, double time) {
    if (directory_.empty()) return;
    if (!local_body_ && body.local_mesh().NumElements() > 0)
      local_body_ =
          std::make_unique<ElasticBody>(body.local_mesh(), scene_.material, scene_.plane);
    auto [points, cells] =
        internal::PieceFields(body, local_body_.get(), u, u_previous, scene_, contact);
    const Mesh& mesh = body.local_mesh();
    cells.push_back({"rank", Eigen::MatrixXd::Constant(1, mesh.NumElements(), rank_)});
    std::vector<std::string> pieces;
    for (int r = 0; r < size_; ++r)
      pieces.push_back(SnapshotFileName(step, "_rank_" + std::to_string(r) + ".vtu"));
    const std::string piece = (directory_ / pieces[static_cast<size_t>(rank_)]).string();
    WriteVtu(piece, mesh, points, cells);
    MPI_Barrier(comm_);  // (every piece is on disk before the .pvtu names it)
    if (rank_ != 0) return;
    const std::string name = SnapshotFileName(step, ".pvtu");
    WritePvtu((directory_ / name).string(), points, cells, pieces);
    series_.emplace_back(time, name);
    WritePvd((directory_ / "solution.pvd").string(), series_);
    for (const std::string& p : pieces)
      files_written_->push_back((directory_ / p).string());
    files_written_->push_back((directory_ / name).string());
  }

  /// Rank 0: closes the CSVs (checked).
  void Finish() {
    if (directory_.empty() || rank_ != 0) return;
    for (ncp::OutputFile* csv : {&steps_, &history_, &stress_, &displacement_})
      if (csv->is_open()) csv->Close();
    files_written_->push_back((directory_ / "solution.pvd").string());
  }

 private:
  MPI_Comm comm_;
  const Scene& scene_;
  int rank_, size_;
  std::filesystem::path directory_;
  // A CSV of rank 0, opened with its header.
  ncp::OutputFile Open(const std::string& name, const std::string& header) {
    const std::string path = (directory_ / name).string();
    ncp::OutputFile file = ncp::OutputFile::Open(path);
    file.stream() << header << "\n";
    file.stream().precision(10);
    file.Commit();
    files_written_->push_back(path);
    return file;
  }

  std::vector<std::string>* files_written_;
  ncp::OutputFile steps_, stress_, history_, displacement_;
  std::vector<std::pair<double, std::string>> series_;
  std::unique_ptr<ElasticBody> local_body_;  // the stresses of this rank's cells
};

// The distributed explicit time loop over the owned free dofs of `body`.
class ExplicitRun {
 public:
  ExplicitRun(MPI_Comm comm, const Scene& scene, const DistributedBody& body)
      : comm_(comm),
        scene_(scene),
        body_(body),
        dim_(body.dim()),
        dt_(scene.dynamics.dt) {
    DM dm = body.dm();
    for (Vec* v : Vectors()) CONTACT_PETSC_CHECK(DMCreateGlobalVector(dm, v));
    CONTACT_PETSC_CHECK(VecGetLocalSize(u_, &n_));
    CONTACT_PETSC_CHECK(VecMax(body.lumped_mass(), nullptr, &m_max_));
    force_scale_ = m_max_ / (dt_ * dt_);
    SetInitialState();
  }
  ~ExplicitRun() {
    for (Vec* v : Vectors()) VecDestroy(v);
  }
  ExplicitRun(const ExplicitRun&) = delete;
  ExplicitRun& operator=(const ExplicitRun&) = delete;

  Vec displacement() const { return u_; }
  Vec previous_displacement() const { return u_previous_; }
  double m_max() const { return m_max_; }

  /// Step k -> k+1 on this rank's dofs and contact nodes, u^{k+1} and K u^{k+1}
  /// (collective: MatMult); *part and *nodes: what the step's record needs from here.
  void Step(long k, bool stop_requested, RankStepPart* part,
            std::vector<NodeResult>* results) {
    *part = RankStepPart();
    part->sum[RankStepPart::kStopRequested] = stop_requested ? 1.0 : 0.0;
    const double factor = ::contact::internal::LoadHistoryFactor(
        scene_.load_history, scene_.dynamics.start_time, scene_.ramp_time,
        scene_.dynamics.start_time + static_cast<double>(k) * dt_);
    {
      Arrays a(*this);
      Predict(factor, a, part);
      SolveContactNodes(a, part);
      Advance(factor, a, part);
      Results(a, results);
    }
    // u^{k-1} <- u^k <- u^{k+1} (the handles), then K u^{k+1} and its products.
    std::swap(u_previous_, u_);
    std::swap(u_, u_next_);
    CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_, Ku_));
    const PetscScalar *u = nullptr, *u_previous = nullptr, *Ku = nullptr;
    CONTACT_PETSC_CHECK(VecGetArrayRead(u_, &u));
    CONTACT_PETSC_CHECK(VecGetArrayRead(u_previous_, &u_previous));
    CONTACT_PETSC_CHECK(VecGetArrayRead(Ku_, &Ku));
    for (PetscInt i = 0; i < n_; ++i) {
      part->sum[RankStepPart::kUKuNext] += u_previous[i] * Ku[i];
      part->sum[RankStepPart::kUNextKuNext] += u[i] * Ku[i];
    }
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(Ku_, &Ku));
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(u_previous_, &u_previous));
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(u_, &u));
  }

 private:
  std::vector<Vec*> Vectors() {
    return {&u_, &u_previous_, &u_next_, &du_, &Ku_, &Mdu_, &f_free_, &Q_, &q_, &d_, &r_};
  }

  // The owned arrays of the state vectors for one step.
  struct Arrays {
    explicit Arrays(const ExplicitRun& run) : run_(run) {
      CONTACT_PETSC_CHECK(VecGetArray(run.u_next_, &u_next));
      CONTACT_PETSC_CHECK(VecGetArray(run.du_, &du));
      CONTACT_PETSC_CHECK(VecGetArray(run.Mdu_, &Mdu));
      CONTACT_PETSC_CHECK(VecGetArray(run.Q_, &Q));
      CONTACT_PETSC_CHECK(VecGetArray(run.q_, &q));
      CONTACT_PETSC_CHECK(VecGetArray(run.r_, &r));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.u_, &u));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.u_previous_, &u_previous));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.Ku_, &Ku));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.f_free_, &f_free));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.d_, &d));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.body_.lumped_mass(), &m));
    }
    ~Arrays() {
      VecRestoreArray(run_.u_next_, &u_next);
      VecRestoreArray(run_.du_, &du);
      VecRestoreArray(run_.Mdu_, &Mdu);
      VecRestoreArray(run_.Q_, &Q);
      VecRestoreArray(run_.q_, &q);
      VecRestoreArray(run_.r_, &r);
      VecRestoreArrayRead(run_.u_, &u);
      VecRestoreArrayRead(run_.u_previous_, &u_previous);
      VecRestoreArrayRead(run_.Ku_, &Ku);
      VecRestoreArrayRead(run_.f_free_, &f_free);
      VecRestoreArrayRead(run_.d_, &d);
      VecRestoreArrayRead(run_.body_.lumped_mass(), &m);
    }
    Arrays(const Arrays&) = delete;
    Arrays& operator=(const Arrays&) = delete;
    const ExplicitRun& run_;
    PetscScalar *u_next = nullptr, *du = nullptr, *Mdu = nullptr, *Q = nullptr,
                *q = nullptr, *r = nullptr;
    const PetscScalar *u = nullptr, *u_previous = nullptr, *Ku = nullptr,
                      *f_free = nullptr, *d = nullptr, *m = nullptr;
  };

  // Q^k = K u^k - f^k - M (u^k - u^{k-1}) / dt^2, q = Q^k / force_scale and the
  // increment off contact du = -q / d (dynamics.cpp LoadStep, explicit_step.cpp), with
  // the maxima of the step's scales.
  void Predict(double factor, Arrays& a, RankStepPart* part) const {
    double* max = part->max;
    for (PetscInt i = 0; i < n_; ++i) {
      const double f = factor * a.f_free[i];
      a.Q[i] = a.Ku[i] - f - a.Mdu[i] / (dt_ * dt_);
      a.q[i] = a.Q[i] / force_scale_;
      a.du[i] = -a.q[i] / a.d[i];
      max[RankStepPart::kF] = std::max(max[RankStepPart::kF], std::abs(f));
      max[RankStepPart::kKu] = std::max(max[RankStepPart::kKu], std::abs(a.Ku[i]));
      max[RankStepPart::kQ] = std::max(max[RankStepPart::kQ], std::abs(a.Q[i]));
      max[RankStepPart::kDu] =
          std::max(max[RankStepPart::kDu], std::abs(a.u[i] - a.u_previous[i]));
    }
  }

  // Per owned contact node the closed form of SolveExplicitContactNode with the Tresca
  // bound f_c lambda^k, and the penetration of u^k (the displacement scale).
  void SolveContactNodes(Arrays& a, RankStepPart* part) {
    const double friction = scene_.friction_coefficient;
    double& penetration = part->max[RankStepPart::kPenetration];
    for (OwnedContactNode& n : nodes_) {
      double un = 0.0;
      for (int c = 0; c < 3; ++c)
        if (n.node.dofs[c] >= 0) un += n.node.normal(c) * a.u[n.node.dofs[c]];
      penetration = std::max(penetration, un - n.node.gap);
      const double bound =
          friction > 0.0 ? (friction / force_scale_) * std::max(n.lambda, 0.0) : 0.0;
      const int first_free = n.node.dofs[0] >= 0   ? n.node.dofs[0]
                             : n.node.dofs[1] >= 0 ? n.node.dofs[1]
                                                   : n.node.dofs[2];
      n.step = ::contact::internal::SolveExplicitContactNode(
          dim_, n.node, a.d[first_free], n.node.gap, bound, a.q, a.u, a.du);
      n.lambda = force_scale_ * n.step.normal_force;
    }
  }

  // u^{k+1} = u^k + du, M du, r = M du / dt^2 + Q^k (the contact forces at the contact
  // nodes, else the equilibrium residual), the energy sums and the maxima
  // (dynamics.cpp MeasureStep, energy_balance.cpp).
  void Advance(double factor, Arrays& a, RankStepPart* part) const {
    double* sum = part->sum;
    double* max = part->max;
    for (PetscInt i = 0; i < n_; ++i) {
      if (!std::isfinite(a.du[i])) sum[RankStepPart::kNonFinite] = 1.0;
      const double f = factor * a.f_free[i];
      a.u_next[i] = a.u[i] + a.du[i];
      a.Mdu[i] = a.m[i] * a.du[i];
      a.r[i] = a.Mdu[i] / (dt_ * dt_) + a.Q[i];
      sum[RankStepPart::kDuMdu] += a.du[i] * a.Mdu[i];
      sum[RankStepPart::kFUNext] += f * a.u_next[i];
      sum[RankStepPart::kFUPrevious] += f * a.u_previous[i];
      max[RankStepPart::kMdu] = std::max(max[RankStepPart::kMdu], std::abs(a.Mdu[i]));
      max[RankStepPart::kUNext] =
          std::max(max[RankStepPart::kUNext], std::abs(a.u_next[i]));
      if (!contact_dof_[static_cast<size_t>(i)])
        max[RankStepPart::kRFree] = std::max(max[RankStepPart::kRFree], std::abs(a.r[i]));
    }
  }

  // The owned contact nodes' results for rank 0.
  void Results(const Arrays& a, std::vector<NodeResult>* results) const {
    results->resize(nodes_.size());
    for (size_t j = 0; j < nodes_.size(); ++j) {
      const OwnedContactNode& n = nodes_[j];
      NodeResult& out = (*results)[j];
      out.index = n.node.node;
      out.normal_force = n.step.normal_force;
      out.gap = n.step.gap;
      out.tangent_force = n.step.tangent_force;
      out.slip = n.step.slip;
      for (int c = 0; c < dim_; ++c) {
        const int i = n.node.dofs[c];
        out.r(c) = i >= 0 ? a.r[i] : 0.0;
        out.u_next(c) = i >= 0 ? a.u_next[i] : 0.0;
        out.u_previous(c) = i >= 0 ? a.u_previous[i] : 0.0;
      }
    }
  }

  // u^0, u^{-1}, f_F, M (u^0 - u^{-1}), K u^0, d = m / m_max and the owned contact nodes,
  // from the node data rank 0 sent.
  void SetInitialState() {
    PetscScalar *u = nullptr, *u_previous = nullptr, *Mdu = nullptr, *f = nullptr,
                *d = nullptr;
    const PetscScalar* m = nullptr;
    CONTACT_PETSC_CHECK(VecGetArray(u_, &u));
    CONTACT_PETSC_CHECK(VecGetArray(u_previous_, &u_previous));
    CONTACT_PETSC_CHECK(VecGetArray(Mdu_, &Mdu));
    CONTACT_PETSC_CHECK(VecGetArray(f_free_, &f));
    CONTACT_PETSC_CHECK(VecGetArray(d_, &d));
    CONTACT_PETSC_CHECK(VecGetArrayRead(body_.lumped_mass(), &m));
    contact_dof_.assign(static_cast<size_t>(n_), 0);
    body_.UnpackStart(u, u_previous, f, &contact_dof_);
    for (PetscInt k = 0; k < n_; ++k) {
      Mdu[k] = m[k] * (u[k] - u_previous[k]);  // M (u^0 - u^{-1})
      d[k] = m[k] / m_max_;
    }
    for (int i = 0; i < body_.NumLocalVertices(); ++i) {
      const double* data = body_.Data(i);
      const bool contact_node = body_.Owns(i) && data[4 * dim_] >= 0;
      if (!contact_node) continue;
      OwnedContactNode n;
      n.node.node = static_cast<int>(data[4 * dim_]);
      for (int c = 0; c < dim_; ++c)
        n.node.dofs[c] = static_cast<int>(body_.OwnedIndex(i, c));
      for (int c = 0; c < 3; ++c) {
        n.node.normal(c) = data[4 * dim_ + 1 + c];
        n.node.tangent1(c) = data[4 * dim_ + 4 + c];
        n.node.tangent2(c) = data[4 * dim_ + 7 + c];
      }
      n.node.gap = data[4 * dim_ + 10];
      n.lambda = data[4 * dim_ + 11];
      nodes_.push_back(n);
    }
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(body_.lumped_mass(), &m));
    CONTACT_PETSC_CHECK(VecRestoreArray(d_, &d));
    CONTACT_PETSC_CHECK(VecRestoreArray(f_free_, &f));
    CONTACT_PETSC_CHECK(VecRestoreArray(Mdu_, &Mdu));
    CONTACT_PETSC_CHECK(VecRestoreArray(u_previous_, &u_previous));
    CONTACT_PETSC_CHECK(VecRestoreArray(u_, &u));
    CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_, Ku_));
  }

  MPI_Comm comm_;
  const Scene& scene_;
  const DistributedBody& body_;
  int dim_;
  double dt_;
  PetscInt n_ = 0;          // owned free dofs
  PetscReal m_max_ = 0.0;   // largest lumped mass [kg]
  double force_scale_ = 0;  // m_max / dt^2 [N]
  // u^k, u^{k-1}, u^{k+1} [m]; du = u^{k+1} - u^k [m]; Ku = K u^k [N]; Mdu = M (u^k -
  // u^{k-1}), then M du [kg m]; f_F [N]; Q^k [N]; q (system units); d = m / m_max (the
  // diagonal of S); r = M du / dt^2 + Q^k [N].
  Vec u_ = nullptr, u_previous_ = nullptr, u_next_ = nullptr, du_ = nullptr,
      Ku_ = nullptr, Mdu_ = nullptr, f_free_ = nullptr, Q_ = nullptr, q_ = nullptr,
      d_ = nullptr, r_ = nullptr;
  std::vector<char> contact_dof_;  // per owned free dof: of an owned contact node
  std::vector<OwnedContactNode> nodes_;
};

void BroadcastString(MPI_Comm comm, std::string* s) {
  int length = static_cast<int>(s->size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  s->resize(static_cast<size_t>(length));
  MPI_Bcast(s->data(), length, MPI_CHAR, 0, comm);
}

// Broadcasts rank 0's StartInfo and summary status/message.
void ShareStart(MPI_Comm comm, StartInfo* info, DynamicSummary* summary) {
  MPI_Bcast(&info->refused, 1, MPI_INT, 0, comm);
  double reals[2] = {info->critical_time_step, info->m_max};
  MPI_Bcast(reals, 2, MPI_DOUBLE, 0, comm);
  info->critical_time_step = reals[0], info->m_max = reals[1];
  int counts[5] = {info->num_dofs, info->num_free_dofs, info->num_contact_nodes,
                   info->num_elements, info->method};
  MPI_Bcast(counts, 5, MPI_INT, 0, comm);
  info->num_dofs = counts[0], info->num_free_dofs = counts[1];
  info->num_contact_nodes = counts[2], info->num_elements = counts[3];
  info->method = counts[4];
  int status = static_cast<int>(summary->status);
  MPI_Bcast(&status, 1, MPI_INT, 0, comm);
  summary->status = static_cast<DynamicStatus>(status);
  BroadcastString(comm, &summary->message);
}

// Broadcasts rank 0's final status, message and step count.
void ShareEnd(MPI_Comm comm, DynamicSummary* summary) {
  int values[2] = {static_cast<int>(summary->status), summary->steps};
  MPI_Bcast(values, 2, MPI_INT, 0, comm);
  summary->status = static_cast<DynamicStatus>(values[0]);
  summary->steps = values[1];
  BroadcastString(comm, &summary->message);
}

}  // namespace

std::string WhyNotDistributed(const Scene& scene) {
  const std::string supported =
      "on more than one MPI rank contact-sim runs the explicit step (solver.step = "
      "\"explicit\" with mass = \"lumped\"), the condensed step with the contact set "
      "gathered (solver.step = \"condensed\", friction \"coulomb-fc\"), the sparse "
      "step (solver.step = \"sparse\", W never formed) and \"auto\" choosing among "
      "them";
  const StepMethod method = scene.dynamics.step_method;
  if (method != StepMethod::kExplicit && method != StepMethod::kCondensed &&
      method != StepMethod::kSparse && method != StepMethod::kAuto)
    return scene.source + ": the scene's step is '" + ToString(method) + "'; " +
           supported;
  if (method == StepMethod::kExplicit && scene.mass != MassKind::kLumped)
    return scene.source +
           ": the explicit step needs mass = \"lumped\" (the scene's mass is "
           "consistent); " +
           supported;
  if ((method == StepMethod::kCondensed || method == StepMethod::kSparse) &&
      scene.friction_coefficient > 0.0 &&
      scene.dynamics.friction_formulation == FrictionFormulation::kLaggedBound)
    return scene.source + ": the " + ToString(method) +
           " step on MPI ranks poses friction as implicit Coulomb "
           "(solver.friction = \"coulomb-fc\"), not with the lagged bound; " +
           supported;
  if (scene.dynamics.compare_with_ipopt)
    return scene.source + ": compare_with_ipopt is not available on MPI ranks; " +
           supported;
  if (scene.kinematics.kinematics == Kinematics::kFinite ||
      scene.kinematics.model != MaterialModel::kLinear)
    return scene.source + ": material.kinematics = \"" +
           ToString(scene.kinematics.kinematics) + "\" with material.model = \"" +
           ToString(scene.kinematics.model) +
           "\": finite strain runs on one process only (MPI ranks run small strain, "
           "material.model = \"linear\")";
  return ::contact::internal::SerialOnlySceneFeature(scene);
}

SceneResult RunSceneDistributed(const Scene& scene, MPI_Comm comm, bool progress) {
  const std::string why_not = WhyNotDistributed(scene);
  if (!why_not.empty()) throw std::invalid_argument(why_not);
  const auto start = Clock::now();
  const int rank = RankOf(comm);
  SceneResult result;
  DynamicSummary& summary = result.summary;
  std::unique_ptr<SceneModel> built;
  StartInfo info;
  std::vector<double> node_data;
  RecorderStart recorder_start;
  // A refused scene or mesh on rank 0 is refused on every rank (no rank left waiting).
  std::string error;
  if (rank == 0) {
    try {
      built = std::make_unique<SceneModel>();
      node_data = ::contact::internal::NamingTheScene(scene, [&] {
        return SerialSetUp(scene, built.get(), &summary, &info, &recorder_start);
      });
      built->model = DynamicModel();  // (the serial K and M: not needed any more)
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  BroadcastString(comm, &error);
  if (!error.empty()) throw SceneError(error);
  ShareStart(comm, &info, &summary);
  result.num_dofs = info.num_dofs, result.num_free_dofs = info.num_free_dofs;
  result.num_contact_nodes = info.num_contact_nodes,
  result.num_elements = info.num_elements;
  summary.critical_time_step = info.critical_time_step;
  const auto method = static_cast<StepMethod>(info.method);
  summary.step_method = method;
  if (info.refused) return result;

  const double setup_seconds = Seconds(start);
  const double setup_peak = rank == 0 && progress ? PeakResidentMiB() : -1.0;
  // The condensed and the sparse step: the same step, W formed or applied (the sparse).
  const bool condensed =
      method == StepMethod::kCondensed || method == StepMethod::kSparse;
  const DistributedBody body(comm, scene, built.get(), node_data, condensed);
  node_data = {};
  const double assembly_peak = rank == 0 && progress ? PeakResidentMiB() : -1.0;
  const bool serial_matrices = !SetUpWithoutSerialMatrices(scene);
  const bool start_on_ranks = StartCompletedOnRanks(scene);
  if (start_on_ranks && !condensed)  // (WhyNotDistributed refuses it)
    throw std::logic_error("contact::petsc: a consistent mass needs the implicit step");
  if (start_on_ranks) info.m_max = MaxAbsEntry(body.mass_matrix());
  // The condensed and sparse steps' solver of M (factored here) completes the start and,
  // with a consistent mass, serves dt_crit; their contact problem waits for dt's check.
  std::unique_ptr<CondensedGatheredStep> condensed_run;
  if (condensed)
    condensed_run = std::make_unique<CondensedGatheredStep>(
        comm, scene, body, built ? &built->frames.nodes : nullptr, info.m_max,
        method == StepMethod::kSparse ? internal::SparseContactSolve()
                                      : internal::ContactSolve::kGatheredDense,
        start_on_ranks);
  const auto lanczos_start = Clock::now();
  if (!serial_matrices) {
    // dt_crit on the ranks; every rank has the same estimate, so the same outcome.
    summary.predicted_cost = StepCostPrediction();  // (the serial prediction needs K)
    internal::MassSolve solve_consistent;
    if (scene.mass == MassKind::kConsistent)
      solve_consistent = [&condensed_run](Vec b, Vec x) {
        if (!condensed_run->SolveMass(b, x))
          throw std::invalid_argument("contact::petsc: dt_crit by Lanczos: " +
                                      condensed_run->failure());
      };
    if (!::contact::internal::AcceptCriticalStep(
            internal::DistributedCriticalTimeStep(body, solve_consistent), scene.dynamics,
            &summary))
      return result;
  }
  const double lanczos_seconds = Seconds(lanczos_start);
  if (condensed_run) condensed_run->SetUpContact();
  if (start_on_ranks) recorder_start.energy = condensed_run->StartEnergy();
  if (progress && rank == 0)
    std::fprintf(stderr,
                 "  set-up on rank 0: %s %.3g s; DMPlex and distribution (%s) %.3g s, "
                 "section %.3g s, assembly of K and M %.3g s\n",
                 serial_matrices  ? "model, dt_crit and initial state"
                 : start_on_ranks ? "mesh, contact frames and load"
                                  : "mesh, contact frames, lumped mass and initial state",
                 setup_seconds, body.partitioner().c_str(), body.distribute_seconds(),
                 body.section_seconds(), body.assemble_seconds());
  if (progress && rank == 0 && !serial_matrices)
    std::fprintf(stderr, "  dt_crit = %.6g s by Lanczos on the ranks' K and %s: %.3g s\n",
                 summary.critical_time_step,
                 scene.mass == MassKind::kConsistent ? "M (solves with M)" : "lumped M",
                 lanczos_seconds);
  if (progress && rank == 0 && start_on_ranks)
    std::fprintf(stderr,
                 "  the start completed on the ranks: u^-1 += dt^2/2 M^-1 (f - K u^0)\n");
  if (progress && rank == 0)
    std::fprintf(stderr,
                 "  rank 0's peak memory: %.0f MiB after its set-up, %.0f MiB after the "
                 "distribution and assembly, %.0f MiB after the set-up of the step\n",
                 setup_peak, assembly_peak, PeakResidentMiB());
  if (progress && rank == 0 && condensed_run)
    std::fprintf(
        stderr,
        "  %s step on ranks: %d contact unknowns %s (W %s); "
        "solves with M by %s; factor %.3g s, W %.3g s\n",
        ToString(method), condensed_run->num_contact_unknowns(),
        condensed_run->contact_solve() == internal::ContactSolve::kDistributed
            ? "on the ranks that own their contact nodes"
            : "gathered on rank 0",
        method == StepMethod::kSparse ? "applied, one solve per product" : "formed",
        condensed_run->mass_solver().c_str(), condensed_run->factor_seconds(),
        condensed_run->delassus_seconds());
  DistributedOutput output(comm, scene, &result.files_written);
  std::unique_ptr<ExplicitRun> explicit_run;
  if (!condensed) explicit_run = std::make_unique<ExplicitRun>(comm, scene, body);
  // u^k [m] (a step may swap the explicit run's Vecs: asked anew each time).
  const auto u_run = [&] {
    return condensed ? condensed_run->displacement() : explicit_run->displacement();
  };
  const auto u_previous_run = [&] {  // u^{k-1} [m] after a step: the snapshot's u^k
    return condensed ? condensed_run->previous_displacement()
                     : explicit_run->previous_displacement();
  };
  // The step scaling S = M / m_max: the largest lumped mass (explicit) or entry of M_FF.
  const double m_max = condensed ? info.m_max : explicit_run->m_max();
  internal::StepGather gather(comm, scene.dim, info.num_contact_nodes);
  // Rank 0 keeps of the serial set-up what the records and the output need (mesh,
  // Dirichlet map, contact nodes).
  Mesh mesh;
  DofMap dofs;
  std::unique_ptr<internal::StepRecorder> recorder;
  std::vector<ContactNode> nodes;
  int marked = -1;  // output.marked_point's contact node
  if (built) {
    mesh = built->body->mesh();
    dofs = built->dofs;
    nodes = built->frames.nodes;
    if (scene.marked_point) {
      marked = ::contact::internal::NearestContactNode(mesh, nodes, *scene.marked_point);
      result.marked_node = nodes[static_cast<size_t>(marked)].node;
    }
    recorder = std::make_unique<internal::StepRecorder>(
        scene, method, built->frames.nodes, recorder_start.lambda0, recorder_start.energy,
        m_max);
    built.reset();
  }
  const DynamicOptions& options = scene.dynamics;
  const long num_steps = static_cast<long>(
      std::ceil((options.end_time - options.start_time) / options.dt - 1e-3));
  if (options.initial_state == InitialState::kPrescribed)  // (as one process: u^0, v^0)
    output.WriteSnapshot(body, nullptr, nullptr,
                         internal::StartSnapshotContact(body, info.num_contact_nodes), 0,
                         options.start_time);
  const double force_scale = m_max / (options.dt * options.dt);
  std::vector<double> stress_times = scene.stress_times;
  std::sort(stress_times.begin(), stress_times.end());
  RankStepPart part;
  std::vector<NodeResult> node_results;
  GatheredStep gathered;
  double last_progress = 0.0;
  summary.status = DynamicStatus::kNotRun;
  for (long k = 0; k < num_steps; ++k) {
    const auto step_start = Clock::now();
    StepRecord rec;
    rec.step = static_cast<int>(k + 1);
    rec.time = options.start_time + static_cast<double>(k) * options.dt + options.dt;
    // Rank 0 records the step and decides for every rank whether the run goes on.
    enum Decision : int { kGoOn, kStopAfterRecord, kStopUnrecorded };
    int decision = kGoOn;
    const int stop_read =
        options.stop_requested && options.stop_requested->load() ? 1 : 0;
    if (condensed) {
      if (!condensed_run->Step(k, stop_read != 0, recorder.get(), &part, &node_results,
                               &rec)) {
        summary.status = DynamicStatus::kSolverFailure;
        summary.message = "step " + std::to_string(k + 1) +
                          " (t = " + std::to_string(rec.time) +
                          " s): " + condensed_run->failure();
        break;
      }
    } else {
      explicit_run->Step(k, stop_read != 0, &part, &node_results);
    }
    rec.solve_seconds = Seconds(step_start);
    gather.Gather(part, node_results, &gathered);
    if (rank == 0) {
      summary.newton_iterations += rec.newton_iterations;
      summary.jacobian_evaluations += rec.jacobian_evaluations;
      summary.residual_evaluations += rec.residual_evaluations;
      summary.krylov_iterations += rec.krylov_iterations;
      if (!recorder->Record(&gathered, num_steps, &rec, &summary))
        decision = summary.status == DynamicStatus::kSolverFailure ? kStopUnrecorded
                                                                   : kStopAfterRecord;
      rec.seconds = Seconds(step_start);
    }
    MPI_Bcast(&decision, 1, MPI_INT, 0, comm);
    if (decision == kStopUnrecorded) break;
    const bool go_on = decision == kGoOn;
    summary.steps = rec.step;
    // The end and the stress times as SceneOutput::WriteStep decides them.
    const bool last = rec.time >= options.end_time - 1e-9 * options.dt;
    const bool stress_time =
        ::contact::internal::ConsumeStressTimes(rec.time, options.dt, &stress_times);
    Eigen::VectorXd u_free;
    if (output.enabled() && (stress_time || last))
      u_free = GatherFreeDofs(body, u_run(), info.num_free_dofs);
    output.WriteStep(rec, mesh, dofs, nodes, marked, gathered.contact, force_scale,
                     stress_time || last ? &u_free : nullptr);
    if ((scene.snapshot_every > 0 && rec.step % scene.snapshot_every == 0) || last)
      output.WriteSnapshot(
          body, u_run(), u_previous_run(),
          internal::ShareSnapshotContact(comm, scene.dim, info.num_contact_nodes,
                                         &gathered.contact, force_scale,
                                         rec.force_accuracy, rec.displacement_accuracy),
          rec.step, rec.time);
    if (rank == 0) {
      summary.records.push_back(rec);
      if (progress && Seconds(start) - last_progress > 1.0) {
        last_progress = Seconds(start);
        std::fprintf(stderr, "  step %d / %ld, t = %.6g s (%s, %d ranks)\n", rec.step,
                     num_steps, rec.time, ToString(method), SizeOf(comm));
      }
    }
    if (!go_on) break;
  }
  if (rank == 0) {
    if (summary.status == DynamicStatus::kNotRun) recorder->Finish(&summary);
    if (summary.status == DynamicStatus::kCompleted)
      summary.message = "all " + std::to_string(summary.steps) +
                        " time steps solved to their accuracy on " +
                        std::to_string(SizeOf(comm)) + " MPI ranks (" + ToString(method) +
                        " step, partitioner " + body.partitioner() + ")";
  }
  if (progress && rank == 0 && method == StepMethod::kSparse)
    std::fprintf(stderr,
                 "  sparse step on ranks: %ld products with W (distributed solves)\n",
                 condensed_run->delassus_products());
  ShareEnd(comm, &summary);
  const Eigen::VectorXd u = GatherFreeDofs(body, u_run(), info.num_free_dofs);
  if (rank == 0) summary.u = u;
  output.Finish();
  summary.seconds = Seconds(start);
  return result;
}

}  // namespace contact::petsc
