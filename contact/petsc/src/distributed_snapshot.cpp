// The snapshot fields of one process on the ranks' pieces (distributed_snapshot.hpp).
#include "distributed_snapshot.hpp"

#include <limits>

#include "petsc_check.hpp"

namespace contact::petsc::internal {
namespace {

// Every dof of the piece's vertices from the global Vec v (the ghosts by
// DMGlobalToLocal); 0 at the Dirichlet components, as the snapshots of one process.
Vector PieceDofs(const DistributedBody& body, Vec v) {
  const int dim = body.dim(), n = body.NumLocalVertices();
  Vector out = Vector::Zero(static_cast<Eigen::Index>(dim) * n);
  Vec local = nullptr;
  CONTACT_PETSC_CHECK(DMGetLocalVector(body.dm(), &local));
  CONTACT_PETSC_CHECK(VecZeroEntries(local));
  CONTACT_PETSC_CHECK(DMGlobalToLocalBegin(body.dm(), v, INSERT_VALUES, local));
  CONTACT_PETSC_CHECK(DMGlobalToLocalEnd(body.dm(), v, INSERT_VALUES, local));
  const PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(local, &x));
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < dim; ++a)
      if (body.Data(i)[a] >= 0) out(dim * i + a) = x[body.LocalOffset(i, a)];
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(local, &x));
  CONTACT_PETSC_CHECK(DMRestoreLocalVector(body.dm(), &local));
  return out;
}

// Every dof of the piece's vertices: u^0 of the node data (value), or the uniform
// initial velocity v^0 [m/s] on the free components (RunOptions' v0).
Vector PieceStart(const DistributedBody& body, const Eigen::VectorXd* velocity) {
  const int dim = body.dim(), n = body.NumLocalVertices();
  Vector out = Vector::Zero(static_cast<Eigen::Index>(dim) * n);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < dim; ++a)
      if (body.Data(i)[a] >= 0)
        out(dim * i + a) = velocity ? (*velocity)(a) : body.Data(i)[dim + a];
  return out;
}

// The serial contact node index of local vertex i (-1: none), NodeData's layout.
int ContactIndex(const DistributedBody& body, int i) {
  return static_cast<int>(body.Data(i)[4 * body.dim()]);
}

// A piece without cells: the same arrays with no values (the .pvtu names every array).
std::pair<std::vector<PointField>, std::vector<CellField>> EmptyFields(int dim) {
  std::vector<PointField> points;
  for (const char* name : {"displacement", "velocity"})  // (NodalVectorField: dim rows)
    points.push_back({name, Eigen::MatrixXd(dim, 0)});
  for (const char* name : {"normal_force", "friction_force", "slip", "contact_normal"})
    points.push_back({name, Eigen::MatrixXd(3, 0)});
  for (const char* name : {"gap", "contact_state"})
    points.push_back({name, Eigen::MatrixXd(1, 0)});
  return {points,
          {{"stress", Eigen::MatrixXd(9, 0)}, {"von_mises", Eigen::MatrixXd(1, 0)}}};
}

}  // namespace

SnapshotContact ShareSnapshotContact(MPI_Comm comm, int dim, int num_contact_nodes,
                                     const ContactSystem::Result* contact,
                                     double force_scale, double force_accuracy,
                                     double displacement_accuracy) {
  const Eigen::Index n = num_contact_nodes, t = dim - 1;
  // One buffer: lambda_c, tau (t x N_c), gap_c, the two accuracies.
  Eigen::VectorXd buffer((2 + t) * n + 2);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) {
    buffer.head(n) = force_scale * contact->normal_force;
    buffer.segment(n, t * n) =
        force_scale * contact->tangent_force.reshaped(t * n, 1);  // (column-major)
    buffer.segment((1 + t) * n, n) = contact->gap;
    buffer((2 + t) * n) = force_accuracy;
    buffer((2 + t) * n + 1) = displacement_accuracy;
  }
  MPI_Bcast(buffer.data(), static_cast<int>(buffer.size()), MPI_DOUBLE, 0, comm);
  SnapshotContact s;
  s.normal_force = buffer.head(n);
  s.tangent_force = buffer.segment(n, t * n).reshaped(t, n);
  s.gap = buffer.segment((1 + t) * n, n);
  s.force_accuracy = buffer((2 + t) * n);
  s.displacement_accuracy = buffer((2 + t) * n + 1);
  return s;
}

SnapshotContact StartSnapshotContact(const DistributedBody& body, int num_contact_nodes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int dim = body.dim();
  SnapshotContact s;
  s.normal_force = Eigen::VectorXd::Constant(num_contact_nodes, nan);
  s.tangent_force = Eigen::MatrixXd::Constant(dim - 1, num_contact_nodes, nan);
  s.gap = Eigen::VectorXd::Constant(num_contact_nodes, nan);
  for (int i = 0; i < body.NumLocalVertices(); ++i) {
    const int c = ContactIndex(body, i);
    if (c < 0) continue;
    const double* d = body.Data(i);
    double normal_u0 = 0.0;  // n_c . u^0_c
    for (int a = 0; a < dim; ++a)
      if (d[a] >= 0) normal_u0 += d[4 * dim + 1 + a] * d[dim + a];
    s.gap(c) = d[4 * dim + 10] - normal_u0;
  }
  return s;
}

std::pair<std::vector<PointField>, std::vector<CellField>> PieceFields(
    const DistributedBody& body, const ElasticBody* local_body, Vec u, Vec u_previous,
    const Scene& scene, const SnapshotContact& contact) {
  const double dt = scene.dynamics.dt;
  const int dim = body.dim();
  if (!local_body) {  // (the ghost exchange is collective: every rank takes part)
    if (u) PieceDofs(body, u), PieceDofs(body, u_previous);
    return EmptyFields(dim);
  }
  // The piece's contact nodes (node = local vertex) and their parts of the contact
  // quantities, in local vertex order.
  std::vector<ContactNode> nodes;
  std::vector<int> serial;
  for (int i = 0; i < body.NumLocalVertices(); ++i) {
    const int c = ContactIndex(body, i);
    if (c < 0) continue;
    ContactNode node = body.ContactFrame(i);
    node.node = i;
    nodes.push_back(node);
    serial.push_back(c);
  }
  ContactSnapshot s;
  s.displacement = u ? PieceDofs(body, u) : PieceStart(body, nullptr);
  // (the start: u^0 - dt v^0, so that the velocity is v^0, as InitialContactSnapshot)
  s.previous_displacement =
      u ? PieceDofs(body, u_previous)
        : Vector(s.displacement - dt * PieceStart(body, &scene.initial_velocity));
  s.dt = dt;
  s.contact_nodes = &nodes;
  const Eigen::Index m = static_cast<Eigen::Index>(nodes.size());
  s.normal_force.resize(m);
  s.tangent_force.resize(dim - 1, m);
  s.gap.resize(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const int c = serial[static_cast<size_t>(k)];
    s.normal_force(k) = contact.normal_force(c);
    s.tangent_force.col(k) = contact.tangent_force.col(c);
    s.gap(k) = contact.gap(c);
  }
  s.force_accuracy = contact.force_accuracy;
  s.displacement_accuracy = contact.displacement_accuracy;
  // Ranks run small strain (finite strain is refused there): the linear stress, as one
  // process writes it wherever small strain is valid (SceneOutput).
  s.finite_strain = false;
  return ContactSnapshotFields(*local_body, s);
}

}  // namespace contact::petsc::internal
