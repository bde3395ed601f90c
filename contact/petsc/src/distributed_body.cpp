#include "distributed_body.hpp"

#include <petscpartitioner.h>
#include <petscsf.h>

#include <chrono>
#include <stdexcept>
#include <string>

#include "contact/elastic_body.hpp"
#include "petsc_check.hpp"

namespace contact::petsc::internal {
namespace {

int Rank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

}  // namespace

DistributedBody::DistributedBody(MPI_Comm comm, const Scene& scene,
                                 const SceneModel* built,
                                 const std::vector<double>& node_data,
                                 bool assemble_mass_matrix)
    : dim_(scene.dim) {
  // The element type and the cell count of rank 0's mesh, known everywhere.
  int header[2] = {0, 0};
  if (Rank(comm) == 0) {
    header[0] = static_cast<int>(built->body->mesh().element_type);
    header[1] = built->body->mesh().NumElements();
  }
  MPI_Bcast(header, 2, MPI_INT, 0, comm);
  // DMPlex distributes the corners only (cells as cones of vertices): every rank refuses.
  const auto type = static_cast<ElementType>(header[0]);
  if (ElementOrder(type) != 1)
    throw std::invalid_argument(
        std::string("contact::petsc: quadratic elements (") + ToString(type) +
        ") are not supported by the distributed solver; use linear elements (tri3, "
        "quad4, tet4, hex8) or run the serial contact-sim");
  auto start = std::chrono::steady_clock::now();
  auto lap = [&start] {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - start).count();
    start = now;
    return seconds;
  };
  CreateAndDistribute(comm, built);
  ReceiveNodeData(node_data, header[1]);
  BuildLocalMesh(static_cast<ElementType>(header[0]));
  distribute_seconds_ = lap();
  CreateSection();
  section_seconds_ = lap();
  Assemble(scene, assemble_mass_matrix);
  assemble_seconds_ = lap();
}

DistributedBody::~DistributedBody() {
  MatDestroy(&K_);
  MatDestroy(&M_);
  VecDestroy(&m_);
  PetscSFDestroy(&migration_);
  DMDestroy(&dm_);
}

// Rank 0 hands its cells and vertex coordinates to DMPlex (not interpolated: cells and
// vertices only, the cones in the mesh's gmsh/VTK node order); DMPlexDistribute moves
// each cell with its vertices to the rank the partitioner gives it (overlap 0: a vertex
// on a partition boundary is on every rank that has one of its cells, owned by one).
void DistributedBody::CreateAndDistribute(MPI_Comm comm, const SceneModel* built) {
  std::vector<PetscInt> cells;
  std::vector<PetscReal> coordinates;
  PetscInt num_cells = 0, num_vertices = 0, corners = 0;
  if (Rank(comm) == 0) {
    const Mesh& mesh = built->body->mesh();
    num_cells = mesh.NumElements();
    num_vertices = mesh.NumNodes();
    corners = static_cast<PetscInt>(mesh.elements.rows());
    cells.assign(mesh.elements.data(), mesh.elements.data() + mesh.elements.size());
    coordinates.assign(mesh.nodes.data(), mesh.nodes.data() + mesh.nodes.size());
  }
  MPI_Bcast(&corners, 1, MPIU_INT, 0, comm);
  CONTACT_PETSC_CHECK(DMPlexCreateFromCellListPetsc(comm, dim_, num_cells, num_vertices,
                                                    corners, PETSC_FALSE, cells.data(),
                                                    dim_, coordinates.data(), &dm_));
  // PT-Scotch by default (Debian's PETSc has it); -petscpartitioner_type picks another.
  PetscPartitioner partitioner = nullptr;
  CONTACT_PETSC_CHECK(DMPlexGetPartitioner(dm_, &partitioner));
  CONTACT_PETSC_CHECK(PetscPartitionerSetType(partitioner, PETSCPARTITIONERPTSCOTCH));
  CONTACT_PETSC_CHECK(PetscPartitionerSetFromOptions(partitioner));
  PetscPartitionerType type = nullptr;
  CONTACT_PETSC_CHECK(PetscPartitionerGetType(partitioner, &type));
  partitioner_ = type ? type : "";
  DM distributed = nullptr;
  CONTACT_PETSC_CHECK(DMPlexDistribute(dm_, 0, &migration_, &distributed));
  if (distributed) {  // (null on one rank: nothing to distribute)
    DMDestroy(&dm_);
    dm_ = distributed;
  }
  CONTACT_PETSC_CHECK(DMPlexGetHeightStratum(dm_, 0, &c_start_, &c_end_));
  CONTACT_PETSC_CHECK(DMPlexGetDepthStratum(dm_, 0, &v_start_, &v_end_));
}

// Rank 0's points are cells 0 .. C-1, then vertices C .. C+N-1
// (DMPlexCreateFromCellList); the migration SF's roots are those points, its leaves the
// points here.
void DistributedBody::ReceiveNodeData(const std::vector<double>& node_data,
                                      int num_original_cells) {
  const int width = NodeData::Width(dim_);
  PetscInt p_start = 0, p_end = 0;
  CONTACT_PETSC_CHECK(DMPlexGetChart(dm_, &p_start, &p_end));
  std::vector<double> leaves(static_cast<size_t>(width) * static_cast<size_t>(p_end),
                             0.0);
  if (!migration_) {
    std::copy(node_data.begin(), node_data.end(),
              leaves.begin() + static_cast<long>(width) * num_original_cells);
  } else {
    PetscInt num_roots = 0;
    CONTACT_PETSC_CHECK(
        PetscSFGetGraph(migration_, &num_roots, nullptr, nullptr, nullptr));
    std::vector<double> roots(static_cast<size_t>(width) * static_cast<size_t>(num_roots),
                              0.0);
    if (num_roots > 0)
      std::copy(node_data.begin(), node_data.end(),
                roots.begin() + static_cast<long>(width) * num_original_cells);
    MPI_Datatype unit;
    MPI_Type_contiguous(width, MPI_DOUBLE, &unit);
    MPI_Type_commit(&unit);
    CONTACT_PETSC_CHECK(
        PetscSFBcastBegin(migration_, unit, roots.data(), leaves.data(), MPI_REPLACE));
    CONTACT_PETSC_CHECK(
        PetscSFBcastEnd(migration_, unit, roots.data(), leaves.data(), MPI_REPLACE));
    MPI_Type_free(&unit);
  }
  data_.assign(leaves.begin() + static_cast<long>(width) * v_start_,
               leaves.begin() + static_cast<long>(width) * v_end_);
}

// This rank's cells over its vertices (local vertex i = point vStart + i), as a
// contact::Mesh for the element kernels.
void DistributedBody::BuildLocalMesh(ElementType type) {
  Mesh& mesh = local_mesh_;
  mesh.dim = dim_;
  mesh.element_type = type;
  const auto num_vertices = static_cast<Eigen::Index>(v_end_ - v_start_);
  mesh.nodes.resize(dim_, num_vertices);
  Vec coordinates = nullptr;
  PetscSection coordinate_section = nullptr;
  CONTACT_PETSC_CHECK(DMGetCoordinatesLocal(dm_, &coordinates));
  CONTACT_PETSC_CHECK(DMGetCoordinateSection(dm_, &coordinate_section));
  const PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(coordinates, &x));
  for (PetscInt v = v_start_; v < v_end_; ++v) {
    PetscInt offset = 0;
    CONTACT_PETSC_CHECK(PetscSectionGetOffset(coordinate_section, v, &offset));
    for (int a = 0; a < dim_; ++a)
      mesh.nodes(a, v - v_start_) = PetscRealPart(x[offset + a]);
  }
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(coordinates, &x));
  const int corners = NodesPerElement(type);
  mesh.elements.resize(corners, static_cast<Eigen::Index>(c_end_ - c_start_));
  for (PetscInt c = c_start_; c < c_end_; ++c) {
    PetscInt size = 0;
    const PetscInt* cone = nullptr;
    CONTACT_PETSC_CHECK(DMPlexGetConeSize(dm_, c, &size));
    CONTACT_PETSC_CHECK(DMPlexGetCone(dm_, c, &cone));
    if (size != corners)
      throw std::logic_error("contact::petsc: a distributed cell has " +
                             std::to_string(size) + " vertices, expected " +
                             std::to_string(corners));
    for (int a = 0; a < corners; ++a)
      mesh.elements(a, c - c_start_) = static_cast<int>(cone[a] - v_start_);
  }
}

// dim dofs per vertex; the constrained components (free index -1 in the node data) are
// constraints of the section, so the global vectors and K hold the free dofs only.
void DistributedBody::CreateSection() {
  const int width = NodeData::Width(dim_);
  PetscInt p_start = 0, p_end = 0;
  CONTACT_PETSC_CHECK(DMPlexGetChart(dm_, &p_start, &p_end));
  PetscSection section = nullptr;
  CONTACT_PETSC_CHECK(
      PetscSectionCreate(PetscObjectComm(reinterpret_cast<PetscObject>(dm_)), &section));
  CONTACT_PETSC_CHECK(PetscSectionSetChart(section, p_start, p_end));
  std::vector<std::vector<PetscInt>> constrained(static_cast<size_t>(v_end_ - v_start_));
  for (PetscInt v = v_start_; v < v_end_; ++v) {
    const double* data = &data_[static_cast<size_t>(width * (v - v_start_))];
    for (int a = 0; a < dim_; ++a)
      if (data[a] < 0) constrained[static_cast<size_t>(v - v_start_)].push_back(a);
    CONTACT_PETSC_CHECK(PetscSectionSetDof(section, v, dim_));
    CONTACT_PETSC_CHECK(PetscSectionSetConstraintDof(
        section, v,
        static_cast<PetscInt>(constrained[static_cast<size_t>(v - v_start_)].size())));
  }
  CONTACT_PETSC_CHECK(PetscSectionSetUp(section));
  for (PetscInt v = v_start_; v < v_end_; ++v)
    if (!constrained[static_cast<size_t>(v - v_start_)].empty())
      CONTACT_PETSC_CHECK(PetscSectionSetConstraintIndices(
          section, v, constrained[static_cast<size_t>(v - v_start_)].data()));
  CONTACT_PETSC_CHECK(DMSetLocalSection(dm_, section));
  CONTACT_PETSC_CHECK(PetscSectionDestroy(&section));

  PetscSection global = nullptr;
  CONTACT_PETSC_CHECK(DMGetGlobalSection(dm_, &global));
  CONTACT_PETSC_CHECK(DMCreateGlobalVector(dm_, &m_));
  PetscInt first = 0, last = 0;
  CONTACT_PETSC_CHECK(VecGetOwnershipRange(m_, &first, &last));
  const auto n = static_cast<size_t>(v_end_ - v_start_);
  owned_.assign(n, 0);
  global_index_.assign(n * static_cast<size_t>(dim_), -1);
  owned_index_.assign(n * static_cast<size_t>(dim_), -1);
  for (PetscInt v = v_start_; v < v_end_; ++v) {
    PetscInt offset = 0;
    CONTACT_PETSC_CHECK(PetscSectionGetOffset(global, v, &offset));
    const bool owned = offset >= 0;  // a ghost's offset is -(owner's offset + 1)
    const PetscInt start = owned ? offset : -(offset + 1);
    const auto i = static_cast<size_t>(v - v_start_);
    owned_[i] = owned ? 1 : 0;
    PetscInt k = 0;  // the free components are numbered in order
    for (int a = 0; a < dim_; ++a) {
      if (data_[static_cast<size_t>(width) * i + static_cast<size_t>(a)] < 0) continue;
      global_index_[static_cast<size_t>(dim_) * i + static_cast<size_t>(a)] = start + k;
      if (owned)
        owned_index_[static_cast<size_t>(dim_) * i + static_cast<size_t>(a)] =
            start + k - first;
      ++k;
    }
  }
}

PetscInt DistributedBody::LocalOffset(int vertex, int a) const {
  PetscSection section = nullptr;
  PetscInt offset = 0;
  CONTACT_PETSC_CHECK(DMGetLocalSection(dm_, &section));
  CONTACT_PETSC_CHECK(PetscSectionGetOffset(section, v_start_ + vertex, &offset));
  return offset + a;
}

// K_FF, the lumped mass and (if asked) the mass matrix M_FF of the scene (consistent, or
// the lumped diagonal): contact::ElasticBody on this
// rank's cells (the project's element kernels and their quadrature), its entries added
// into the global rows and columns of the free dofs; a partition-boundary row is summed
// over the ranks that share the vertex.
void DistributedBody::Assemble(const Scene& scene, bool assemble_mass_matrix) {
  CONTACT_PETSC_CHECK(DMCreateMatrix(dm_, &K_));
  CONTACT_PETSC_CHECK(MatSetOption(K_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  if (assemble_mass_matrix) {
    CONTACT_PETSC_CHECK(DMCreateMatrix(dm_, &M_));
    CONTACT_PETSC_CHECK(MatSetOption(M_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  }
  CONTACT_PETSC_CHECK(VecZeroEntries(m_));
  if (local_mesh_.NumElements() > 0) {
    const ElasticBody body(local_mesh_, scene.material, scene.plane);
    AddRows(body.StiffnessMatrix(), K_);
    if (M_ && scene.mass == MassKind::kConsistent)
      AddRows(body.ConsistentMassMatrix(), M_);
    const Vector lumped = body.LumpedMass();
    for (Eigen::Index j = 0; j < lumped.size(); ++j) {
      const PetscInt row = global_index_[static_cast<size_t>(j)];
      if (row >= 0) CONTACT_PETSC_CHECK(VecSetValue(m_, row, lumped(j), ADD_VALUES));
    }
  }
  CONTACT_PETSC_CHECK(VecAssemblyBegin(m_));
  CONTACT_PETSC_CHECK(VecAssemblyEnd(m_));
  if (M_ && scene.mass == MassKind::kLumped) {  // M = diag(m), as the serial model's
    PetscInt first = 0, last = 0;
    const PetscScalar* m = nullptr;
    CONTACT_PETSC_CHECK(VecGetOwnershipRange(m_, &first, &last));
    CONTACT_PETSC_CHECK(VecGetArrayRead(m_, &m));
    for (PetscInt row = first; row < last; ++row)
      CONTACT_PETSC_CHECK(MatSetValue(M_, row, row, m[row - first], INSERT_VALUES));
    CONTACT_PETSC_CHECK(VecRestoreArrayRead(m_, &m));
  }
  for (Mat A : {K_, M_}) {
    if (!A) continue;
    CONTACT_PETSC_CHECK(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
    CONTACT_PETSC_CHECK(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
    // (Both are symmetric by construction; M is positive definite - MUMPS's Cholesky.)
    CONTACT_PETSC_CHECK(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
  }
  if (M_) CONTACT_PETSC_CHECK(MatSetOption(M_, MAT_SPD, PETSC_TRUE));
}

// A is exactly symmetric (ElasticBody symmetrizes each element matrix): column j of the
// compressed-column A is row j, added as one row (AIJ stores rows) of the free dofs.
void DistributedBody::AddRows(const SparseMatrix& A, Mat target) const {
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    const PetscInt row = global_index_[static_cast<size_t>(j)];
    if (row < 0) continue;
    columns.clear();
    values.clear();
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      const PetscInt column = global_index_[static_cast<size_t>(it.row())];
      if (column < 0) continue;
      columns.push_back(column);
      values.push_back(it.value());
    }
    CONTACT_PETSC_CHECK(MatSetValues(target, 1, &row,
                                     static_cast<PetscInt>(columns.size()),
                                     columns.data(), values.data(), ADD_VALUES));
  }
}

ContactNode DistributedBody::ContactFrame(int vertex) const {
  const double* d = Data(vertex);
  ContactNode node;
  for (int a = 0; a < 3; ++a) {
    node.normal(a) = d[4 * dim_ + 1 + a];
    node.tangent1(a) = d[4 * dim_ + 4 + a];
    node.tangent2(a) = d[4 * dim_ + 7 + a];
  }
  node.gap = d[4 * dim_ + 10];
  return node;
}

void DistributedBody::UnpackStart(PetscScalar* u, PetscScalar* u_previous, PetscScalar* f,
                                  std::vector<char>* contact_dof) const {
  for (int i = 0; i < NumLocalVertices(); ++i) {
    const double* data = Data(i);
    const bool contact_node = Owns(i) && data[4 * dim_] >= 0;
    for (int c = 0; c < dim_; ++c) {
      const PetscInt k = OwnedIndex(i, c);
      if (k < 0) continue;
      u[k] = data[dim_ + c];
      u_previous[k] = data[2 * dim_ + c];
      f[k] = data[3 * dim_ + c];
      (*contact_dof)[static_cast<size_t>(k)] = contact_node ? 1 : 0;
    }
  }
}

}  // namespace contact::petsc::internal
