// Shared pieces of the runs: linear-solver option strings, grid levels, clocks, and the
// SNESVI runs (PETSc's own solvers, configured only through its options database).
#include "obstacle_runs.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <sstream>

#include "bueler_obstacle.hpp"

namespace ncp_petsc_bench {

bool HasSymmetricNewtonMatrix(SolverKind kind) {
  return kind == SolverKind::kSnesViRsls || kind == SolverKind::kNcpMin;
}

std::string KspDescription(LinearFamily linear, SolverKind kind) {
  const std::string krylov = HasSymmetricNewtonMatrix(kind) ? "cg" : "gmres";
  switch (linear) {
    case LinearFamily::kMumpsLu:
      return "preonly+lu";
    case LinearFamily::kMultigrid:
      return krylov + "+mg";
    case LinearFamily::kHypre:
      return krylov + "+hypre";
    case LinearFamily::kGamg:
      return krylov + "+gamg";
  }
  return "?";
}

std::string LinearOptions(LinearFamily linear, SolverKind kind, const std::string& prefix,
                          const RunSettings& settings, int multigrid_levels) {
  std::ostringstream o;
  const std::string p = "-" + prefix;
  const char* krylov = HasSymmetricNewtonMatrix(kind) ? "cg" : "gmres";
  o.precision(3);
  switch (linear) {
    case LinearFamily::kMumpsLu:
      o << p << "ksp_type preonly " << p << "pc_type lu " << p
        << "pc_factor_mat_solver_type mumps";
      return o.str();
    case LinearFamily::kMultigrid:
      // Smoother: one SOR sweep pair (symmetric SOR, one Richardson step) before and one
      // after the coarse correction (no eigenvalue estimate to redo for each Newton
      // matrix, as PETSc's default Chebyshev smoother needs; PCMG's default of two steps
      // cost more than the CG iterations it saved, benchmarks/results/petsc/README.md).
      o << p << "ksp_type " << krylov << " " << p << "pc_type mg " << p
        << "mg_levels_ksp_type richardson " << p << "mg_levels_ksp_max_it 1 " << p
        << "mg_levels_pc_type sor ";
      if (multigrid_levels > 0) o << p << "pc_mg_levels " << multigrid_levels << " ";
      break;
    case LinearFamily::kHypre:
      o << p << "ksp_type " << krylov << " " << p << "pc_type hypre " << p
        << "pc_hypre_type boomeramg ";
      break;
    case LinearFamily::kGamg:
      o << p << "ksp_type " << krylov << " " << p << "pc_type gamg ";
      break;
  }
  o << p << "ksp_rtol " << settings.ksp_rtol;
  return o.str();
}

int GridLevels(PetscInt coarse_grid, PetscInt grid) {
  if (coarse_grid < 3 || grid < coarse_grid) return 0;
  int levels = 1;
  PetscInt m = coarse_grid;
  while (m < grid) {
    m = 2 * (m - 1) + 1;
    ++levels;
  }
  return m == grid ? levels : 0;
}

PetscErrorCode CheckedGridLevels(const RunConfig& config, const RunSettings& settings,
                                 int* levels) {
  PetscFunctionBeginUser;
  *levels = GridLevels(settings.coarse_grid, settings.grid);
  PetscCheck(!config.grid_sequencing || *levels > 0, PETSC_COMM_WORLD,
             PETSC_ERR_ARG_OUTOFRANGE,
             "--grid %" PetscInt_FMT " is not (coarse %" PetscInt_FMT " - 1) 2^k + 1",
             settings.grid, settings.coarse_grid);
  PetscFunctionReturn(0);
}

std::string OptionsPrefix(const RunConfig& config) {
  std::string prefix = config.name + "_";
  std::replace(prefix.begin(), prefix.end(), '-', '_');
  return prefix;
}

double WallSeconds() { return MPI_Wtime(); }

double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

PetscErrorCode FinishMeasurements(MPI_Comm comm, double wall_start, double cpu_start,
                                  RunResult* result) {
  PetscFunctionBeginUser;
  const double wall = WallSeconds() - wall_start, cpu = ProcessCpuSeconds() - cpu_start;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double rss_mib = usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
  PetscCallMPI(MPI_Allreduce(&wall, &result->seconds, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&cpu, &result->cpu_seconds, 1, MPI_DOUBLE, MPI_SUM, comm));
  PetscCallMPI(
      MPI_Allreduce(&rss_mib, &result->peak_rss_mib, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  result->ranks = size;
  PetscFunctionReturn(0);
}

namespace {

double CellAreaOfGrid(PetscInt grid) {
  const double h = (kDomainMax - kDomainMin) / double(grid - 1);
  return h * h;
}

const char* SnesTypeOf(SolverKind kind) {
  return kind == SolverKind::kSnesViSsls ? SNESVINEWTONSSLS : SNESVINEWTONRSLS;
}

/// Maps a SNESConvergedReason onto the shared status vocabulary.
std::string StatusOf(SNESConvergedReason reason) {
  if (reason > 0) return "converged";
  switch (reason) {
    case SNES_DIVERGED_MAX_IT:
      return "max_iterations";
    case SNES_DIVERGED_LINE_SEARCH:
      return "line_search_failure";
    case SNES_DIVERGED_FNORM_NAN:
      return "numerical_error";
    case SNES_DIVERGED_LOCAL_MIN:
      return "stationary_point";
    default:
      return "failure";
  }
}

/// Counts Newton steps over every grid of a -snes_grid_sequence solve.
PetscErrorCode CountSteps(SNES, PetscInt iteration, PetscReal, void* counter) {
  if (iteration > 0) ++*static_cast<int*>(counter);
  return 0;
}

}  // namespace

PetscErrorCode RunSnesVi(const RunConfig& config, const RunSettings& settings,
                         RunResult* result) {
  PetscFunctionBeginUser;
  const MPI_Comm comm = PETSC_COMM_WORLD;
  int levels = 0;
  PetscCall(CheckedGridLevels(config, settings, &levels));
  const std::string prefix = OptionsPrefix(config);
  const PetscInt start_grid =
      config.grid_sequencing ? settings.coarse_grid : settings.grid;
  // PCMG of a grid made directly at its size takes its levels from -pc_mg_levels; under
  // -snes_grid_sequence PETSc counts the refinements of the DM itself.
  const int mg_levels = config.grid_sequencing ? 0 : (levels > 0 ? levels : 1);
  std::ostringstream options;
  options.precision(17);
  options << LinearOptions(config.linear, config.kind, prefix, settings, mg_levels)
          << " -" << prefix << "snes_type " << SnesTypeOf(config.kind) << " -" << prefix
          << "snes_max_it " << settings.max_newton_iterations << " -" << prefix
          << "snes_max_funcs 1000000 -" << prefix << "snes_rtol 0 -" << prefix
          << "snes_stol 0 -" << prefix << "snes_atol "
          << settings.tolerance * CellAreaOfGrid(settings.grid) *
                 double(settings.grid);  // sqrt(n) = M
  if (config.grid_sequencing)
    options << " -" << prefix << "snes_grid_sequence " << levels - 1;
  PetscCall(PetscOptionsInsertString(nullptr, options.str().c_str()));

  PetscCall(PetscBarrier(nullptr));
  const double wall_start = WallSeconds(), cpu_start = ProcessCpuSeconds();
  DM da;
  Vec u;
  SNES snes;
  int total_steps = 0;
  PetscCall(CreateGrid(comm, start_grid, &da));
  PetscCall(SNESCreate(comm, &snes));
  PetscCall(SNESSetOptionsPrefix(snes, prefix.c_str()));
  PetscCall(SNESSetDM(snes, da));
  PetscCall(DMDASNESSetFunctionLocal(da, INSERT_VALUES,
                                     (DMDASNESFunction)FormResidualLocal, nullptr));
  PetscCall(DMDASNESSetJacobianLocal(da, (DMDASNESJacobian)FormJacobianLocal, nullptr));
  PetscCall(SNESSetType(snes, SnesTypeOf(config.kind)));
  PetscCall(SNESVISetComputeVariableBounds(snes, ComputeBoundsOnSnesGrid));
  PetscCall(SNESMonitorSet(snes, CountSteps, &total_steps, nullptr));
  PetscCall(SNESSetFromOptions(snes));
  PetscCall(DMCreateGlobalVector(da, &u));
  PetscCall(
      VecSet(u, 0.0));  // the zero start of every solver (the VI solvers project it)
  PetscCall(SNESSolve(snes, nullptr, u));
  PetscCall(FinishMeasurements(comm, wall_start, cpu_start, result));

  // After -snes_grid_sequence the SNES holds the finest DM and its solution.
  DM fine;
  Vec solution;
  SNESConvergedReason reason;
  PetscInt iterations, ksp_iterations;
  PetscCall(SNESGetDM(snes, &fine));
  PetscCall(SNESGetSolution(snes, &solution));
  PetscCall(SNESGetConvergedReason(snes, &reason));
  PetscCall(SNESGetIterationNumber(snes, &iterations));
  PetscCall(SNESGetLinearSolveIterations(snes, &ksp_iterations));
  PetscCall(VecGetSize(solution, &result->n));
  result->newton_iterations = int(iterations);
  result->total_newton_iterations = total_steps;
  result->ksp_iterations = int(ksp_iterations);
  result->native_status = SNESConvergedReasons[reason];
  result->status = StatusOf(reason);
  ErrorVsExact error;
  PetscCall(ComputeErrorVsExact(fine, solution, &error));
  result->error_max = error.max_norm;
  result->error_l2 = error.discrete_l2;
  PetscCall(ComputeNaturalResidual(fine, solution, &result->natural_residual));
  PetscCall(VecDestroy(&u));
  PetscCall(SNESDestroy(&snes));
  PetscCall(DMDestroy(&da));
  PetscFunctionReturn(0);
}

}  // namespace ncp_petsc_bench
