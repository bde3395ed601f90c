// MUMPS (Amestoy et al. 2001) behind a PETSc KSP: which PC factorizes with MUMPS, its
// factor matrix, and the two recoveries of ncp::petsc::Solver's solves - a factorization
// retried with more workspace, and one set up afresh (MUMPS skips every numeric
// factorization after a failed one: its INFOG(1) stays < 0).
#pragma once

#include <petscksp.h>

namespace ncp::petsc {

// Whether pc is an LU or Cholesky factorization by MATSOLVERMUMPS.
bool UsesMumps(PC pc);

// Whether ksp is one direct MUMPS solve (KSPPREONLY with a MUMPS factorization).
bool IsDirectMumpsSolve(KSP ksp);

// MUMPS' factor matrix of ksp's PC (after a solve), or nullptr for another PC.
Mat MumpsFactor(KSP ksp);

// ICNTL(14) to factorize again with when ksp's PC is a MUMPS factorization that failed
// for want of workspace (INFOG(1) = -8, -9, -11, -12, -14, -15, -17: MUMPS' "increase
// ICNTL(14)" errors): twice the last ICNTL(14), at least 50 (percent); else 0. The same
// answer on every rank of comm (collective).
int MumpsWorkspaceToRetry(MPI_Comm comm, KSP ksp);

// The factorization of ksp's PC from scratch at the next solve of op, with MUMPS'
// ICNTL(14) = workspace_percent when that is > 0, and MUMPS' null-pivot detection
// (ArmNullPivotDetection, rank_revealing.hpp) when null_pivots.
void ResetMumpsFactorization(KSP ksp, Mat op, int workspace_percent, bool null_pivots);

}  // namespace ncp::petsc
