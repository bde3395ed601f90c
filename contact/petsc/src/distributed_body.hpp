// The elastic body on the ranks of a communicator: the scene's mesh (built on rank 0 by
// the project's readers) handed to DMPlex, partitioned by DMPlexDistribute, a
// PetscSection with dim dofs per vertex whose Dirichlet components are constraints
// (eliminated from the global vectors, as contact::DofMap eliminates them), K as a
// parallel AIJ matrix assembled from the element kernels of contact::ElasticBody on each
// rank's cells, the lumped mass a Vec and, when asked, the consistent mass a parallel AIJ
// matrix like K.
#pragma once

#include <petscdmplex.h>
#include <petscmat.h>

#include <string>
#include <vector>

#include "contact/contact_system.hpp"
#include "contact/mesh.hpp"
#include "contact/scene.hpp"

namespace contact::petsc::internal {

/// Per mesh node of the scene, what rank 0 knows and the ranks that get the node need
/// (sent along DMPlexDistribute's migration SF).
struct NodeData {
  static int Width(int dim) { return 4 * dim + 12; }
  // Layout of one node's doubles: free dof index per component (-1 = constrained), u^0,
  // u^{-1}, f_F per component, the contact node index (-1 = none), its normal, tangent1,
  // tangent2 (3 each), its gap s_c [m] and its initial normal force lambda^0 [N].
};

class DistributedBody {
 public:
  /// Collective. `built` is read on rank 0 only (may be null elsewhere); node_data (rank
  /// 0: NodeData::Width(dim) doubles per mesh node) is sent to the ranks that get each
  /// node. assemble_mass_matrix: also assemble the mass matrix (mass_matrix()).
  DistributedBody(MPI_Comm comm, const Scene& scene, const SceneModel* built,
                  const std::vector<double>& node_data,
                  bool assemble_mass_matrix = false);
  ~DistributedBody();
  DistributedBody(const DistributedBody&) = delete;
  DistributedBody& operator=(const DistributedBody&) = delete;

  int dim() const { return dim_; }
  DM dm() const { return dm_; }
  /// K_FF [N/m], MATMPIAIJ over the owned free dofs.
  Mat stiffness() const { return K_; }
  /// The lumped mass [kg] per owned free dof.
  Vec lumped_mass() const { return m_; }
  /// M_FF [kg], the scene's mass matrix (consistent, or diagonal for mass = "lumped") as
  /// MATMPIAIJ with the pattern of K; null unless the constructor was asked for it.
  Mat mass_matrix() const { return M_; }
  /// Global index (in the DM's global Vecs) of component a of a local vertex; -1 if
  /// constrained.
  PetscInt GlobalIndex(int vertex, int a) const {
    return global_index_[static_cast<size_t>(dim_ * vertex + a)];
  }
  const std::string& partitioner() const { return partitioner_; }
  /// Wall time of the set-up phases on this rank [s]: DMPlex creation and distribution
  /// with the node data; section; K and mass assembly.
  double distribute_seconds() const { return distribute_seconds_; }
  double section_seconds() const { return section_seconds_; }
  double assemble_seconds() const { return assemble_seconds_; }
  /// This rank's cells and vertices (vertex i = DMPlex point vStart + i).
  const Mesh& local_mesh() const { return local_mesh_; }
  int NumLocalVertices() const { return local_mesh_.NumNodes(); }
  bool Owns(int vertex) const { return owned_[static_cast<size_t>(vertex)] != 0; }
  /// Index into the owned part of a global Vec of component a of a local vertex; -1 if
  /// the vertex is not owned or the component is constrained.
  PetscInt OwnedIndex(int vertex, int a) const {
    return owned_index_[static_cast<size_t>(dim_ * vertex + a)];
  }
  /// Offset of component a of a local vertex in a local Vec (DMGetLocalVector).
  PetscInt LocalOffset(int vertex, int a) const;
  /// The contact frame of a local vertex from its NodeData: n_c, t1, t2, s_c (node and
  /// dofs left unset).
  ContactNode ContactFrame(int vertex) const;
  /// The vertex's NodeData (Width doubles).
  const double* Data(int vertex) const {
    return &data_[static_cast<size_t>(NodeData::Width(dim_) * vertex)];
  }
  /// The start from the node data rank 0 sent, at this rank's owned entries of the global
  /// Vecs: u^0 [m], u^{-1} [m], f_F [N], and contact_dof 1 at the dofs of owned contact
  /// nodes (0 elsewhere). Each array holds the owned part of a Vec (VecGetArray).
  void UnpackStart(PetscScalar* u, PetscScalar* u_previous, PetscScalar* f,
                   std::vector<char>* contact_dof) const;

 private:
  void CreateAndDistribute(MPI_Comm comm, const SceneModel* built);
  void ReceiveNodeData(const std::vector<double>& node_data, int num_original_cells);
  void BuildLocalMesh(ElementType type);
  void CreateSection();
  void Assemble(const Scene& scene, bool assemble_mass_matrix);
  void AddRows(const SparseMatrix& A, Mat target) const;

  int dim_ = 0;
  DM dm_ = nullptr;
  PetscSF migration_ =
      nullptr;  // original points (rank 0) -> distributed points; null on 1 rank
  Mat K_ = nullptr;
  Mat M_ = nullptr;
  Vec m_ = nullptr;
  std::string partitioner_;
  double distribute_seconds_ = 0, section_seconds_ = 0, assemble_seconds_ = 0;
  PetscInt c_start_ = 0, c_end_ = 0, v_start_ = 0, v_end_ = 0;
  Mesh local_mesh_;
  std::vector<double> data_;  // NodeData per local vertex
  std::vector<char> owned_;   // per local vertex
  std::vector<PetscInt>
      global_index_;  // dim per local vertex: global free dof, -1 constrained
  std::vector<PetscInt> owned_index_;  // dim per local vertex, see OwnedIndex
};

}  // namespace contact::petsc::internal
