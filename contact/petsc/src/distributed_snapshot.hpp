// The fields of one process's snapshot (ContactSnapshotFields) on each rank's piece:
// displacement, velocity, gap, normal and friction force, slip, contact state, contact
// normal at the piece's vertices, stress and von Mises stress in its cells.
#pragma once

#include <petscvec.h>

#include <utility>
#include <vector>

#include "contact/contact_system.hpp"
#include "contact/elastic_body.hpp"
#include "contact/scene.hpp"
#include "contact/vtk_writer.hpp"
#include "distributed_body.hpp"

namespace contact::petsc::internal {

/// The contact quantities of a snapshot, every contact node in the serial node order.
struct SnapshotContact {
  Eigen::VectorXd normal_force;        ///< lambda_c [N] (NaN: not known, the start)
  Eigen::MatrixXd tangent_force;       ///< (dim - 1) x N_c along t1 (, t2) [N]
  Eigen::VectorXd gap;                 ///< gap_c = s_c - n_c . u_c [m]
  double force_accuracy = 0.0;         ///< the step's [N]
  double displacement_accuracy = 0.0;  ///< the step's [m]
};

/// Collective: rank 0's contact result of the step (system units; times force_scale
/// [N]) and the step's accuracies, broadcast to every rank. contact and the accuracies
/// are read on rank 0 only.
SnapshotContact ShareSnapshotContact(MPI_Comm comm, int dim, int num_contact_nodes,
                                     const ContactSystem::Result* contact,
                                     double force_scale, double force_accuracy,
                                     double displacement_accuracy);

/// The start's contact quantities on every rank, as InitialContactSnapshot: the forces
/// not known (NaN), the gaps s_c - n_c . u^0_c (of the contact nodes this rank has;
/// NaN for the others, which its piece does not show).
SnapshotContact StartSnapshotContact(const DistributedBody& body, int num_contact_nodes);

/// Collective (ghost exchange): the fields of this rank's piece, for the global Vecs u
/// (u^{k+1}) and u_previous (u^k) [m], or with u == nullptr the start: u^0 of the node
/// data and scene.initial_velocity [m/s] on the free components;
/// local_body: ElasticBody on body.local_mesh(), null for a piece without cells (then the
/// same arrays, empty). The contact nodes' frames are the node data's. Small strain (the
/// ranks' kinematics).
std::pair<std::vector<PointField>, std::vector<CellField>> PieceFields(
    const DistributedBody& body, const ElasticBody* local_body, Vec u, Vec u_previous,
    const Scene& scene, const SnapshotContact& contact);

}  // namespace contact::petsc::internal
