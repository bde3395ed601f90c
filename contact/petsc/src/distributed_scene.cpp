// A scene on MPI ranks with the explicit step (contact/petsc/distributed_scene.hpp).
//
// Set-up on rank 0 (not yet distributed): the scene's model as contact-sim builds it
// (BuildSceneModel), and contact::Simulation's critical time step and initial state. Then
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

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>

#include "contact/simulation.hpp"
#include "contact/vtk_writer.hpp"
#include "distributed_body.hpp"
#include "distributed_implicit_step.hpp"
#include "mass_inverse.hpp"
#include "ncp/output_file.hpp"
#include "petsc_check.hpp"
#include "scene/scene_error.hpp"
#include "scene/scene_load.hpp"
#include "scene/scene_output.hpp"
#include "step/explicit_contact_node.hpp"

namespace contact::petsc {
namespace {

using internal::CondensedGatheredStep;
using internal::DistributedBody;
using internal::NodeData;
using Clock = std::chrono::steady_clock;
constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

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

// What rank 0 has computed before the distributed steps, and tells every rank.
struct StartInfo {
  int refused = 0;  // the serial set-up refused the run (summary says why)
  double critical_time_step = 0.0;  // [s]
  int num_dofs = 0, num_free_dofs = 0, num_contact_nodes = 0, num_elements = 0;
  int method = static_cast<int>(StepMethod::kExplicit);  // the step on ranks
  double m_max = 0.0;  // the largest entry of the serial M_FF [kg]
};

// Rank 0: the model, the critical step and the initial state of the serial run, and the
// NodeData of every mesh node.
std::vector<double> SerialSetUp(const Scene& scene, SceneModel* built,
                                DynamicSummary* summary, StartInfo* info) {
  *built = BuildSceneModel(scene);
  const Mesh& mesh = built->body->mesh();
  const int dim = mesh.dim;
  const StepMethod method = internal::ResolveDistributedStep(scene, *built);
  info->method = static_cast<int>(method);
  info->m_max = ::contact::internal::MaxAbsEntry(built->model.M);
  DynamicOptions options = built->options;
  options.progress = false;
  options.on_step = nullptr;
  // (The serial step is never taken here: for the condensed step on ranks the full
  // step, whose set-up is cheapest, stands in, so that rank 0 does not form W.)
  options.step_method =
      method == StepMethod::kExplicit ? StepMethod::kExplicit : StepMethod::kFull;
  const Simulation initial(built->model,
                           options);  // checks dt against dt_crit, u^0, u^{-1}
  *summary = initial.summary();
  info->critical_time_step = summary->critical_time_step;
  info->num_dofs = mesh.NumDofs();
  info->num_free_dofs = built->dofs.NumFreeDofs();
  info->num_contact_nodes = static_cast<int>(built->frames.nodes.size());
  info->num_elements = mesh.NumElements();
  if (initial.state() == SimulationState::kFailed) {
    info->refused = 1;
    return {};
  }
  const Eigen::VectorXd& u0 = initial.displacement();
  const Eigen::VectorXd u_previous = u0 - options.dt * initial.velocity();
  const Eigen::VectorXd f = ::contact::internal::SceneLoadVector(scene, *built);
  const ContactNodeStates start = initial.contact();
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
    const double lambda0 = start.normal_force(static_cast<Eigen::Index>(c));
    d[4 * dim + 11] =
        std::isfinite(lambda0) ? lambda0 : 0.0;  // (prescribed start: unknown = 0)
  }
  return data;
}

// A contact node owned by this rank: its frame with dofs = indices into the owned arrays.
struct OwnedContactNode {
  ContactNode node;   // node.node = the contact node's index in the serial order
  double lambda = 0;  // lambda^k [N]
  ::contact::internal::ExplicitNodeStep step;
};

// The result of every contact node gathered on rank 0 (serial node order): per node its
// index, normal force, gap, tangent force and slip (system units), by one MPI_Gatherv.
class ContactGather {
 public:
  ContactGather(MPI_Comm comm, int dim)
      : comm_(comm), width_(2 * dim + 1), rank_(RankOf(comm)) {
    counts_.resize(static_cast<size_t>(SizeOf(comm)));
    offsets_.resize(counts_.size());
  }

  /// Collective; on rank 0 fills *result (normal_force, gap, tangent_force, slip) for
  /// num_nodes contact nodes.
  void Gather(int dim, int num_nodes, const std::vector<OwnedContactNode>& nodes,
              ContactSystem::Result* result) {
    send_.clear();
    for (const OwnedContactNode& n : nodes) {
      send_.push_back(n.node.node);
      send_.push_back(n.step.normal_force);
      send_.push_back(n.step.gap);
      for (int a = 0; a < dim - 1; ++a) send_.push_back(n.step.tangent_force(a));
      for (int a = 0; a < dim - 1; ++a) send_.push_back(n.step.slip(a));
    }
    const int count = static_cast<int>(send_.size());
    MPI_Gather(&count, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, comm_);
    int total = 0;
    if (rank_ == 0)
      for (size_t r = 0; r < counts_.size(); ++r)
        offsets_[r] = total, total += counts_[r];
    receive_.resize(static_cast<size_t>(total));
    MPI_Gatherv(send_.data(), count, MPI_DOUBLE, receive_.data(), counts_.data(),
                offsets_.data(), MPI_DOUBLE, 0, comm_);
    if (rank_ != 0) return;
    const Eigen::Index N = num_nodes;
    result->normal_force.setZero(N);
    result->gap.setZero(N);
    result->tangent_force.setZero(dim - 1, N);
    result->slip.setZero(dim - 1, N);
    for (size_t k = 0; k + static_cast<size_t>(width_) <= receive_.size();
         k += static_cast<size_t>(width_)) {
      const double* d = &receive_[k];
      const auto c = static_cast<Eigen::Index>(d[0]);
      result->normal_force(c) = d[1];
      result->gap(c) = d[2];
      for (int a = 0; a < dim - 1; ++a)
        result->tangent_force(a, c) = d[3 + a], result->slip(a, c) = d[dim + 2 + a];
    }
  }

 private:
  MPI_Comm comm_;
  int width_, rank_;
  std::vector<int> counts_, offsets_;
  std::vector<double> send_, receive_;
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

// The files of the run: steps.csv and displacement.csv on rank 0; per snapshot one .vtu
// piece per rank (its cells, the displacement of their vertices and the rank as a cell
// field), the .pvtu that joins them and series.pvd listing the .pvtu files (rank 0).
class DistributedOutput {
 public:
  DistributedOutput(MPI_Comm comm, const Scene& scene,
                    std::vector<std::string>* files_written)
      : comm_(comm),
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
        steps_ = ncp::OutputFile::Open((directory_ / "steps.csv").string());
        steps_.stream() << ::contact::internal::kStepsCsvHeader << "\n";
        steps_.stream().precision(10);
        steps_.Commit();
        files_written_->push_back((directory_ / "steps.csv").string());
      }
    }
    MPI_Bcast(&created, 1, MPI_INT, 0, comm_);  // (the pieces go into the directory)
    if (!created)
      throw ncp::OutputError("cannot create directory", directory_.string(), 0);
  }

  bool enabled() const { return !directory_.empty(); }

  void WriteStepRow(const StepRecord& record) {
    if (directory_.empty() || rank_ != 0) return;
    ::contact::internal::WriteStepsCsvRow(record, &steps_.stream());
    steps_.Commit();
  }

  /// Collective: the snapshot of global displacement vector u at `time`.
  void WriteSnapshot(const DistributedBody& body, Vec u, int step, double time) {
    if (directory_.empty()) return;
    const Mesh& mesh = body.local_mesh();
    Vec local = nullptr;
    CONTACT_PETSC_CHECK(DMGetLocalVector(body.dm(), &local));
    CONTACT_PETSC_CHECK(VecZeroEntries(local));
    CONTACT_PETSC_CHECK(DMGlobalToLocalBegin(body.dm(), u, INSERT_VALUES, local));
    CONTACT_PETSC_CHECK(DMGlobalToLocalEnd(body.dm(), u, INSERT_VALUES, local));
    PointField displacement{"displacement",
                            Eigen::MatrixXd::Zero(body.dim(), mesh.NumNodes())};
    const PetscScalar* x = nullptr;
    CONTACT_PETSC_CHECK(VecGetArrayRead(local, &x));
    for (int i = 0; i < mesh.NumNodes(); ++i)
      for (int a = 0; a < body.dim(); ++a)
        if (body.Data(i)[a] >= 0)
          displacement.values(a, i) = x[body.LocalOffset(i, a)];  // (Dirichlet: 0)
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(local, &x));
    CONTACT_PETSC_CHECK(DMRestoreLocalVector(body.dm(), &local));
    CellField rank{"rank", Eigen::MatrixXd::Constant(1, mesh.NumElements(), rank_)};
    char name[64];
    std::vector<std::string> pieces;
    for (int r = 0; r < size_; ++r) {
      std::snprintf(name, sizeof name, "snapshot_%06d_rank_%d.vtu", step, r);
      pieces.push_back(name);
    }
    const std::string piece = (directory_ / pieces[static_cast<size_t>(rank_)]).string();
    WriteVtu(piece, mesh, {displacement}, {rank});
    MPI_Barrier(comm_);  // (every piece is on disk before the .pvtu names it)
    if (rank_ != 0) return;
    std::snprintf(name, sizeof name, "snapshot_%06d.pvtu", step);
    WritePvtu((directory_ / name).string(), {displacement}, {rank}, pieces);
    series_.emplace_back(time, name);
    WritePvd((directory_ / "series.pvd").string(), series_);
    for (const std::string& p : pieces)
      files_written_->push_back((directory_ / p).string());
    files_written_->push_back((directory_ / name).string());
  }

  /// Rank 0: displacement.csv (every node, as from one process) and closes steps.csv.
  void Finish(const Mesh& mesh, const DofMap& dofs, double time,
              const Eigen::VectorXd& u_free) {
    if (directory_.empty() || rank_ != 0) return;
    steps_.Close();
    if (u_free.size() == 0) return;
    const int dim = mesh.dim;
    const std::string path = (directory_ / "displacement.csv").string();
    ncp::OutputFile file = ncp::OutputFile::Open(path);
    file.stream() << (dim == 2 ? "time,node,ux,uy\n" : "time,node,ux,uy,uz\n");
    file.stream().precision(10);
    const Eigen::VectorXd u = dofs.Expand(u_free);
    for (int i = 0; i < mesh.NumNodes(); ++i) {
      file.stream() << time << ',' << i;
      for (int a = 0; a < dim; ++a) file.stream() << ',' << u(dim * i + a);
      file.stream() << '\n';
    }
    file.Close();
    files_written_->push_back(path);
    files_written_->push_back((directory_ / "series.pvd").string());
  }

 private:
  MPI_Comm comm_;
  int rank_, size_;
  std::filesystem::path directory_;
  std::vector<std::string>* files_written_;
  ncp::OutputFile steps_;
  std::vector<std::pair<double, std::string>> series_;
};

// The distributed explicit time loop over the owned free dofs of `body`.
class ExplicitRun {
 public:
  ExplicitRun(MPI_Comm comm, const Scene& scene, const DistributedBody& body,
              int num_contact_nodes)
      : comm_(comm),
        rank_(RankOf(comm)),
        scene_(scene),
        body_(body),
        dim_(body.dim()),
        num_contact_nodes_(num_contact_nodes),
        dt_(scene.dynamics.dt) {
    DM dm = body.dm();
    for (Vec* v : {&u_, &du_, &Ku_, &Mdu_, &f_free_, &q_, &d_})
      CONTACT_PETSC_CHECK(DMCreateGlobalVector(dm, v));
    CONTACT_PETSC_CHECK(VecGetLocalSize(u_, &n_));
    CONTACT_PETSC_CHECK(VecMax(body.lumped_mass(), nullptr, &m_max_));
    force_scale_ = m_max_ / (dt_ * dt_);
    SetInitialState();
  }
  ~ExplicitRun() {
    for (Vec* v : {&u_, &du_, &Ku_, &Mdu_, &f_free_, &q_, &d_}) VecDestroy(v);
  }
  ExplicitRun(const ExplicitRun&) = delete;
  ExplicitRun& operator=(const ExplicitRun&) = delete;

  Vec displacement() const { return u_; }
  int num_contact_nodes_owned() const { return static_cast<int>(nodes_.size()); }

  /// Step k -> k+1 (collective). False if a value is not finite (on any rank).
  bool Step(long k, StepRecord* rec, ContactSystem::Result* contact,
            ContactGather* gather) {
    const auto start = Clock::now();
    rec->step = static_cast<int>(k + 1);
    rec->time = scene_.dynamics.start_time + static_cast<double>(k) * dt_ + dt_;
    const double factor = ::contact::internal::LoadHistoryFactor(
        scene_.load_history, scene_.dynamics.start_time, scene_.ramp_time,
        scene_.dynamics.start_time + static_cast<double>(k) * dt_);
    Arrays a(*this);
    // Q^k, q and the increment off contact (dynamics.cpp LoadStep, explicit_step.cpp).
    for (PetscInt i = 0; i < n_; ++i) {
      const double f = factor * a.f_free[i];
      const double Q = a.Ku[i] - f - a.Mdu[i] / (dt_ * dt_);
      a.q[i] = Q / force_scale_;
      a.du[i] = -a.q[i] / a.d[i];
    }
    const double friction = scene_.friction_coefficient;
    for (OwnedContactNode& n : nodes_) {
      const double bound =
          friction > 0.0 ? (friction / force_scale_) * std::max(n.lambda, 0.0) : 0.0;
      const int first_free = n.node.dofs[0] >= 0   ? n.node.dofs[0]
                             : n.node.dofs[1] >= 0 ? n.node.dofs[1]
                                                   : n.node.dofs[2];
      n.step = ::contact::internal::SolveExplicitContactNode(
          dim_, n.node, a.d[first_free], n.node.gap, bound, a.q, a.u, a.du);
      n.lambda = force_scale_ * n.step.normal_force;
    }
    rec->solve_seconds = Seconds(start);
    // u^{k+1}, M du, the kinetic energy (dynamics.cpp MeasureStep, energy_balance.cpp).
    double kinetic = 0.0, non_finite = 0.0;
    for (PetscInt i = 0; i < n_; ++i) {
      if (!std::isfinite(a.du[i])) non_finite = 1.0;
      a.u[i] = a.u[i] + a.du[i];
      a.Mdu[i] = a.m[i] * a.du[i];
      kinetic += a.du[i] * a.Mdu[i];
    }
    a.Restore();
    // One reduction: the kinetic energy and the number of ranks with a non-finite
    // increment.
    double sums[2] = {kinetic, non_finite};
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_);
    if (sums[1] > 0.0) return false;
    CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_, Ku_));
    PetscScalar uKu = 0.0;
    CONTACT_PETSC_CHECK(VecDot(u_, Ku_, &uKu));
    rec->kinetic = 0.5 * sums[0] / (dt_ * dt_);
    rec->strain = 0.5 * uKu;
    gather->Gather(dim_, num_contact_nodes_, nodes_, contact);
    if (rank_ == 0) Record(*contact, rec);
    rec->seconds = Seconds(start);
    return true;
  }

  double force_scale() const { return force_scale_; }

 private:
  // The owned arrays of the state vectors for one step.
  struct Arrays {
    explicit Arrays(const ExplicitRun& run) : run_(run) {
      CONTACT_PETSC_CHECK(VecGetArray(run.u_, &u));
      CONTACT_PETSC_CHECK(VecGetArray(run.du_, &du));
      CONTACT_PETSC_CHECK(VecGetArray(run.Mdu_, &Mdu));
      CONTACT_PETSC_CHECK(VecGetArray(run.q_, &q));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.Ku_, &Ku));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.f_free_, &f_free));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.d_, &d));
      CONTACT_PETSC_CHECK(VecGetArrayRead(run.body_.lumped_mass(), &m));
    }
    void Restore() {
      if (!u) return;
      VecRestoreArray(run_.u_, &u);
      VecRestoreArray(run_.du_, &du);
      VecRestoreArray(run_.Mdu_, &Mdu);
      VecRestoreArray(run_.q_, &q);
      VecRestoreArrayRead(run_.Ku_, &Ku);
      VecRestoreArrayRead(run_.f_free_, &f_free);
      VecRestoreArrayRead(run_.d_, &d);
      VecRestoreArrayRead(run_.body_.lumped_mass(), &m);
      u = nullptr;
    }
    ~Arrays() { Restore(); }
    const ExplicitRun& run_;
    PetscScalar *u = nullptr, *du = nullptr, *Mdu = nullptr, *q = nullptr;
    const PetscScalar *Ku = nullptr, *f_free = nullptr, *d = nullptr, *m = nullptr;
  };

  // u^0, f_F, M (u^0 - u^{-1}), K u^0, d = m / m_max and the owned contact nodes, from
  // the node data rank 0 sent.
  void SetInitialState() {
    PetscScalar *u = nullptr, *Mdu = nullptr, *f = nullptr, *d = nullptr;
    const PetscScalar* m = nullptr;
    CONTACT_PETSC_CHECK(VecGetArray(u_, &u));
    CONTACT_PETSC_CHECK(VecGetArray(Mdu_, &Mdu));
    CONTACT_PETSC_CHECK(VecGetArray(f_free_, &f));
    CONTACT_PETSC_CHECK(VecGetArray(d_, &d));
    CONTACT_PETSC_CHECK(VecGetArrayRead(body_.lumped_mass(), &m));
    for (int i = 0; i < body_.NumLocalVertices(); ++i) {
      const double* data = body_.Data(i);
      for (int c = 0; c < dim_; ++c) {
        const PetscInt k = body_.OwnedIndex(i, c);
        if (k < 0) continue;
        u[k] = data[dim_ + c];
        const double du = data[dim_ + c] - data[2 * dim_ + c];  // u^0 - u^{-1}
        Mdu[k] = m[k] * du;
        f[k] = data[3 * dim_ + c];
        d[k] = m[k] / m_max_;
      }
      if (!body_.Owns(i) || data[4 * dim_] < 0) continue;
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
    CONTACT_PETSC_CHECK(VecRestoreArray(u_, &u));
    CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_, Ku_));
  }

  // Rank 0: the record's contact sums in the serial node order (dynamics.cpp
  // MeasureStep); the accuracy and energy-balance measures are not computed here.
  void Record(const ContactSystem::Result& contact, StepRecord* rec) const {
    const Eigen::VectorXd lambda = force_scale_ * contact.normal_force;
    rec->normal_force_sum = lambda.sum();
    rec->tangent_force_sum = 0.0;
    for (Eigen::Index c = 0; c < contact.tangent_force.cols(); ++c)
      rec->tangent_force_sum += force_scale_ * contact.tangent_force.col(c).norm();
    rec->max_penetration =
        std::max(0.0, contact.gap.size() ? -contact.gap.minCoeff() : 0.0);
    rec->solver_status = "converged";
    for (double* measure :
         {&rec->external_work, &rec->normal_contact_work, &rec->friction_dissipation,
          &rec->energy_balance_error, &rec->equilibrium_residual,
          &rec->complementarity_residual, &rec->friction_residual, &rec->force_accuracy,
          &rec->displacement_accuracy})
      *measure = kNotMeasured;
    rec->active_nodes = -1;
  }

  MPI_Comm comm_;
  int rank_;
  const Scene& scene_;
  const DistributedBody& body_;
  int dim_;
  int num_contact_nodes_;  // of the whole body
  double dt_;
  PetscInt n_ = 0;          // owned free dofs
  PetscReal m_max_ = 0.0;   // largest lumped mass [kg]
  double force_scale_ = 0;  // m_max / dt^2 [N]
  // u^k [m]; du: the last increment [m]; Ku [N]; Mdu = M du [kg m]; f_F [N]; q (system
  // units); d = m / m_max (the diagonal of S).
  Vec u_ = nullptr, du_ = nullptr, Ku_ = nullptr, Mdu_ = nullptr, f_free_ = nullptr,
      q_ = nullptr, d_ = nullptr;
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

}  // namespace

std::string WhyNotDistributed(const Scene& scene) {
  const std::string supported =
      "on more than one MPI rank contact-sim runs the explicit step (solver.step = "
      "\"explicit\" with mass = \"lumped\"), the condensed step with the contact set "
      "gathered (solver.step = \"condensed\", friction \"coulomb-fc\") and \"auto\" "
      "choosing between them";
  const StepMethod method = scene.dynamics.step_method;
  if (method != StepMethod::kExplicit && method != StepMethod::kCondensed &&
      method != StepMethod::kAuto)
    return scene.source + ": the scene's step is '" + ToString(method) + "'; " +
           supported;
  if (method == StepMethod::kExplicit && scene.mass != MassKind::kLumped)
    return scene.source +
           ": the explicit step needs mass = \"lumped\" (the scene's mass is "
           "consistent); " +
           supported;
  if (method == StepMethod::kCondensed && scene.friction_coefficient > 0.0 &&
      scene.dynamics.friction_formulation == FrictionFormulation::kLaggedBound)
    return scene.source +
           ": the condensed step on MPI ranks poses friction as implicit Coulomb "
           "(solver.friction = \"coulomb-fc\"), not with the lagged bound; " +
           supported;
  if (scene.dynamics.compare_with_ipopt)
    return scene.source + ": compare_with_ipopt is not available on MPI ranks; " +
           supported;
  if (scene.marked_point || !scene.stress_times.empty())
    return scene.source +
           ": the marked node history and the contact stress output "
           "(output.marked_point, "
           "output.stress_times) are not yet written on MPI ranks; remove them or run on "
           "one rank";
  return "";
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
  // A refused scene or mesh on rank 0 is refused on every rank (no rank left waiting).
  std::string error;
  if (rank == 0) {
    try {
      built = std::make_unique<SceneModel>();
      node_data = ::contact::internal::NamingTheScene(
          scene, [&] { return SerialSetUp(scene, built.get(), &summary, &info); });
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
  const bool condensed = method == StepMethod::kCondensed;
  const DistributedBody body(comm, scene, built.get(), node_data, condensed);
  node_data = {};
  std::unique_ptr<CondensedGatheredStep> condensed_run;
  if (condensed)
    condensed_run = std::make_unique<CondensedGatheredStep>(
        comm, scene, body, built ? &built->frames.nodes : nullptr, info.m_max);
  // Rank 0 keeps of the serial set-up only what the output needs (mesh, Dirichlet map).
  Mesh mesh;
  DofMap dofs;
  if (built) {
    mesh = built->body->mesh();
    dofs = built->dofs;
    built.reset();
  }
  if (progress && rank == 0)
    std::fprintf(stderr,
                 "  set-up on rank 0: model, dt_crit and initial state %.3g s; DMPlex "
                 "and distribution "
                 "(%s) %.3g s, section %.3g s, assembly of K and M %.3g s\n",
                 setup_seconds, body.partitioner().c_str(), body.distribute_seconds(),
                 body.section_seconds(), body.assemble_seconds());
  if (progress && rank == 0 && condensed_run)
    std::fprintf(stderr,
                 "  condensed step on ranks: %d contact unknowns gathered on rank 0; "
                 "solves with M by %s; factor %.3g s, W %.3g s\n",
                 condensed_run->num_contact_unknowns(),
                 condensed_run->mass_solver().c_str(), condensed_run->factor_seconds(),
                 condensed_run->delassus_seconds());
  DistributedOutput output(comm, scene, &result.files_written);
  std::unique_ptr<ExplicitRun> explicit_run;
  if (!condensed)
    explicit_run =
        std::make_unique<ExplicitRun>(comm, scene, body, info.num_contact_nodes);
  ContactGather gather(comm, scene.dim);
  const Vec u_run =
      condensed ? condensed_run->displacement() : explicit_run->displacement();
  const DynamicOptions& options = scene.dynamics;
  const long num_steps = static_cast<long>(
      std::ceil((options.end_time - options.start_time) / options.dt - 1e-3));
  output.WriteSnapshot(body, u_run, 0, options.start_time);
  summary.max_penetration = 0.0;
  for (double* measure :
       {&summary.max_equilibrium_residual, &summary.max_complementarity_residual,
        &summary.max_friction_residual, &summary.energy_balance_error})
    *measure = kNotMeasured;
  ContactSystem::Result contact;
  double last_progress = 0.0;
  summary.status = DynamicStatus::kCompleted;
  for (long k = 0; k < num_steps; ++k) {
    StepRecord rec;
    if (condensed ? !condensed_run->Step(k, &rec, &contact)
                  : !explicit_run->Step(k, &rec, &contact, &gather)) {
      summary.status = DynamicStatus::kSolverFailure;
      summary.message =
          "step " + std::to_string(k + 1) + " (t = " + std::to_string(rec.time) +
          " s): " +
          (condensed ? condensed_run->failure()
                     : std::string("non-finite values in the explicit step"));
      break;
    }
    summary.steps = rec.step;
    output.WriteStepRow(rec);
    if ((scene.snapshot_every > 0 && rec.step % scene.snapshot_every == 0) ||
        k + 1 == num_steps)
      output.WriteSnapshot(body, u_run, rec.step, rec.time);
    if (rank == 0) {
      summary.max_penetration = std::max(summary.max_penetration, rec.max_penetration);
      summary.newton_iterations += rec.newton_iterations;
      summary.jacobian_evaluations += rec.jacobian_evaluations;
      summary.residual_evaluations += rec.residual_evaluations;
      summary.records.push_back(rec);
      if (progress && Seconds(start) - last_progress > 1.0) {
        last_progress = Seconds(start);
        std::fprintf(stderr, "  step %d / %ld, t = %.6g s (%s, %d ranks)\n", rec.step,
                     num_steps, rec.time, ToString(method), SizeOf(comm));
      }
    }
  }
  if (summary.status == DynamicStatus::kCompleted)
    summary.message = "completed " + std::to_string(summary.steps) + " steps on " +
                      std::to_string(SizeOf(comm)) + " MPI ranks (" + ToString(method) +
                      " step, partitioner " + body.partitioner() + ")";
  const Eigen::VectorXd u = GatherFreeDofs(body, u_run, info.num_free_dofs);
  if (rank == 0) summary.u = u;
  output.Finish(
      mesh, dofs,
      summary.records.empty() ? options.start_time : summary.records.back().time, u);
  summary.seconds = Seconds(start);
  return result;
}

}  // namespace contact::petsc
