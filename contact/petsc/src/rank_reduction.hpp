// Sums and maxima over the ranks of a communicator for ncp::fc's distributed operator
// problem (ncp/fc/operator_problem.hpp, Reduction): the contact Newton of the sparse step
// on ranks (distributed_implicit_step.hpp, ContactSolve::kDistributed) runs on every rank
// over the rank's own contact nodes, and each of its dot products, norms and maxima is
// reduced here. Each rank's values are gathered onto every rank (one MPI_Allgather) and
// combined in rank order, so every rank gets the same bits (MPI_Allreduce does not
// promise that) and a run gets the same bits as another with the same partition; every
// rank then takes the same branch of the Newton and none waits alone in a collective
// call.
#pragma once

#include <mpi.h>

#include <string>

#include "ncp/fc/operator_problem.hpp"

namespace contact::petsc::internal {

/// The reduction over the ranks of `comm` (which must outlive its uses). With one rank it
/// is unset: the serial solver, bit for bit.
ncp::fc::Reduction RankReduction(MPI_Comm comm);

/// Collective: rank 0's *s on every rank.
void BroadcastText(MPI_Comm comm, std::string* s);

/// Collective: throws rank 0's message (std::invalid_argument) on every rank (empty:
/// nothing to throw), so that a failure of rank 0's part leaves no rank waiting in a
/// collective call.
void ThrowFromRankZero(MPI_Comm comm, std::string message);

}  // namespace contact::petsc::internal
