// The ncp rows: ncp::petsc::Solver (FB or min semismooth Newton) on the obstacle
// problem, with nested iteration when asked: solve on the coarse grid, interpolate the
// solution bilinearly (DMRefine + DMCreateInterpolation) to the next grid as its start
// point, and repeat up to the finest grid (full multigrid's outer loop; Bueler 2021, ch.
// 12).
#include <petscdmda.h>

#include <sstream>

#include "bueler_obstacle.hpp"
#include "ncp/petsc/solver.hpp"
#include "obstacle_runs.hpp"

namespace ncp_petsc_bench {
namespace {

std::string StatusOf(ncp::TerminationType termination) {
  switch (termination) {
    case ncp::TerminationType::kConverged:
      return "converged";
    case ncp::TerminationType::kAtRoundoffFloor:
      return "at_roundoff_floor";
    case ncp::TerminationType::kMaxIterations:
      return "max_iterations";
    case ncp::TerminationType::kTimeLimit:
      return "time_limit";
    case ncp::TerminationType::kStationaryPoint:
      return "stationary_point";
    case ncp::TerminationType::kLineSearchFailure:
      return "line_search_failure";
    case ncp::TerminationType::kNonFiniteValues:
      return "numerical_error";
    default:
      return "failure";
  }
}

/// One grid of the sequence: its DMDA, bounds and Jacobian matrix.
struct GridLevel {
  DM da = nullptr;
  Vec lower = nullptr, upper = nullptr;
  Mat jacobian = nullptr;
  PetscErrorCode Create(DM grid) {
    PetscFunctionBeginUser;
    da = grid;
    PetscCall(DMCreateGlobalVector(da, &lower));
    PetscCall(VecDuplicate(lower, &upper));
    PetscCall(FormBounds(da, lower, upper));
    PetscCall(DMCreateMatrix(da, &jacobian));
    PetscFunctionReturn(0);
  }
  PetscErrorCode Destroy() {
    PetscFunctionBeginUser;
    PetscCall(MatDestroy(&jacobian));
    PetscCall(VecDestroy(&lower));
    PetscCall(VecDestroy(&upper));
    PetscCall(DMDestroy(&da));
    PetscFunctionReturn(0);
  }
};

/// Solves the obstacle problem on `level` from x (start in, solution out).
PetscErrorCode SolveOnGrid(const RunConfig& config, const RunSettings& settings,
                           const GridLevel& level, int mg_levels, Vec x,
                           ncp::Summary* summary, int* ksp_iterations) {
  PetscFunctionBeginUser;
  const std::string prefix = OptionsPrefix(config);
  PetscCall(PetscOptionsInsertString(
      nullptr,
      LinearOptions(config.linear, config.kind, prefix, settings, mg_levels).c_str()));
  ncp::Options options;
  options.ncp_function = config.kind == SolverKind::kNcpMin
                             ? ncp::NcpFunction::kMin
                             : ncp::NcpFunction::kFischerBurmeister;
  double area = 0.0;
  PetscCall(CellArea(level.da, &area));
  options.tolerance = settings.tolerance * area;  // F is -Laplace u times the cell area
  options.max_iterations = settings.max_newton_iterations;
  PetscBool trace = PETSC_FALSE;  // -bench_trace: ncp's iteration log on stderr
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-bench_trace", &trace, nullptr));
  options.log_to_stderr = trace == PETSC_TRUE;
  // The min function's rows compare u - psi with F scaled by min_scale (RunSettings):
  // the tolerance scales with F, so the test on the rows where F is the smaller side is
  // unchanged (and stricter where u - psi is).
  const double scale = config.kind == SolverKind::kNcpMin ? settings.min_scale : 1.0;
  options.tolerance *= scale;
  ncp::petsc::Solver solver(PetscObjectComm((PetscObject)level.da), options, prefix);
  // -bench_full_galerkin: PCMG on the whole embedded Newton matrix (the eliminated rows
  // included in the Galerkin products), for comparison with the inactive-set multigrid.
  PetscBool full_galerkin = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-bench_full_galerkin", &full_galerkin,
                                nullptr));
  if (config.linear == LinearFamily::kMultigrid && config.kind == SolverKind::kNcpMin &&
      !full_galerkin) {
    // The min function's Newton system is the reduced (inactive-set) system: PCMG on the
    // grid's hierarchy restricted to the inactive set at each step (SetMultigridGrid).
    solver.SetMultigridGrid(level.da);
  } else if (config.linear == LinearFamily::kMultigrid) {
    // PCMG builds its hierarchy by coarsening this grid; the Newton matrix D_a + D_b F'
    // is not a rediscretization, so the coarse operators are Galerkin products P^T A P.
    PetscCall(KSPSetDM(solver.ksp(), level.da));
    PetscCall(KSPSetDMActive(solver.ksp(), PETSC_FALSE));
    PC pc;
    PetscCall(KSPGetPC(solver.ksp(), &pc));
    PetscCall(PCSetType(pc, PCMG));
    PetscCall(PCMGSetGalerkin(pc, PC_MG_GALERKIN_PMAT));
  }
  DM da = level.da;
  ncp::petsc::BoxMcp problem;
  problem.residual = [da, scale](Vec u, Vec f) {
    PetscCall(EvaluateResidual(da, u, f));
    return VecScale(f, scale);
  };
  problem.jacobian = [da, scale](Vec u, Mat J) {
    PetscCall(EvaluateJacobian(da, u, J));
    return MatScale(J, scale);
  };
  problem.jacobian_matrix = level.jacobian;
  problem.lower = level.lower;
  problem.upper = level.upper;
  solver.Solve(problem, x, summary);
  if (trace)
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)level.da), "%s\n",
                          summary->message.c_str()));
  *ksp_iterations = solver.ksp_report().linear_iterations;
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode RunNcp(const RunConfig& config, const RunSettings& settings,
                      RunResult* result) {
  PetscFunctionBeginUser;
  const MPI_Comm comm = PETSC_COMM_WORLD;
  int levels = 0;
  PetscCall(CheckedGridLevels(config, settings, &levels));
  PetscCall(PetscBarrier(nullptr));
  const double wall_start = WallSeconds(), cpu_start = ProcessCpuSeconds();

  GridLevel level;
  DM grid;
  PetscCall(CreateGrid(
      comm, config.grid_sequencing ? settings.coarse_grid : settings.grid, &grid));
  PetscCall(level.Create(grid));
  Vec x;
  PetscCall(DMCreateGlobalVector(level.da, &x));
  PetscCall(VecSet(x, 0.0));  // the zero start of every solver
  ncp::Summary summary;
  int total_steps = 0, ksp_iterations = 0;
  const int num_grids = config.grid_sequencing ? levels : 1;
  for (int k = 0; k < num_grids; ++k) {
    if (k > 0) {  // refine: the interpolated coarse solution starts the finer solve
      DM finer;
      Vec x_fine;
      PetscCall(DMRefine(level.da, comm, &finer));
      // The finer grid remembers the grid it was refined from, and the interpolation
      // between them is kept on it (ncp::petsc::GridInterpolation): the multigrid of
      // SetMultigridGrid takes its coarse levels and their interpolations from there.
      PetscCall(DMSetCoarseDM(finer, level.da));
      Mat interpolation = ncp::petsc::GridInterpolation(level.da, finer);  // borrowed
      PetscCall(DMCreateGlobalVector(finer, &x_fine));
      PetscCall(MatInterpolate(interpolation, x, x_fine));
      PetscCall(VecDestroy(&x));
      PetscCall(level.Destroy());
      PetscCall(level.Create(finer));
      x = x_fine;
    }
    // Multigrid levels: the refinements made so far (directly made grids: by halving).
    const int mg_levels = config.grid_sequencing ? k + 1 : (levels > 0 ? levels : 1);
    PetscCall(
        SolveOnGrid(config, settings, level, mg_levels, x, &summary, &ksp_iterations));
    total_steps += summary.iterations;
    if (!summary.IsSolutionUsable()) break;
  }
  PetscCall(FinishMeasurements(comm, wall_start, cpu_start, result));

  result->n =
      settings.grid * settings.grid;  // a sequence that stopped early reports the goal
  result->newton_iterations = summary.iterations;
  result->total_newton_iterations = total_steps;
  result->ksp_iterations = ksp_iterations;
  result->status = StatusOf(summary.termination);
  result->native_status = ncp::ToString(summary.termination);
  ErrorVsExact error;
  PetscCall(ComputeErrorVsExact(level.da, x, &error));
  result->error_max = error.max_norm;
  result->error_l2 = error.discrete_l2;
  PetscCall(ComputeNaturalResidual(level.da, x, &result->natural_residual));
  PetscCall(VecDestroy(&x));
  PetscCall(level.Destroy());
  PetscFunctionReturn(0);
}

}  // namespace ncp_petsc_bench
