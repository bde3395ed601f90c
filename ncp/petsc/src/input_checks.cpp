// Misuse at the API boundary of ncp::petsc::Solver::Solve, checked collectively: the same
// exception on every rank.

#include "input_checks.hpp"

#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ncp::petsc {

[[noreturn]] void Misuse(const std::string& what) {
  throw std::invalid_argument("ncp::petsc::Solver::Solve: " + what);
}

void CheckLayout(MPI_Comm comm, Vec x, Vec v, const char* name) {
  PetscInt n = 0, nl = 0, N = 0, NL = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(VecGetSize(v, &N));
  NCP_PETSC_CHECK(VecGetLocalSize(v, &NL));
  if (AnyRank(comm, N != n || NL != nl))
    Misuse(std::string(name) + " has global size " + std::to_string(N) +
           ", the start point " + std::to_string(n) +
           (N == n ? " (but the local sizes differ on some rank)" : "") +
           ": both must have the same layout");
}

void CheckMatrixLayout(MPI_Comm comm, Vec x, Mat J) {
  PetscInt n = 0, nl = 0, rows = 0, cols = 0, local_rows = 0, local_cols = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(MatGetSize(J, &rows, &cols));
  NCP_PETSC_CHECK(MatGetLocalSize(J, &local_rows, &local_cols));
  if (AnyRank(comm, rows != n || cols != n || local_rows != nl || local_cols != nl))
    Misuse("the Jacobian matrix is " + std::to_string(rows) + " x " +
           std::to_string(cols) + ", the start point has size " + std::to_string(n) +
           ": the matrix must be square with rows and columns laid out like x");
}

// The first (lowest global index) bad entry of the bounds or the start point, reported
// with its values on every rank (the owner contributes them to a sum, the others zeros).
void CheckBoundsAndStart(MPI_Comm comm, PetscInt first, const LocalArray<double>& lower,
                         const LocalArray<double>& upper, Vec x) {
  const auto n = static_cast<PetscInt>(lower.size());
  LocalRead xa(x);
  long long bad = LLONG_MAX;
  for (PetscInt i = 0; i < n && bad == LLONG_MAX; ++i) {
    const double l = lower[static_cast<size_t>(i)], u = upper[static_cast<size_t>(i)];
    const bool problem = std::isnan(l) || std::isnan(u) || l > u ||
                         l == std::numeric_limits<double>::infinity() ||
                         u == -std::numeric_limits<double>::infinity() ||
                         !std::isfinite(xa[i]);
    if (problem) bad = first + i;
  }
  const long long global_bad = MinRanks(comm, bad);
  if (global_bad == LLONG_MAX) return;
  double values[3] = {0.0, 0.0, 0.0};  // l, u, x0 at global_bad
  if (bad == global_bad) {
    const auto i = static_cast<size_t>(bad - first);
    values[0] = lower[i];
    values[1] = upper[i];
    values[2] = xa[static_cast<PetscInt>(i)];
  }
  double at_bad[3];
  MPI_Allreduce(values, at_bad, 3, MPI_DOUBLE, MPI_SUM, comm);
  const double l = at_bad[0], u = at_bad[1], x0 = at_bad[2];
  const std::string at = "[" + std::to_string(global_bad) + "]";
  if (std::isnan(l) || std::isnan(u)) Misuse("bound" + at + " is NaN");
  if (l > u)
    Misuse("lower" + at + " = " + FormatNumber("%.17g", l) + " > upper" + at + " = " +
           FormatNumber("%.17g", u));
  if (l == std::numeric_limits<double>::infinity() ||
      u == -std::numeric_limits<double>::infinity())
    Misuse("empty box at" + at + " (lower = +inf or upper = -inf)");
  Misuse("start point x" + at + " = " + FormatNumber("%g", x0) + " is not finite");
}

// Solver::SetMultigridGrid's preconditions, checked collectively at the solve; the
// hierarchy is built here at the first solve on the grid.
void CheckMultigridGrid(MPI_Comm comm, KSP ksp, const std::string& prefix,
                        bool symmetric_newton, InactiveSetMultigrid& multigrid, Vec x) {
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  PetscBool mg = PETSC_FALSE;
  NCP_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCMG, &mg));
  if (!mg || !symmetric_newton)
    Misuse(
        "SetMultigridGrid restricts PCMG to the inactive set of the symmetrized "
        "Newton system: it needs -" +
        prefix + "pc_type mg and the symmetric mode (a CG-like KSP or -" + prefix +
        "symmetric_newton true); the PC is " +
        (mg ? std::string("mg") : std::string("not mg")) + ", symmetric mode " +
        (symmetric_newton ? "on" : "off"));
  Vec layout = nullptr;
  NCP_PETSC_CHECK(DMCreateGlobalVector(multigrid.grid(), &layout));
  PetscInt grid_local = 0, x_local = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(layout, &grid_local));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &x_local));
  VecDestroy(&layout);
  if (AnyRank(comm, grid_local != x_local))
    Misuse("the multigrid grid's global vectors have " + std::to_string(grid_local) +
           " local entries, the start point " + std::to_string(x_local) +
           " (on some rank): the grid must be the one x lives on");
  if (!multigrid.attached()) multigrid.Attach(pc);
}

}  // namespace ncp::petsc
