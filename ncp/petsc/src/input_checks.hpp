// The checks of ncp::petsc::Solver::Solve's arguments. Each is collective: local
// violations are reduced over the communicator, so every rank throws the same
// std::invalid_argument (never one rank alone, which would leave the others waiting).
#pragma once

#include <petscksp.h>

#include <string>
#include <vector>

#include "huge_page_memory.hpp"
#include "inactive_set_multigrid.hpp"

namespace ncp::petsc {

// Throws std::invalid_argument("ncp::petsc::Solver::Solve: " + what).
[[noreturn]] void Misuse(const std::string& what);

// v (named `name` in the message) has x's global and local sizes.
void CheckLayout(MPI_Comm comm, Vec x, Vec v, const char* name);

// J is square with rows and columns laid out like x.
void CheckMatrixLayout(MPI_Comm comm, Vec x, Mat J);

// No NaN bound, no l > u, no empty box, a finite start point; the first bad entry (lowest
// global index) is reported with its values. first: the rank's first global row.
void CheckBoundsAndStart(MPI_Comm comm, PetscInt first, const LocalArray<double>& lower,
                         const LocalArray<double>& upper, Vec x);

// Solver::SetMultigridGrid's preconditions (PCMG, symmetric mode, the grid of x);
// attaches the hierarchy at the first solve on the grid.
void CheckMultigridGrid(MPI_Comm comm, KSP ksp, const std::string& prefix,
                        bool symmetric_newton, InactiveSetMultigrid& multigrid, Vec x);

}  // namespace ncp::petsc
