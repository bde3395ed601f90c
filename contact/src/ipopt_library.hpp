// Ipopt's C interface (coin/IpStdCInterface.h), reached through dlopen of libipopt.so.1
// on first use instead of linking it, so that Ipopt's sequential MUMPS never enters the
// process's global symbol scope (docs/petsc-contact.md, "Ipopt beside PETSc's parallel
// MUMPS").
//
// Debian's libipopt.so.1 needs libdmumps_seq, whose dmumps_c and whose one-process stubs
// of MPI_Init, MPI_Comm_rank, ... have the names of the parallel MUMPS and of MPI that
// PETSc calls. Loaded with RTLD_LOCAL | RTLD_DEEPBIND, libipopt and the libraries it
// brings resolve their references in their own dependency tree first (Ipopt's dmumps_c is
// libdmumps_seq's) and add nothing to the global scope (PETSc's dmumps_c stays
// libdmumps's, its MPI_Init libmpi's).
#pragma once

#include <coin/IpStdCInterface.h>

#include <string>

namespace contact::internal {

/// The entry points of libipopt.so.1 used by SolveConvexQpIpopt.
struct IpoptLibrary {
  decltype(&CreateIpoptProblem) create_problem = nullptr;
  decltype(&FreeIpoptProblem) free_problem = nullptr;
  decltype(&AddIpoptStrOption) add_string_option = nullptr;
  decltype(&AddIpoptNumOption) add_number_option = nullptr;
  decltype(&AddIpoptIntOption) add_integer_option = nullptr;
  decltype(&SetIntermediateCallback) set_intermediate_callback = nullptr;
  decltype(&IpoptSolve) solve = nullptr;
  /// Empty when every entry point above is set; otherwise why Ipopt cannot be used.
  std::string error;
};

/// Loads libipopt.so.1 once per process (thread-safe) and returns its entry points, or
/// the reason it cannot be used (library missing, or not isolable: under
/// AddressSanitizer, which refuses RTLD_DEEPBIND, while another MUMPS is in the global
/// scope).
const IpoptLibrary& LoadIpopt();

}  // namespace contact::internal
