/// \file distributed_scene.hpp
/// A contact scene on the MPI ranks of a communicator through PETSc
/// (docs/petsc-contact.md, "Contact scenes on MPI ranks"): the mesh of the scene handed
/// to DMPlex and partitioned by DMPlexDistribute, K assembled per rank into a MATMPIAIJ
/// with the element kernels of contact/ (contact::ElasticBody on each rank's cells), the
/// lumped mass a Vec, and the explicit central-difference step (StepMethod::kExplicit) on
/// each rank's own nodes, or the condensed step (StepMethod::kCondensed, implicit Coulomb
/// friction) with the consistent or lumped mass as a parallel matrix, its solves by
/// PETSc's KSP (MUMPS's Cholesky by default) and the contact set gathered onto rank 0.
/// PetscInitialize is the caller's.
#pragma once

#include <mpi.h>

#include <string>

#include "contact/scene.hpp"

namespace contact::petsc {

/// Empty if RunSceneDistributed can run `scene` as far as the scene file tells;
/// otherwise one sentence naming the scene's step (or setting) and what the distributed
/// run supports. (With solver.step = "auto" the choice needs the mesh:
/// RunSceneDistributed runs the sparse step above internal::kMaxGatheredContactUnknowns
/// contact unknowns, the condensed step up to it; docs/petsc-contact.md.)
std::string WhyNotDistributed(const Scene& scene);

/// Runs the scene on the ranks of `comm` (collective; every rank passes the same scene).
/// Throws std::invalid_argument with WhyNotDistributed's sentence for a scene it cannot
/// run. On rank 0 the result is complete: summary (status, records, u = the final
/// displacement on the free dofs in the serial numbering) and files_written; on the other
/// ranks the summary has the status, message and step count only. With any step
/// (explicit, condensed, sparse) each step's record has the accuracy and energy measures
/// of one process (the same definitions and scales, summed over the ranks in rank order),
/// and the energy blow-up guard, accuracy-not-reached and scene.dynamics.stop_requested
/// (read on every rank, agreed at the step's end) end the run with the status of one
/// process. Files (rank 0 unless said): steps.csv, contact_stress.csv and
/// displacement.csv (at output.stress_times and the end), node_history.csv
/// (output.marked_point), as from one process, and the snapshots as one .vtu piece per
/// rank (each rank writes its own), one .pvtu per snapshot and solution.pvd.
SceneResult RunSceneDistributed(const Scene& scene, MPI_Comm comm, bool progress);

}  // namespace contact::petsc
