// PETSc error codes as exceptions for contact::petsc (the calls are set-up or a step's
// vector operations: an error there is a programming or resource error, not a numerical
// outcome).
#pragma once

#include <petscsys.h>

#include <stdexcept>
#include <string>

namespace contact::petsc::internal {

inline void Check(PetscErrorCode code, const char* call) {
  if (code != 0)
    throw std::runtime_error(std::string("contact::petsc: ") + call +
                             " failed with PETSc error " +
                             std::to_string(static_cast<int>(code)));
}

}  // namespace contact::petsc::internal

#define CONTACT_PETSC_CHECK(call) ::contact::petsc::internal::Check((call), #call)
