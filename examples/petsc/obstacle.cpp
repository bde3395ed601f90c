// The 2D obstacle problem on PETSc with ncp::petsc: a membrane over (0,1)^2, clamped at
// the boundary, pushed up by an obstacle:
//
//     -Lap u = f,  u >= psi  in (0,1)^2,  complementarity  (u - psi) (-Lap u - f) = 0,
//     u = 0 on the boundary,
//
// with f = 0 and the bump psi(x, y) = 1/2 - 8 |(x, y) - (1/2, 1/2)|^2 (the problem
// ncp::collection::Obstacle2D(m, kLowerBump) solves on one process). Finite differences
// on an m x m grid of interior nodes, h = 1/(m + 1), 5-point stencil: the box MCP
//
//     u >= psi  perp  F(u) = h^-2 (4 u_ij - u_i-1,j - u_i+1,j - u_i,j-1 - u_i,j+1) -
//     f_ij.
//
// Run (docs/petsc.md):
//   mpiexec -n 2 ./bin/ncp-petsc-obstacle -m 300
//   mpiexec -n 2 ./bin/ncp-petsc-obstacle -m 1000 -ncp_ksp_type cg -ncp_pc_type gamg
//   -ncp_ksp_rtol 1e-10
// Options: -m <interior nodes per direction>, -function fb|min|pfb, -tolerance <on
// ||Phi||_inf, default 1e-10; below the rows' round-off floor the solve ends
// at-roundoff-floor>, -trace (one line per Newton iteration), and every -ncp_ksp_* /
// -ncp_pc_* option of PETSc for the Newton systems (default: MUMPS LU); --help prints
// them (kUsage), --version the version.
//
// Copy this file to start your own problem: the grid (a DMDA) gives the layout,
// Residual() and Jacobian() are all the solver needs, and the bounds are plain Vecs.

#include <petscdmda.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "ncp/petsc/solver.hpp"

namespace {

class ObstacleProblem {
 public:
  explicit ObstacleProblem(PetscInt m) : m_(m), h_(1.0 / static_cast<double>(m + 1)) {}
  ~ObstacleProblem() {
    VecDestroy(&u_);
    VecDestroy(&psi_);
    MatDestroy(&J_);
    DMDestroy(&da_);
  }

  // ---- the grid: a DMDA of m x m interior nodes, one unknown each, stencil width 1 ----
  PetscErrorCode MakeGrid() {
    PetscFunctionBeginUser;
    PetscCall(DMDACreate2d(PETSC_COMM_WORLD, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE,
                           DMDA_STENCIL_STAR, m_, m_, PETSC_DECIDE, PETSC_DECIDE, 1, 1,
                           nullptr, nullptr, &da_));
    PetscCall(DMSetFromOptions(da_));
    PetscCall(DMSetUp(da_));
    PetscCall(DMCreateGlobalVector(da_, &u_));
    PetscCall(VecDuplicate(u_, &psi_));
    PetscCall(
        DMCreateMatrix(da_, &J_));  // AIJ with the 5-point pattern, rows laid out like u
    PetscFunctionReturn(0);
  }

  // ---- the obstacle psi (the lower bound) and the start u0 = 0 ------------------------
  PetscErrorCode MakeBounds() {
    PetscFunctionBeginUser;
    DMDALocalInfo info;
    PetscCall(DMDAGetLocalInfo(da_, &info));
    PetscScalar** psi = nullptr;
    PetscCall(DMDAVecGetArray(da_, psi_, &psi));
    for (PetscInt j = info.ys; j < info.ys + info.ym; ++j)
      for (PetscInt i = info.xs; i < info.xs + info.xm; ++i) {
        const double x = (i + 1) * h_ - 0.5, y = (j + 1) * h_ - 0.5;
        psi[j][i] = 0.5 - 8.0 * (x * x + y * y);
      }
    PetscCall(DMDAVecRestoreArray(da_, psi_, &psi));
    PetscCall(VecSet(u_, 0.0));
    PetscFunctionReturn(0);
  }

  // ---- F(u) = -Lap_h u - f on the local part of the grid (ghosts from the DMDA) -------
  PetscErrorCode Residual(Vec u, Vec F) {
    PetscFunctionBeginUser;
    Vec local = nullptr;
    PetscCall(DMGetLocalVector(da_, &local));
    PetscCall(DMGlobalToLocalBegin(da_, u, INSERT_VALUES, local));
    PetscCall(DMGlobalToLocalEnd(da_, u, INSERT_VALUES, local));
    DMDALocalInfo info;
    PetscCall(DMDAGetLocalInfo(da_, &info));
    const PetscScalar** uu = nullptr;
    PetscScalar** ff = nullptr;
    PetscCall(DMDAVecGetArrayRead(da_, local, &uu));
    PetscCall(DMDAVecGetArray(da_, F, &ff));
    const double inverse_h2 = 1.0 / (h_ * h_);
    // u = 0 on the boundary: a neighbour outside the interior contributes nothing.
    auto at = [&](PetscInt i, PetscInt j) {
      return i < 0 || j < 0 || i >= m_ || j >= m_ ? 0.0 : uu[j][i];
    };
    for (PetscInt j = info.ys; j < info.ys + info.ym; ++j)
      for (PetscInt i = info.xs; i < info.xs + info.xm; ++i) {
        const double c = uu[j][i];
        ff[j][i] = inverse_h2 * (((c - at(i - 1, j)) + (c - at(i + 1, j))) +
                                 ((c - at(i, j - 1)) + (c - at(i, j + 1)))) -
                   kLoad;
      }
    PetscCall(DMDAVecRestoreArrayRead(da_, local, &uu));
    PetscCall(DMDAVecRestoreArray(da_, F, &ff));
    PetscCall(DMRestoreLocalVector(da_, &local));
    PetscFunctionReturn(0);
  }

  // ---- F'(u): the 5-point Laplacian h^-2 [4; -1 -1 -1 -1] (constant, F is affine) ----
  PetscErrorCode Jacobian(Vec, Mat J) {
    PetscFunctionBeginUser;
    DMDALocalInfo info;
    PetscCall(DMDAGetLocalInfo(da_, &info));
    const double inverse_h2 = 1.0 / (h_ * h_);
    for (PetscInt j = info.ys; j < info.ys + info.ym; ++j)
      for (PetscInt i = info.xs; i < info.xs + info.xm; ++i) {
        MatStencil row = {0, j, i, 0}, cols[5];
        PetscScalar values[5];
        PetscInt count = 0;
        auto add = [&](PetscInt ii, PetscInt jj, double v) {
          if (ii < 0 || jj < 0 || ii >= m_ || jj >= m_)
            return;  // boundary node: no unknown
          cols[count] = MatStencil{0, jj, ii, 0};
          values[count++] = v;
        };
        add(i, j, 4.0 * inverse_h2);
        add(i - 1, j, -inverse_h2);
        add(i + 1, j, -inverse_h2);
        add(i, j - 1, -inverse_h2);
        add(i, j + 1, -inverse_h2);
        PetscCall(MatSetValuesStencil(J, 1, &row, count, cols, values, INSERT_VALUES));
      }
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    PetscFunctionReturn(0);
  }

  // ---- the solve: ncp::petsc::Solver with the options from the command line -----------
  ncp::Summary Solve(const ncp::Options& options, ncp::petsc::KspReport* report) {
    ncp::petsc::BoxMcp problem;
    problem.residual = [this](Vec u, Vec F) { return Residual(u, F); };
    problem.jacobian = [this](Vec u, Mat J) { return Jacobian(u, J); };
    problem.jacobian_matrix = J_;
    problem.lower = psi_;  // u >= psi
    problem.upper =
        nullptr;  // no upper bound (a Vec of PETSC_INFINITY would say the same)
    ncp::petsc::Solver solver(PETSC_COMM_WORLD, options, "ncp_");
    ncp::Summary summary;
    solver.Solve(problem, u_, &summary);
    *report = solver.ksp_report();
    return summary;
  }

  // ---- an independent check: ||min(u - psi, F(u))||_inf, and the contact set's size ---
  PetscErrorCode Check(double* natural_residual, PetscInt* contact_nodes) {
    PetscFunctionBeginUser;
    Vec F = nullptr;
    PetscCall(VecDuplicate(u_, &F));
    PetscCall(Residual(u_, F));
    const PetscScalar *u = nullptr, *psi = nullptr, *f = nullptr;
    PetscInt n = 0;
    PetscCall(VecGetLocalSize(u_, &n));
    PetscCall(VecGetArrayRead(u_, &u));
    PetscCall(VecGetArrayRead(psi_, &psi));
    PetscCall(VecGetArrayRead(F, &f));
    double local_residual = 0.0;
    PetscInt local_contact = 0;
    for (PetscInt k = 0; k < n; ++k) {
      local_residual = std::max(local_residual, std::abs(std::min(u[k] - psi[k], f[k])));
      local_contact += u[k] - psi[k] <= 1e-12;
    }
    PetscCall(VecRestoreArrayRead(u_, &u));
    PetscCall(VecRestoreArrayRead(psi_, &psi));
    PetscCall(VecRestoreArrayRead(F, &f));
    PetscCall(VecDestroy(&F));
    MPI_Allreduce(&local_residual, natural_residual, 1, MPI_DOUBLE, MPI_MAX,
                  PETSC_COMM_WORLD);
    MPI_Allreduce(&local_contact, contact_nodes, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD);
    PetscFunctionReturn(0);
  }

 private:
  static constexpr double kLoad = 0.0;  // f
  PetscInt m_;
  double h_;
  DM da_ = nullptr;
  Vec u_ = nullptr, psi_ = nullptr;
  Mat J_ = nullptr;
};

PetscErrorCode Run() {
  PetscFunctionBeginUser;
  PetscInt m = 300;
  char function[16] = "fb";
  PetscBool trace = PETSC_FALSE;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-m", &m, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-function", function,
                                  sizeof function, nullptr));
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-trace", &trace, nullptr));
  ncp::Options options;
  PetscCall(
      PetscOptionsGetReal(nullptr, nullptr, "-tolerance", &options.tolerance, nullptr));
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance))
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
            "-tolerance (on ||Phi||_inf) must be finite and >= 0, got %g",
            static_cast<double>(options.tolerance));
  if (m < 1)
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
            "-m (interior nodes per side) must be >= 1, got %d", static_cast<int>(m));
  options.log_to_stderr = trace;
  // Start from u0 = 0 as given, below the obstacle where it rises above 0: projected onto
  // u >= psi the start would hold the obstacle's kinks, from which the method needs more
  // iterations (docs/petsc.md gives both counts).
  options.project_start_point = false;
  if (std::strcmp(function, "min") == 0)
    options.ncp_function = ncp::NcpFunction::kMin;
  else if (std::strcmp(function, "pfb") == 0)
    options.ncp_function = ncp::NcpFunction::kPenalizedFischerBurmeister;
  else if (std::strcmp(function, "fb") != 0)
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
            "-function must be fb, min or pfb, got %s", function);

  ObstacleProblem obstacle(m);
  PetscCall(obstacle.MakeGrid());
  PetscCall(obstacle.MakeBounds());
  ncp::petsc::KspReport report;
  const ncp::Summary summary = obstacle.Solve(options, &report);
  double natural_residual = 0.0;
  PetscInt contact = 0;
  PetscCall(obstacle.Check(&natural_residual, &contact));

  PetscCall(PetscPrintf(
      PETSC_COMM_WORLD,
      "2D obstacle, %d x %d = %d unknowns on %d ranks, KSP %s + %s%s%s\n",
      static_cast<int>(m), static_cast<int>(m), static_cast<int>(m * m), report.ranks,
      report.ksp_type.c_str(), report.pc_type.c_str(),
      report.factor_solver_type.empty() ? "" : " ", report.factor_solver_type.c_str()));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n  %s\n", summary.BriefReport().c_str(),
                        summary.message.c_str()));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "Newton iterations %d, linear iterations %d, contact nodes %d, "
                        "||min(u - psi, F(u))||_inf = %.3e (recomputed)\n",
                        summary.iterations, report.linear_iterations,
                        static_cast<int>(contact), natural_residual));
  if (!summary.IsSolutionUsable())
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "not solved");
  PetscFunctionReturn(0);
}

constexpr const char* kUsage =
    "ncp-petsc-obstacle: the 2D obstacle problem -Lap u = 0, u >= psi (a bump), u = 0 "
    "on\n"
    "the boundary of (0,1)^2, on an m x m grid of interior nodes, solved by ncp::petsc.\n"
    "\n"
    "usage: [mpiexec -n R] ncp-petsc-obstacle [options]\n"
    "  -m N              interior nodes per direction (N >= 1, default 300)\n"
    "  -function F       NCP function: fb (default), min or pfb\n"
    "  -tolerance T      on ||Phi||_inf (default 1e-10); below the round-off floor the\n"
    "                    solve ends at-roundoff-floor (usable, not converged)\n"
    "  -trace            one line per Newton iteration on stderr\n"
    "  -ncp_ksp_* -ncp_pc_*  PETSc's options of the Newton systems (default: MUMPS LU)\n"
    "  -help             PETSc's list of the options the run queries (runs the problem)\n"
    "  -h, --help        this help;  --version  the version\n"
    "Exit code 0: usable (converged, or at the round-off floor); 1 otherwise (the "
    "status\n"
    "says why).\n";

/// --help, -h and --version answer without PETSc and without running the problem.
bool AnswersWithoutRunning(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return true;
    }
    if (std::strcmp(argv[i], "--version") == 0) {
      std::printf("ncp-petsc-obstacle %s\n", NCP_VERSION);
      return true;
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (AnswersWithoutRunning(argc, argv)) return 0;
  PetscCall(
      PetscInitialize(&argc, &argv, nullptr, nullptr));  // the user's job, not ncp's
  PetscErrorCode code = 0;
  try {
    code = Run();
  } catch (const std::exception& e) {
    PetscPrintf(PETSC_COMM_WORLD, "error: %s\n", e.what());
    code = 1;
  }
  PetscCall(PetscFinalize());
  return code == 0 ? 0 : 1;
}
