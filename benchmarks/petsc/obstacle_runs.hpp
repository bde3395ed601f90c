/// \file obstacle_runs.hpp
/// One run of one solver configuration on Bueler's obstacle problem
/// (bueler_obstacle.hpp): ncp::petsc::Solver with nested iteration, or PETSc's SNESVI
/// (SSLS, RSLS) with or without -snes_grid_sequence, each with the same KSP/PC family.
#pragma once

#include <petscsys.h>

#include <string>

namespace ncp_petsc_bench {

enum class SolverKind {
  kNcpFischerBurmeister,  ///< ncp::petsc::Solver, phi = Fischer-Burmeister
  kNcpMin,      ///< ncp::petsc::Solver, phi = min (the primal-dual active set method)
  kSnesViSsls,  ///< SNESVINEWTONSSLS (semismooth FB Newton, Munson et al. 2001)
  kSnesViRsls,  ///< SNESVINEWTONRSLS (reduced-space active set)
};
/// The KSP/PC of the Newton systems, the same options for every solver kind.
enum class LinearFamily {
  kMumpsLu,    ///< preonly + LU by MUMPS
  kMultigrid,  ///< Krylov + PCMG on the DMDA hierarchy, SOR smoother (Galerkin coarse
               ///< operators for ncp)
  kHypre,      ///< Krylov + hypre BoomerAMG
  kGamg,       ///< Krylov + PETSc's GAMG
};
/// The Krylov method of the iterative families follows the Newton matrix: CG where it is
/// symmetric positive definite - RSLS: the Laplacian restricted to the inactive set; ncp
/// with the min function: the same reduced system, since its Newton row is e_i' on the
/// active set (d_i eliminated exactly) and F'_i on the inactive set (ncp::petsc's
/// symmetric mode, on for CG) - GMRES where it is not (SSLS and ncp with FB:
/// diag(c_F) F' + diag(c_I), rows scaled differently).
bool HasSymmetricNewtonMatrix(SolverKind kind);
/// "preonly+lu", "cg+mg", "gmres+hypre", ...: the KSP and PC a configuration runs with.
std::string KspDescription(LinearFamily linear, SolverKind kind);

struct RunConfig {
  std::string name;  ///< row label, e.g. "ncp-fb-seq-mg"; ncp rows start with "ncp"
  SolverKind kind = SolverKind::kNcpFischerBurmeister;
  bool grid_sequencing =
      false;  ///< solve coarse first, interpolate, refine (nested iteration)
  LinearFamily linear = LinearFamily::kMultigrid;
};

struct RunSettings {
  PetscInt grid = 0;         ///< finest grid: nodes per side M (n = M^2)
  PetscInt coarse_grid = 0;  ///< coarsest grid of the sequence / multigrid hierarchy
  /// Newton stopping test in the units of -Laplace u (F divided by the cell area h^2):
  /// ncp stops at ||Phi||_inf <= tolerance h^2; SNESVI at ||residual||_2 <= tolerance h^2
  /// sqrt(n) (an RMS of tolerance h^2, the same scale). Bounds the algebraic error in u
  /// by about tolerance / (pi^2 / 8), below the discretization error of every grid run
  /// here.
  double tolerance = 1e-8;
  /// A converged run whose recomputed natural residual max_i |min(u_i - psi_i, F_i)|
  /// (units of -Laplace u) exceeds this is "false_convergence". Looser than `tolerance`
  /// because SNESVI tests a 2-norm (an RMS), not the max; error_vs_exact judges accuracy.
  double check_tolerance = 1e-5;
  int max_newton_iterations = 100;
  /// ncp with the min function solves min(u - psi, s F) = 0 with s = min_scale (and its
  /// tolerance times s). The solution does not depend on s, the Newton path does: a row
  /// is taken as active when u - psi < s F, the primal-dual active set method's rule
  /// lambda + c (psi - u) > 0 with c = 1 / (s h^2) in units of -Laplace u. A smaller s
  /// trusts the multiplier more than the gap, as the reduced-space method (active only
  /// at the bound with F > 0) does in the limit s -> 0. Default 0.1: from the
  /// interpolated coarse solution, 2 finest-grid Newton steps instead of 3 at 2.6e5 and
  /// 1e6 unknowns (benchmarks/results/petsc/solver/README.md).
  double min_scale = 0.1;
  double ksp_rtol = 1e-6;  ///< relative tolerance of each Krylov solve (not used by LU)
};

struct RunResult {
  int ranks = -1;
  PetscInt n = -1;
  int newton_iterations = -1;        ///< on the finest grid
  int total_newton_iterations = -1;  ///< summed over all grids of the sequence
  int ksp_iterations = -1;           ///< on the finest grid
  double seconds = -1.0;             ///< wall time, slowest rank, grid setup to solution
  double cpu_seconds = -1.0;         ///< process CPU time summed over ranks
  double error_max = -1.0;           ///< max |u - u_exact| at the nodes
  double error_l2 = -1.0;            ///< discrete L2 norm of u - u_exact
  double natural_residual = -1.0;    ///< recomputed max |min(u - psi, F(u))|
  std::string status = "failure";    ///< shared vocabulary (ncp-bench)
  std::string native_status;         ///< the solver's own reason
  double peak_rss_mib = -1.0;  ///< largest resident set of a rank (process lifetime)
};

/// The PETSc options string of a linear family under `prefix` (e.g. "-ssls_ksp_type cg
/// ...").
std::string LinearOptions(LinearFamily linear, SolverKind kind, const std::string& prefix,
                          const RunSettings& settings, int multigrid_levels);
/// Prefix of a configuration's objects in PETSc's options database: its name with '-' ->
/// '_'.
std::string OptionsPrefix(const RunConfig& config);
/// Number of grids from coarse_grid to grid by doubling (grid - 1 = (coarse_grid - 1)
/// 2^k): k + 1; 0 when grid is not in that sequence.
int GridLevels(PetscInt coarse_grid, PetscInt grid);
/// GridLevels of the settings; an error if grid sequencing needs them and the grid is not
/// a refinement of the coarse grid.
PetscErrorCode CheckedGridLevels(const RunConfig& config, const RunSettings& settings,
                                 int* levels);

PetscErrorCode RunSnesVi(const RunConfig& config, const RunSettings& settings,
                         RunResult* result);
PetscErrorCode RunNcp(const RunConfig& config, const RunSettings& settings,
                      RunResult* result);

/// Wall and CPU clocks, and the per-run collective measurements.
double WallSeconds();
double ProcessCpuSeconds();
PetscErrorCode FinishMeasurements(MPI_Comm comm, double wall_start, double cpu_start,
                                  RunResult* result);

}  // namespace ncp_petsc_bench
