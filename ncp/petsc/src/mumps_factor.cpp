#include "mumps_factor.hpp"

#include <algorithm>
#include <string>

#include "petsc_support.hpp"
#include "rank_revealing.hpp"

namespace ncp::petsc {

bool UsesMumps(PC pc) {
  PetscBool factor = PETSC_FALSE;
  NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factor,
                                            PCLU, PCCHOLESKY, ""));
  MatSolverType type = nullptr;
  if (factor) NCP_PETSC_CHECK(PCFactorGetMatSolverType(pc, &type));
  return type && std::string(type) == MATSOLVERMUMPS;
}

bool IsDirectMumpsSolve(KSP ksp) {
  PetscBool preonly = PETSC_FALSE;
  NCP_PETSC_CHECK(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(ksp), KSPPREONLY, &preonly));
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  return preonly && UsesMumps(pc);
}

Mat MumpsFactor(KSP ksp) {
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  if (!UsesMumps(pc)) return nullptr;
  Mat F = nullptr;
  NCP_PETSC_CHECK(PCFactorGetMatrix(pc, &F));
  return F;
}

int MumpsWorkspaceToRetry(MPI_Comm comm, KSP ksp) {
  Mat F = MumpsFactor(ksp);
  PetscInt info = 0, percent = 0;
  if (F) {
    NCP_PETSC_CHECK(MatMumpsGetInfog(F, 1, &info));
    NCP_PETSC_CHECK(MatMumpsGetIcntl(F, 14, &percent));
  }
  const bool short_of_workspace = info == -8 || info == -9 || info == -11 ||
                                  info == -12 || info == -14 || info == -15 ||
                                  info == -17;
  if (!AnyRank(comm, short_of_workspace)) return 0;
  return static_cast<int>(
      std::max<long long>(50, 2 * -MinRanks(comm, -static_cast<long long>(percent))));
}

void ResetMumpsFactorization(KSP ksp, Mat op, int workspace_percent, bool null_pivots) {
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
  NCP_PETSC_CHECK(PCReset(pc));
  NCP_PETSC_CHECK(KSPSetOperators(ksp, op, op));
  if ((workspace_percent <= 0 && !null_pivots) || !UsesMumps(pc)) return;
  NCP_PETSC_CHECK(PCFactorSetUpMatSolverType(pc));
  Mat F = nullptr;
  NCP_PETSC_CHECK(PCFactorGetMatrix(pc, &F));
  if (workspace_percent > 0) NCP_PETSC_CHECK(MatMumpsSetIcntl(F, 14, workspace_percent));
  if (null_pivots) {
    PetscInt n = 0;
    NCP_PETSC_CHECK(MatGetSize(op, &n, nullptr));
    ArmNullPivotDetection(F, n);
  }
}

}  // namespace ncp::petsc
