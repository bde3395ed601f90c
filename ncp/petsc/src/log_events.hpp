// PETSc log events of ncp::petsc::Solver's phases, so that -log_view shows where a solve
// spends its time next to PETSc's own events (KSPSolve, MatPtAP, ...). Registered once
// per PetscInitialize. Without -log_view PetscLogEventBegin/End test a flag and return.
#pragma once

#include <petscsys.h>

namespace ncp::petsc {

struct LogEvents {
  PetscLogEvent solve;       // NCPSolve: Solver::Solve as a whole
  PetscLogEvent start;       // NCPStart: work vectors, KSP configuration, Phi(x0)
  PetscLogEvent newton_mat;  // NCPNewtonMat: the Newton matrix (re)built for F''s pattern
  PetscLogEvent evaluate;    // NCPEvaluate: F (callback) and Phi row by row
  PetscLogEvent jacobian;    // NCPJacobian: F' (callback), c_F, c_I, grad psi
  PetscLogEvent roundoff;    // NCPRoundoff: the round-off floor |G||y|
  PetscLogEvent symmetrize;  // NCPSymmetrize: the reduced symmetric Newton system
  PetscLogEvent mg_update;   // NCPMGUpdate: Galerkin operators of the inactive set
  PetscLogEvent backward;    // NCPBackwardErr: J d + Phi and |J||d| of the guard
  PetscLogEvent line_search;  // NCPLineSearch: Armijo trials (evaluations included)
};

// The events, registered at the first call after PetscInitialize.
const LogEvents& SolverLogEvents();

// PetscLogEventBegin/End of `event` for the lifetime of the object.
class LogScope {
 public:
  explicit LogScope(PetscLogEvent event) : event_(event) {
    PetscLogEventBegin(event_, 0, 0, 0, 0);
  }
  ~LogScope() { PetscLogEventEnd(event_, 0, 0, 0, 0); }
  LogScope(const LogScope&) = delete;
  LogScope& operator=(const LogScope&) = delete;

 private:
  PetscLogEvent event_;
};

}  // namespace ncp::petsc
