#include "distributed_implicit_step.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "compressed_matrix.hpp"
#include "mass_inverse.hpp"
#include "petsc_check.hpp"
#include "rank_reduction.hpp"
#include "scene/scene_load.hpp"
#include "step/step_method.hpp"
#include "step_accuracy.hpp"

namespace contact::petsc::internal {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// True if PETSc's calls to MUMPS reach the parallel MUMPS. Debian's sequential MUMPS
// (libdmumps_seq, a dependency of Ipopt) defines the same dmumps_c; had it entered the
// global scope first (a program that links libipopt itself; the contact library loads it
// with RTLD_DEEPBIND and adds nothing to the global scope), a factorization over more
// than one rank would see only each rank's rows and fail (INFOG(1) = -10).
bool ParallelMumpsBound() {
  void* entry = dlsym(RTLD_DEFAULT, "dmumps_c");
  Dl_info info;
  if (!entry || dladdr(entry, &info) == 0 || !info.dli_fname) return false;
  return std::strstr(info.dli_fname, "_seq") == nullptr;
}

std::string KspDescription(KSP ksp) {
  KSPType ksp_type = nullptr;
  PC pc = nullptr;
  PCType pc_type = nullptr;
  CONTACT_PETSC_CHECK(KSPGetType(ksp, &ksp_type));
  CONTACT_PETSC_CHECK(KSPGetPC(ksp, &pc));
  CONTACT_PETSC_CHECK(PCGetType(pc, &pc_type));
  std::string out =
      std::string(ksp_type ? ksp_type : "?") + " + " + (pc_type ? pc_type : "?");
  MatSolverType package = nullptr;
  if (PCFactorGetMatSolverType(pc, &package) == 0 && package)
    out += std::string(" (") + package + ")";
  return out;
}

}  // namespace

int CountContactUnknowns(int dim, const std::vector<ContactNode>& nodes) {
  int count = 0;
  for (const ContactNode& node : nodes)
    for (int a = 0; a < dim; ++a)
      if (node.dofs[a] >= 0) ++count;
  return count;
}

ContactSolve SparseContactSolve() {
  char value[64] = "";
  PetscBool set = PETSC_FALSE;
  CONTACT_PETSC_CHECK(PetscOptionsGetString(nullptr, nullptr, "-contact_newton", value,
                                            sizeof value, &set));
  const std::string v = value;
  if (!set || v == "distributed") return ContactSolve::kDistributed;
  if (v == "gathered") return ContactSolve::kGatheredOperator;
  throw std::invalid_argument(
      "contact::petsc: PETSc option -contact_newton is '" + v +
      "'; accepted: distributed (the sparse step's contact unknowns on the ranks that "
      "own their contact nodes, the default) or gathered (on rank 0)");
}

StepMethod ResolveDistributedStep(const Scene& scene, const SceneModel& built) {
  const DynamicOptions& options = built.options;
  const DynamicModel& model = built.model;
  StepMethod method = options.step_method;
  if (method == StepMethod::kAuto) {
    // The serial choice when it is the explicit step (lumped M, no implicit friction).
    if (scene.mass == MassKind::kLumped) {
      const ::contact::internal::MassInverse mass(model.M, "contact::petsc");
      if (::contact::internal::PredictStepCost(model, options, mass).choice ==
          StepMethod::kExplicit)
        return StepMethod::kExplicit;
    }
    // Gathered (W formed on rank 0) up to the limit, matrix-free (sparse) above it.
    const int unknowns = CountContactUnknowns(model.dim, model.contact_nodes);
    method = unknowns > kMaxGatheredContactUnknowns ? StepMethod::kSparse
                                                    : StepMethod::kCondensed;
  }
  if ((method == StepMethod::kCondensed || method == StepMethod::kSparse) &&
      options.friction_coefficient > 0.0 &&
      options.friction_formulation == FrictionFormulation::kLaggedBound)
    throw std::invalid_argument(
        scene.source + ": on MPI ranks the " + ToString(method) +
        " step poses friction as implicit Coulomb (solver.friction = \"coulomb-fc\", "
        "the default), not with the lagged bound (lagged-bound); the explicit step "
        "(mass = \"lumped\") takes the lagged bound");
  return method;
}

CondensedGatheredStep::CondensedGatheredStep(MPI_Comm comm, const Scene& scene,
                                             const DistributedBody& body,
                                             const std::vector<ContactNode>* nodes,
                                             double m_max, ContactSolve solve,
                                             bool complete_start)
    : comm_(comm),
      rank_(0),
      scene_(scene),
      body_(body),
      dim_(body.dim()),
      dt_(scene.dynamics.dt),
      m_max_(m_max),
      force_scale_(m_max / (scene.dynamics.dt * scene.dynamics.dt)),
      tolerance_(scene.dynamics.ncp.tolerance) {
  MPI_Comm_rank(comm, &rank_);
  solve_ = solve;
  if (!body.mass_matrix())
    throw std::logic_error("CondensedGatheredStep: the body has no mass matrix");
  for (Vec* v : Vectors()) CONTACT_PETSC_CHECK(DMCreateGlobalVector(body.dm(), v));
  auto start = Clock::now();
  CreateMassSolver();
  factor_seconds_ = Seconds(start);
  if (distributed()) {  // (its contact set-up waits for SetUpContact too)
    SetInitialState(complete_start);
    return;
  }
  BuildContactScatter(nodes);
  products_ = std::make_unique<DelassusProducts>(
      comm_, [this] { return MultiplyW(); },
      [this](const Eigen::VectorXd& F) {
        PetscScalar* x = nullptr;
        CONTACT_PETSC_CHECK(VecGetArray(contact_, &x));
        for (int i = 0; i < num_unknowns_; ++i) x[i] = F(i);
        CONTACT_PETSC_CHECK(VecRestoreArray(contact_, &x));
      },
      [this](Eigen::VectorXd* x) { ReadContact(x); });
  SetInitialState(complete_start);
}

void CondensedGatheredStep::SetUpContact() {
  const auto start = Clock::now();
  if (distributed())
    SetUpDistributed();
  else if (solve_ == ContactSolve::kGatheredOperator)
    SetUpOperator();
  else
    FormDelassus();
  delassus_seconds_ = Seconds(start);
}

CondensedGatheredStep::~CondensedGatheredStep() {
  for (Vec* v : Vectors()) VecDestroy(v);
  VecDestroy(&contact_);
  VecScatterDestroy(&to_contact_);
  KSPDestroy(&ksp_);
}

// M^-1 by PETSc's KSP on the parallel M: by default MUMPS's Cholesky factor (preonly),
// computed once and reused by every solve of the run; on more than one rank when the
// sequential MUMPS is bound in MUMPS's place (ParallelMumpsBound false: a program that
// links libipopt or libdmumps_seq before PETSc), CG with Jacobi's preconditioner (M's
// condition number after diagonal scaling is bounded independently of the mesh size: a
// few tens of iterations; exact for a lumped M). The options database under "mass_"
// overrides either (-mass_ksp_type cg -mass_pc_type gamg, -mass_pc_type redundant, ...).
void CondensedGatheredStep::CreateMassSolver() {
  int ranks = 1;
  MPI_Comm_size(comm_, &ranks);
  const bool mumps = ranks == 1 || ParallelMumpsBound();
  CONTACT_PETSC_CHECK(KSPCreate(comm_, &ksp_));
  CONTACT_PETSC_CHECK(KSPSetOptionsPrefix(ksp_, "mass_"));
  // The factor and the solves on M without its zero entries (compressed_matrix.hpp): a
  // third of the 3D factor's entries and of a solve's work.
  Mat mass = CopyWithoutZeros(body_.mass_matrix());
  CONTACT_PETSC_CHECK(KSPSetOperators(ksp_, mass, mass));
  CONTACT_PETSC_CHECK(MatDestroy(&mass));  // (the KSP holds its reference)
  CONTACT_PETSC_CHECK(KSPSetType(ksp_, mumps ? KSPPREONLY : KSPCG));
  PC pc = nullptr;
  CONTACT_PETSC_CHECK(KSPGetPC(ksp_, &pc));
  CONTACT_PETSC_CHECK(PCSetType(pc, mumps ? PCCHOLESKY : PCJACOBI));
  if (mumps) CONTACT_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  // An iterative solve to 1e-12 of |b| (the trajectory is compared with one process's to
  // 1e-9), or tighter per step (SolveS), in the true residual's norm (the step's
  // equilibrium residual is force_scale times it).
  CONTACT_PETSC_CHECK(KSPSetTolerances(ksp_, 1e-12, 0.0, PETSC_DEFAULT, 10000));
  if (!mumps) CONTACT_PETSC_CHECK(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED));
  CONTACT_PETSC_CHECK(KSPSetFromOptions(ksp_));
  mass_solver_ = KspDescription(ksp_);
  // preonly applies the preconditioner once: M^-1 only if it is a factorization (or the
  // inverse of a diagonal M), never an approximation taken for the solve.
  PetscBool preonly = PETSC_FALSE, exact = PETSC_FALSE;
  CONTACT_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp_), KSPPREONLY, &preonly));
  CONTACT_PETSC_CHECK(KSPGetPC(ksp_, &pc));
  CONTACT_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &exact,
                                                PCCHOLESKY, PCLU, PCREDUNDANT, ""));
  if (!exact && scene_.mass == MassKind::kLumped)
    CONTACT_PETSC_CHECK(
        PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCJACOBI, &exact));
  if (preonly && !exact)
    throw std::invalid_argument(
        "contact::petsc: the solves with the mass matrix are set to " + mass_solver_ +
        ", one application of a preconditioner that is not M^-1; with -mass_ksp_type "
        "preonly use -mass_pc_type cholesky, lu or redundant (jacobi for a lumped "
        "mass), or a Krylov method (-mass_ksp_type cg)");
  CONTACT_PETSC_CHECK(KSPSetUp(ksp_));
  CONTACT_PETSC_CHECK(KSPGetTolerances(ksp_, &rtol_, nullptr, nullptr, &max_its_));
}

// An iterative solve M z = b stops at |M z - b|_2 <= max(kRoundoffRtol |b|, min(rtol
// |b|, kStepSolveFraction tol F / force_scale)) (rtol: 1e-12 or -mass_ksp_rtol): the
// equilibrium residual it leaves, force_scale |M z - b| [N], is then a thousandth of the
// step's force accuracy tol F, and the displacement error |S^-1 (M z - b)| <= m_max /
// m_min |M z - b| stays below tol F dt^2 / m_max <= tol D (S's smallest eigenvalue is
// about m_min / m_max, F dt^2 / m_max <= D by the scales' definition), never looser than
// rtol |b| and never below the round-off of b.
constexpr double kStepSolveFraction = 1e-3;
constexpr double kRoundoffRtol = 1e-14;

bool CondensedGatheredStep::SolveS(Vec b, Vec x, double step_force) {
  if (!SolveM(b, x, step_force)) return false;
  CONTACT_PETSC_CHECK(VecScale(x, m_max_));  // S^-1 = m_max M^-1
  return true;
}

bool CondensedGatheredStep::SolveMass(Vec b, Vec x) { return SolveM(b, x, 0.0); }

bool CondensedGatheredStep::SolveM(Vec b, Vec x, double step_force) {
  PetscBool preonly = PETSC_FALSE;
  CONTACT_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp_), KSPPREONLY, &preonly));
  if (!preonly) {
    PetscReal b_norm = 0.0;
    CONTACT_PETSC_CHECK(VecNorm(b, NORM_2, &b_norm));
    double absolute = rtol_ * b_norm;
    if (step_force > 0.0)
      absolute = std::max(kRoundoffRtol * b_norm,
                          std::min(absolute, kStepSolveFraction * tolerance_ *
                                                 step_force / force_scale_));
    CONTACT_PETSC_CHECK(KSPSetTolerances(ksp_, 0.0, absolute, PETSC_DEFAULT, max_its_));
  }
  CONTACT_PETSC_CHECK(KSPSolve(ksp_, b, x));
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  CONTACT_PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
  if (reason < 0) {
    failure_ = "the solve with the mass matrix (" + mass_solver_ +
               ") did not converge: " + KSPConvergedReasons[reason];
    return false;
  }
  return true;
}

// u^0, u^{-1}, du = u^0 - u^{-1}, f_F and the contact dofs from the node data rank 0
// sent (with complete_start, u^{-1} += dt^2 / 2 M^-1 (f(t_0) - K u^0)); M du and K u^0.
void CondensedGatheredStep::SetInitialState(bool complete_start) {
  PetscScalar *u = nullptr, *u_previous = nullptr, *f = nullptr;
  CONTACT_PETSC_CHECK(VecGetArray(u_, &u));
  CONTACT_PETSC_CHECK(VecGetArray(u_previous_, &u_previous));
  CONTACT_PETSC_CHECK(VecGetArray(f_free_, &f));
  PetscInt n = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(u_, &n));
  contact_dof_.assign(static_cast<size_t>(n), 0);
  body_.UnpackStart(u, u_previous, f, &contact_dof_);
  CONTACT_PETSC_CHECK(VecRestoreArray(f_free_, &f));
  CONTACT_PETSC_CHECK(VecRestoreArray(u_previous_, &u_previous));
  CONTACT_PETSC_CHECK(VecRestoreArray(u_, &u));
  CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_, Ku_));
  if (complete_start) {
    // M a^0 = f(t_0) - K u^0 (rhs_ and y_ as buffers), u^{-1} += dt^2 / 2 a^0.
    const double t0 = scene_.dynamics.start_time;
    CONTACT_PETSC_CHECK(VecAXPBYPCZ(rhs_,
                                    ::contact::internal::LoadHistoryFactor(
                                        scene_.load_history, t0, scene_.ramp_time, t0),
                                    -1.0, 0.0, f_free_, Ku_));
    const bool solved = SolveMass(rhs_, y_);
    ThrowFromRankZero(comm_, solved ? std::string()
                                    : "contact::petsc: the prescribed "
                                      "start's acceleration: " +
                                          failure_);
    CONTACT_PETSC_CHECK(VecAXPY(u_previous_, 0.5 * dt_ * dt_, y_));
  }
  CONTACT_PETSC_CHECK(VecWAXPY(du_, -1.0, u_previous_, u_));
  CONTACT_PETSC_CHECK(MatMult(body_.mass_matrix(), du_, Mdu_previous_));
}

::contact::internal::EnergyBalance CondensedGatheredStep::StartEnergy() const {
  double local[3] = {0.0, 0.0, 0.0};  // du' M du, (u^{-1})' K u^0, (u^0)' K u^0
  PetscInt n = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(u_, &n));
  const PetscScalar *u = nullptr, *u_previous = nullptr, *du = nullptr, *Ku = nullptr,
                    *Mdu = nullptr;
  const std::pair<Vec, const PetscScalar**> read[] = {{u_, &u},
                                                      {u_previous_, &u_previous},
                                                      {du_, &du},
                                                      {Ku_, &Ku},
                                                      {Mdu_previous_, &Mdu}};
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecGetArrayRead(v, a));
  for (PetscInt i = 0; i < n; ++i) {
    local[0] += du[i] * Mdu[i];
    local[1] += u_previous[i] * Ku[i];
    local[2] += u[i] * Ku[i];
  }
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecRestoreArrayRead(v, a));
  int size = 1;
  MPI_Comm_size(comm_, &size);
  std::vector<double> parts(3 * static_cast<size_t>(size));
  MPI_Allgather(local, 3, MPI_DOUBLE, parts.data(), 3, MPI_DOUBLE, comm_);
  double sum[3] = {0.0, 0.0, 0.0};  // in rank order: the same bits on every rank
  for (int r = 0; r < size; ++r)
    for (int j = 0; j < 3; ++j) sum[j] += parts[3 * static_cast<size_t>(r) + j];
  ::contact::internal::EnergyBalance energy;  // (EnergyBalance's constructor's terms)
  energy.kinetic0 = 0.5 * sum[0] / (dt_ * dt_);
  energy.energy0 = energy.kinetic0 + 0.5 * sum[1];
  energy.strain0 = 0.5 * sum[2];
  return energy;
}

bool CondensedGatheredStep::Step(long k, bool stop_requested,
                                 const StepRecorder* recorder, RankStepPart* part,
                                 std::vector<NodeResult>* results, StepRecord* rec) {
  *part = RankStepPart();
  part->sum[RankStepPart::kStopRequested] = stop_requested ? 1.0 : 0.0;
  results->clear();
  const double factor = ::contact::internal::LoadHistoryFactor(
      scene_.load_history, scene_.dynamics.start_time, scene_.ramp_time,
      scene_.dynamics.start_time + static_cast<double>(k) * dt_);
  LoadStep(factor, part);
  // The maxima of the step's scales and of the penetration of u^k_c (rank 0's, from the
  // gathered u^k_c; kDistributed: each rank's, from its nodes) onto rank 0, which sets
  // the scales of the step (every rank solves with M to them); y = S^-1 q and -H y onto
  // rank 0 (kDistributed: read on each rank).
  if (distributed()) {
    ReadOwned(u_, &u_contact_);
    part->max[RankStepPart::kPenetration] = SetGaps();
  }
  double maxima[4] = {part->max[RankStepPart::kF], part->max[RankStepPart::kKu],
                      part->max[RankStepPart::kDu],
                      part->max[RankStepPart::kPenetration]};
  MPI_Reduce(rank_ == 0 ? MPI_IN_PLACE : maxima, maxima, 4, MPI_DOUBLE, MPI_MAX, 0,
             comm_);
  if (!distributed()) GatherContact(u_, &u_contact_);
  double scales[2] = {0.0, 0.0};  // F [N], D [m]
  if (rank_ == 0) {
    const double penetration = distributed() ? maxima[3] : SetGaps();
    part->max[RankStepPart::kPenetration] = penetration;
    const ::contact::internal::StepScales s =
        recorder->Scales(maxima[0], maxima[1], maxima[2], penetration);
    scales[0] = s.force, scales[1] = s.displacement;
  }
  MPI_Bcast(scales, 2, MPI_DOUBLE, 0, comm_);
  if (!SolveS(q_, y_, scales[0])) return false;
  int solved = 0;
  if (distributed()) {
    // Every rank its part of the contact problem; the outcome is the same on every rank.
    ReadOwned(y_, &x_free_);
    product_failure_.clear();
    solved = SolveContact(scales[0], scales[1], rec) ? 1 : 0;
    if (!product_failure_.empty()) solved = 0, failure_ = product_failure_;
  } else {
    // Rank 0: F into force_ (with the sparse step, the other ranks serve its products
    // with W); every rank learns whether it was found.
    GatherContact(y_, &x_free_);
    if (!products_->Run(
            [&] { solved = SolveContact(scales[0], scales[1], rec) ? 1 : 0; })) {
      solved = 0;
      if (rank_ == 0) failure_ = products_->failure();
    }
  }
  MPI_Bcast(&solved, 1, MPI_INT, 0, comm_);
  if (!solved) {
    BroadcastText(comm_, &failure_);
    return false;
  }
  // du = S^-1 (H' F - q).
  if (distributed()) {
    WriteOwned(force_, rhs_);
  } else {
    if (rank_ == 0) {
      PetscScalar* F = nullptr;
      CONTACT_PETSC_CHECK(VecGetArray(contact_, &F));
      for (int i = 0; i < num_unknowns_; ++i) F[i] = force_(i);
      CONTACT_PETSC_CHECK(VecRestoreArray(contact_, &F));
    }
    ScatterContact(rhs_);
  }
  CONTACT_PETSC_CHECK(VecAXPY(rhs_, -1.0, q_));
  if (!SolveS(rhs_, du_, scales[0])) return false;
  Advance(factor, part);
  Results(results);
  // u^{k-1} <- u^k <- u^{k+1} (the handles); M du and K u^{k+1} go along.
  std::swap(u_previous_, u_);
  std::swap(u_, u_next_);
  std::swap(Mdu_previous_, Mdu_);
  return true;
}

// Q^k = K u^k - f^k - M (u^k - u^{k-1}) / dt^2, q = Q^k / force_scale (dynamics.cpp
// LoadStep), and this rank's maxima |f^k|, |K u^k|, |u^k - u^{k-1}|, |Q^k|.
void CondensedGatheredStep::LoadStep(double factor, RankStepPart* part) {
  PetscInt n = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(q_, &n));
  PetscScalar *q = nullptr, *Q = nullptr;
  const PetscScalar *Ku = nullptr, *f_free = nullptr, *Mdu = nullptr, *du = nullptr;
  const std::pair<Vec, PetscScalar**> write[] = {{q_, &q}, {Q_, &Q}};
  const std::pair<Vec, const PetscScalar**> read[] = {
      {Ku_, &Ku}, {f_free_, &f_free}, {Mdu_previous_, &Mdu}, {du_, &du}};
  for (const auto& [v, a] : write) CONTACT_PETSC_CHECK(VecGetArray(v, a));
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecGetArrayRead(v, a));
  double* max = part->max;
  for (PetscInt i = 0; i < n; ++i) {
    const double f = factor * f_free[i];
    Q[i] = Ku[i] - f - Mdu[i] / (dt_ * dt_);
    q[i] = Q[i] / force_scale_;
    max[RankStepPart::kF] = std::max(max[RankStepPart::kF], std::abs(f));
    max[RankStepPart::kKu] = std::max(max[RankStepPart::kKu], std::abs(Ku[i]));
    max[RankStepPart::kDu] = std::max(max[RankStepPart::kDu], std::abs(du[i]));
    max[RankStepPart::kQ] = std::max(max[RankStepPart::kQ], std::abs(Q[i]));
  }
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecRestoreArrayRead(v, a));
  for (const auto& [v, a] : write) CONTACT_PETSC_CHECK(VecRestoreArray(v, a));
}

// u^{k+1} = u^k + du, M du (the scene's M: consistent or lumped), K u^{k+1}, r = M du /
// dt^2 + Q^k (the contact forces at the contact nodes, else the equilibrium residual),
// the energy sums and the maxima (dynamics.cpp MeasureStep, energy_balance.cpp).
void CondensedGatheredStep::Advance(double factor, RankStepPart* part) {
  CONTACT_PETSC_CHECK(VecWAXPY(u_next_, 1.0, du_, u_));
  CONTACT_PETSC_CHECK(MatMult(body_.mass_matrix(), du_, Mdu_));
  CONTACT_PETSC_CHECK(MatMult(body_.stiffness(), u_next_, Ku_));
  PetscInt n = 0;
  CONTACT_PETSC_CHECK(VecGetLocalSize(u_, &n));
  PetscScalar* r = nullptr;
  const PetscScalar *u = nullptr, *u_previous = nullptr, *u_next = nullptr, *du = nullptr,
                    *Mdu = nullptr, *Ku = nullptr, *Q = nullptr, *f_free = nullptr;
  CONTACT_PETSC_CHECK(VecGetArray(r_, &r));
  const std::pair<Vec, const PetscScalar**> read[] = {
      {u_, &u},           {u_previous_, &u_previous},
      {u_next_, &u_next}, {du_, &du},
      {Mdu_, &Mdu},       {Ku_, &Ku},
      {Q_, &Q},           {f_free_, &f_free}};
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecGetArrayRead(v, a));
  double* sum = part->sum;
  double* max = part->max;
  for (PetscInt i = 0; i < n; ++i) {
    if (!std::isfinite(du[i])) sum[RankStepPart::kNonFinite] = 1.0;
    const double f = factor * f_free[i];
    r[i] = Mdu[i] / (dt_ * dt_) + Q[i];
    sum[RankStepPart::kDuMdu] += du[i] * Mdu[i];
    sum[RankStepPart::kFUNext] += f * u_next[i];
    sum[RankStepPart::kFUPrevious] += f * u_previous[i];
    sum[RankStepPart::kUKuNext] += u[i] * Ku[i];
    sum[RankStepPart::kUNextKuNext] += u_next[i] * Ku[i];
    max[RankStepPart::kMdu] = std::max(max[RankStepPart::kMdu], std::abs(Mdu[i]));
    max[RankStepPart::kUNext] = std::max(max[RankStepPart::kUNext], std::abs(u_next[i]));
    if (!contact_dof_[static_cast<size_t>(i)])
      max[RankStepPart::kRFree] = std::max(max[RankStepPart::kRFree], std::abs(r[i]));
  }
  for (const auto& [v, a] : read) CONTACT_PETSC_CHECK(VecRestoreArrayRead(v, a));
  CONTACT_PETSC_CHECK(VecRestoreArray(r_, &r));
}

void CondensedGatheredStep::Results(std::vector<NodeResult>* results) {
  if (distributed()) {
    ReadOwned(r_, &r_contact_);
    ReadOwned(u_next_, &u_next_contact_);
    ReadOwned(u_previous_, &u_previous_contact_);
  } else {
    GatherContact(r_, &r_contact_);
    GatherContact(u_next_, &u_next_contact_);
    GatherContact(u_previous_, &u_previous_contact_);
    if (rank_ != 0) return;
  }
  results->resize(nodes_.size());
  for (size_t j = 0; j < nodes_.size(); ++j) {
    const ContactNode& node = nodes_[j];
    const auto c = static_cast<Eigen::Index>(j);
    NodeResult& out = (*results)[j];
    out.index = distributed() ? node_index_[j] : static_cast<int>(j);
    out.normal_force = contact_result_.normal_force(c);
    out.gap = contact_result_.gap(c);
    for (int a = 0; a < dim_ - 1; ++a) {
      out.tangent_force(a) = contact_result_.tangent_force(a, c);
      out.slip(a) = contact_result_.slip(a, c);
    }
    for (int a = 0; a < dim_; ++a) {
      const int i = node.dofs[a];  // (numbered on the contact unknowns)
      out.r(a) = i >= 0 ? r_contact_(i) : 0.0;
      out.u_next(a) = i >= 0 ? u_next_contact_(i) : 0.0;
      out.u_previous(a) = i >= 0 ? u_previous_contact_(i) : 0.0;
    }
  }
}

}  // namespace contact::petsc::internal
