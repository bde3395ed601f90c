// The Catch2 main of the tests that run under mpiexec (label mpi).
#pragma once

#include <petscsys.h>

#include <catch2/catch.hpp>
#include <utility>
#include <vector>

/// main() of the tests under mpiexec: every rank runs every test (the solves are
/// collective), a failure on any rank fails the test; a failure prints doubles in full.
/// `options`: PETSc options set before the tests (name, value).
inline int RunTestsOnRanks(
    int argc, char** argv,
    const std::vector<std::pair<const char*, const char*>>& options = {}) {
  if (PetscInitializeNoArguments() != 0) return 1;  // (PETSc options: PETSC_OPTIONS)
  for (const auto& [name, value] : options)
    if (PetscOptionsSetValue(nullptr, name, value) != 0) return 1;
  int result = 0;
  {
    Catch::StringMaker<double>::precision = 17;
    Catch::Session session;
    result = session.run(argc, argv);
  }
  MPI_Allreduce(MPI_IN_PLACE, &result, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  PetscFinalize();
  return result;
}
