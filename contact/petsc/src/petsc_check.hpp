// PETSc error codes as exceptions for contact::petsc (the calls are set-up or a step's
// vector operations: an error there is a programming or resource error, not a numerical
// outcome).
#pragma once

#include <petscsys.h>

#include <stdexcept>
#include <string>

namespace contact::petsc::internal {

/// Throws std::runtime_error naming the call, PETSc's error code and its message - the
/// generic text of the code and the specific one PETSc recorded (e.g. "Unable to find
/// requested KSP type nonsense" for -mass_ksp_type nonsense), so that a user sees which
/// option or input PETSc refused without PETSc's traceback.
inline void Check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  char* specific = nullptr;
  std::string what = std::string("contact::petsc: ") + call +
                     " failed with PETSc error " + std::to_string(static_cast<int>(code));
  if (PetscErrorMessage(code, &text, &specific) == 0) {
    if (text) what += ": " + std::string(text);
    if (specific && *specific) what += ": " + std::string(specific);
  }
  throw std::runtime_error(what);
}

}  // namespace contact::petsc::internal

#define CONTACT_PETSC_CHECK(call) ::contact::petsc::internal::Check((call), #call)
