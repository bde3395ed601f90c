// The critical step of central differences on the ranks: Lanczos on the pencil (K, M)
// with the distributed K and mass of a DistributedBody - the serial iteration
// (contact/src/critical_time_step.cpp), its vector operations over the owned free dofs.
#pragma once

#include <mpi.h>
#include <petscvec.h>

#include <Eigen/Core>
#include <functional>

#include "contact/dynamics_types.hpp"
#include "distributed_body.hpp"

namespace contact::petsc::internal {

/// x' y over the ranks of comm (x, y: this rank's parts): each rank's partial sum, added
/// in rank order, the same value on every rank and on every run with the same ranks.
double DeterministicDot(MPI_Comm comm, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& y);

/// Collective: x = M^-1 b on global Vecs of the body's DM (M: the body's mass matrix),
/// by the run's own solver of M. Throws std::invalid_argument, on every rank, if the
/// solve failed.
using MassSolve = std::function<void(Vec b, Vec x)>;

/// Collective. dt_crit = 2 / omega_max of the pencil (K, M) of `body` by the serial
/// Lanczos iteration (the same start vector, indexed by the serial free-dof numbering,
/// the same tolerance kCriticalStepTolerance and iteration limit), K x by MatMult and
/// the dot products by DeterministicDot. M is the lumped mass (M^-1 x elementwise) when
/// solve_consistent is empty, else the body's mass matrix (M x by MatMult, M^-1 b by
/// solve_consistent). Differs from the serial estimate by the round-off of K x, of the
/// solves with M and of the sums (the partition-boundary rows add their ranks' parts in
/// another order), far below the estimate's own tolerance.
CriticalTimeStep DistributedCriticalTimeStep(const DistributedBody& body,
                                             const MassSolve& solve_consistent = {});

}  // namespace contact::petsc::internal
