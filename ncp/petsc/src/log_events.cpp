#include "log_events.hpp"

#include <stdexcept>

namespace ncp::petsc {
namespace {

LogEvents events;
bool registered = false;

PetscErrorCode ForgetEvents() {
  registered = false;  // PetscFinalize drops the event log; register anew after
  return 0;
}

PetscErrorCode RegisterEvents() {
  PetscFunctionBeginUser;
  PetscClassId id = 0;
  PetscCall(PetscClassIdRegister("ncp::petsc::Solver", &id));
  PetscCall(PetscLogEventRegister("NCPSolve", id, &events.solve));
  PetscCall(PetscLogEventRegister("NCPStart", id, &events.start));
  PetscCall(PetscLogEventRegister("NCPNewtonMat", id, &events.newton_mat));
  PetscCall(PetscLogEventRegister("NCPEvaluate", id, &events.evaluate));
  PetscCall(PetscLogEventRegister("NCPJacobian", id, &events.jacobian));
  PetscCall(PetscLogEventRegister("NCPRoundoff", id, &events.roundoff));
  PetscCall(PetscLogEventRegister("NCPSymmetrize", id, &events.symmetrize));
  PetscCall(PetscLogEventRegister("NCPMGUpdate", id, &events.mg_update));
  PetscCall(PetscLogEventRegister("NCPBackwardErr", id, &events.backward));
  PetscCall(PetscLogEventRegister("NCPLineSearch", id, &events.line_search));
  PetscCall(PetscRegisterFinalize(ForgetEvents));
  PetscFunctionReturn(0);
}

}  // namespace

const LogEvents& SolverLogEvents() {
  if (!registered) {
    if (RegisterEvents() != 0)
      throw std::runtime_error("ncp::petsc::Solver: PetscLogEventRegister failed");
    registered = true;
  }
  return events;
}

}  // namespace ncp::petsc
