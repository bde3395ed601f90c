// ncp::petsc::Solver's construction, accessors and the checks around a solve (the
// iteration itself: iteration.cpp).

#include "ncp/petsc/solver.hpp"

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "format_number.hpp"
#include "input_checks.hpp"
#include "log_events.hpp"
#include "solver_impl.hpp"

namespace ncp::petsc {

// ---------------------------------------------------------------------------------------
// The public API.

BoxMcp BoxMcp::FromFunctionPointers(ResidualFunctionPointer residual,
                                    JacobianFunctionPointer jacobian, void* context,
                                    Mat jacobian_matrix, Vec lower, Vec upper) {
  BoxMcp p;
  if (residual)
    p.residual = [residual, context](Vec x, Vec f) { return residual(x, f, context); };
  if (jacobian)
    p.jacobian = [jacobian, context](Vec x, Mat J) { return jacobian(x, J, context); };
  p.jacobian_matrix = jacobian_matrix;
  p.lower = lower;
  p.upper = upper;
  return p;
}

namespace {

// A KSP with the options prefix `prefix` and the default of both linear systems: one
// direct solve by MUMPS' LU (Amestoy et al. 2001), exact up to round-off like the serial
// backends, so that the iterates are the serial solver's.
KSP DirectKsp(MPI_Comm comm, const std::string& prefix) {
  KSP ksp = nullptr;
  NCP_PETSC_CHECK(KSPCreate(comm, &ksp));
  NCP_PETSC_CHECK(KSPSetOptionsPrefix(ksp, prefix.c_str()));
  NCP_PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  NCP_PETSC_CHECK(PCSetType(pc, PCLU));
  NCP_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  return ksp;
}

}  // namespace

Solver::Solver(MPI_Comm comm, const Options& options, const std::string& options_prefix)
    : impl_(new Impl) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    throw std::invalid_argument(
        "ncp::petsc::Solver: PETSc is not initialized; call PetscInitialize "
        "before constructing the solver (and PetscFinalize after destroying it)");
  std::string error;
  if (!options.IsValid(&error))
    throw std::invalid_argument("ncp::petsc::Solver: " + error);
  if (options.linear_solver != LinearSolverType::kAuto)
    throw std::invalid_argument(
        std::string("ncp::petsc::Solver: Options::linear_solver = ") +
        ToString(options.linear_solver) +
        " names a serial backend; over PETSc the Newton systems are solved by "
        "the KSP (leave kAuto, choose with -" +
        options_prefix + "ksp_type / -" + options_prefix + "pc_type)");
  impl_->comm = comm;
  impl_->options = options;
  impl_->prefix = options_prefix;
  impl_->ksp = DirectKsp(comm, options_prefix);
  impl_->lm_ksp = DirectKsp(comm, options_prefix + "lm_");
  impl_->minimum_norm = std::make_unique<MinimumNormSolver>(options_prefix + "mn_");
  int size = 0;
  MPI_Comm_size(comm, &size);
  impl_->report.ranks = size;
}

Solver::~Solver() = default;

void Solver::SetMultigridGrid(DM grid) { impl_->multigrid.SetGrid(grid); }

const Options& Solver::options() const { return impl_->options; }
KSP Solver::ksp() const { return impl_->ksp; }
const KspReport& Solver::ksp_report() const { return impl_->report; }

namespace {

// Misuse of Solve's arguments (null pointers, unset callbacks, other communicator or
// layout, a non-AIJ matrix): thrown on every rank with the same message.
void CheckSolveArguments(const Solver::Impl& impl, const BoxMcp& problem, Vec x,
                         const Summary* summary) {
  if (x == nullptr || summary == nullptr) Misuse("x and summary must not be null");
  if (!problem.residual || !problem.jacobian)
    Misuse("BoxMcp::residual and BoxMcp::jacobian must be set");
  if (problem.jacobian_matrix == nullptr) Misuse("BoxMcp::jacobian_matrix must be set");
  int compare = MPI_UNEQUAL;
  MPI_Comm_compare(PetscObjectComm(reinterpret_cast<PetscObject>(x)), impl.comm,
                   &compare);
  if (compare != MPI_IDENT && compare != MPI_CONGRUENT)
    Misuse("the start point lives on another communicator than the solver");
  if (problem.lower) CheckLayout(impl.comm, x, problem.lower, "lower");
  if (problem.upper) CheckLayout(impl.comm, x, problem.upper, "upper");
  CheckMatrixLayout(impl.comm, x, problem.jacobian_matrix);
  bool parallel = false;
  if (AnyRank(impl.comm, !IsAij(problem.jacobian_matrix, &parallel)))
    Misuse("the Jacobian matrix must be of type AIJ (MATSEQAIJ or MATMPIAIJ)");
}

// The rows of the mixed form from the local bounds, normalized (|b| >= infinite_bound is
// no bound), checked against each other and the start point.
MixedLayout MakeLayout(const Solver::Impl& impl, const BoxMcp& problem, Vec x) {
  PetscInt local = 0, first = 0, last = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(x, &local));
  NCP_PETSC_CHECK(VecGetOwnershipRange(x, &first, &last));
  constexpr double kInf = std::numeric_limits<double>::infinity();
  LocalArray<double> lower(static_cast<size_t>(local), -kInf),
      upper(static_cast<size_t>(local), kInf);
  for (auto [bound, out] : {std::pair<Vec, LocalArray<double>*>{problem.lower, &lower},
                            std::pair<Vec, LocalArray<double>*>{problem.upper, &upper}}) {
    if (!bound) continue;
    LocalRead a(bound);
    for (PetscInt i = 0; i < local; ++i)
      (*out)[static_cast<size_t>(i)] = NormalizeBound(a[i], impl.options.infinite_bound);
  }
  CheckBoundsAndStart(impl.comm, first, lower, upper, x);
  return MixedLayout(impl.comm, std::move(lower), std::move(upper));
}

// The KSP configured; its multigrid grid and the symmetrized system checked against x.
void ConfigureKsp(Solver::Impl& impl, const MixedLayout& layout, Vec x) {
  impl.Configure();
  if (impl.multigrid.grid())
    CheckMultigridGrid(impl.comm, impl.ksp, impl.prefix, impl.symmetric_newton,
                       impl.multigrid, x);
  if (impl.symmetric_newton && layout.total_slacks > 0)
    Misuse(
        "two-sided bounds (l < u, both finite) at " +
        std::to_string(layout.total_slacks) +
        " components make the Newton matrix of the slack form unsymmetric, and the "
        "KSP asks for the symmetrized Newton system (a CG-like KSP, Cholesky/ICC or -" +
        impl.prefix +
        "symmetric_newton true): use a KSP for unsymmetric systems (the default LU, "
        "GMRES) and -" +
        impl.prefix + "symmetric_newton false");
}

// The returned x lies in [l, u] whatever the status (FB iterates may leave the box), as
// ncp::Solver's; the message says how many components were moved and by how much.
void ProjectFinalIterate(MPI_Comm comm, const MixedLayout& layout, Vec x,
                         Summary* summary) {
  double largest = 0.0;
  const long long outside =
      SumRanks(comm, ProjectOntoBox(layout.lower, layout.upper, x, &largest));
  double largest_all = 0.0;
  MPI_Allreduce(&largest, &largest_all, 1, MPI_DOUBLE, MPI_MAX, comm);
  summary->projected_final_components = static_cast<int>(outside);
  if (outside > 0)
    summary->message += " (" + std::to_string(outside) +
                        " components of the last iterate were outside [l, u], by up to " +
                        FormatNumber("%.3e", largest_all) +
                        ", and were projected onto it)";
}

}  // namespace

void Solver::Solve(const BoxMcp& problem, Vec x, Summary* summary) {
  LogScope scope(SolverLogEvents().solve);
  Impl& impl = *impl_;
  CheckSolveArguments(impl, problem, x, summary);
  const MixedLayout layout = MakeLayout(impl, problem, x);
  ConfigureKsp(impl, layout, x);

  // Options::project_start_point: x0 <- mid(l, u, x0).
  const long long moved =
      impl.options.project_start_point
          ? SumRanks(impl.comm, ProjectOntoBox(layout.lower, layout.upper, x))
          : 0;

  RunIteration(impl, problem, x, summary, layout);

  summary->projected_start_components = static_cast<int>(moved);
  if (moved > 0)
    summary->message +=
        " (" + std::to_string(moved) +
        " components of the start point were outside [l, u] and were projected onto it)";
  ProjectFinalIterate(impl.comm, layout, x, summary);
}

}  // namespace ncp::petsc
