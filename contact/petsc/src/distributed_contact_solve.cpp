// The contact problem of the condensed and sparse steps on ranks (CondensedGatheredStep,
// distributed_implicit_step.hpp): the contact unknowns gathered on rank 0 with W formed
// (condensed) or applied by distributed solves (sparse, stage A), or distributed over the
// owners of the contact nodes (sparse, kDistributed); the gaps and rank 0's or every
// rank's CoulombStep solve.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "distributed_implicit_step.hpp"
#include "petsc_check.hpp"
#include "rank_reduction.hpp"

namespace contact::petsc::internal {

// The contact unknowns in the serial order of H (contact node by node, its free
// components in order): rank 0 learns the global index of each from the ranks that own
// the contact nodes, and one VecScatter moves them between the global Vecs and rank 0.
void CondensedGatheredStep::BuildContactScatter(const std::vector<ContactNode>* nodes) {
  // (serial free-dof index, global index) of every owned free component of a contact
  // node.
  std::vector<long long> send;
  for (int i = 0; i < body_.NumLocalVertices(); ++i) {
    if (!body_.Owns(i) || body_.Data(i)[4 * dim_] < 0) continue;
    for (int a = 0; a < dim_; ++a)
      if (body_.GlobalIndex(i, a) >= 0) {
        send.push_back(static_cast<long long>(body_.Data(i)[a]));
        send.push_back(static_cast<long long>(body_.GlobalIndex(i, a)));
      }
  }
  int size = 1;
  MPI_Comm_size(comm_, &size);
  std::vector<int> counts(static_cast<size_t>(size)), offsets(static_cast<size_t>(size));
  const int count = static_cast<int>(send.size());
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
  int total = 0;
  if (rank_ == 0)
    for (size_t r = 0; r < counts.size(); ++r) offsets[r] = total, total += counts[r];
  std::vector<long long> received(static_cast<size_t>(total));
  MPI_Gatherv(send.data(), count, MPI_LONG_LONG, received.data(), counts.data(),
              offsets.data(), MPI_LONG_LONG, 0, comm_);
  std::vector<PetscInt> indices;
  std::string error;
  if (rank_ == 0) {
    long long num_free = 0;
    for (size_t k = 0; k + 1 < received.size(); k += 2)
      num_free = std::max(num_free, received[k] + 1);
    for (const ContactNode& node : *nodes)
      for (int a = 0; a < dim_; ++a) num_free = std::max(num_free, node.dofs[a] + 1LL);
    std::vector<PetscInt> global_of_free(static_cast<size_t>(num_free), -1);
    for (size_t k = 0; k + 1 < received.size(); k += 2)
      global_of_free[static_cast<size_t>(received[k])] =
          static_cast<PetscInt>(received[k + 1]);
    nodes_ = *nodes;
    for (ContactNode& node : nodes_)  // renumbered onto the contact unknowns (as H)
      for (int a = 0; a < dim_; ++a) {
        if (node.dofs[a] < 0) continue;
        const PetscInt global = global_of_free[static_cast<size_t>(node.dofs[a])];
        if (global < 0)
          error = "contact::petsc: contact node " + std::to_string(node.node) +
                  " has no owner among the ranks";
        node.dofs[a] = static_cast<int>(indices.size());
        indices.push_back(global);
      }
  }
  ThrowFromRankZero(comm_, error);
  num_unknowns_ = static_cast<int>(indices.size());
  MPI_Bcast(&num_unknowns_, 1, MPI_INT, 0, comm_);
  IS is = nullptr;
  CONTACT_PETSC_CHECK(ISCreateGeneral(PETSC_COMM_SELF,
                                      static_cast<PetscInt>(indices.size()),
                                      indices.data(), PETSC_COPY_VALUES, &is));
  CONTACT_PETSC_CHECK(
      VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(indices.size()), &contact_));
  CONTACT_PETSC_CHECK(VecScatterCreate(u_, is, contact_, nullptr, &to_contact_));
  CONTACT_PETSC_CHECK(ISDestroy(&is));
}

// W = H S^-1 H' on rank 0, column by column: e_j scattered to its owner, one distributed
// solve, the column gathered (as the serial DelassusOperator, then symmetrized); rank 0
// sets up the serial step's CoulombStep on it.
void CondensedGatheredStep::FormDelassus() {
  Eigen::MatrixXd W;
  Eigen::VectorXd column;
  if (rank_ == 0) W.resize(num_unknowns_, num_unknowns_);
  for (int j = 0; j < num_unknowns_; ++j) {
    CONTACT_PETSC_CHECK(VecZeroEntries(contact_));
    if (rank_ == 0) CONTACT_PETSC_CHECK(VecSetValue(contact_, j, 1.0, INSERT_VALUES));
    CONTACT_PETSC_CHECK(VecAssemblyBegin(contact_));
    CONTACT_PETSC_CHECK(VecAssemblyEnd(contact_));
    if (!MultiplyW()) throw std::invalid_argument("contact::petsc: " + failure_);
    ReadContact(&column);
    if (rank_ == 0) W.col(j) = column;
  }
  if (rank_ == 0) W = 0.5 * (W + W.transpose());
  SetUpContactSolver(
      [&] {
        return std::make_unique<::contact::internal::CoulombStep>(
            dim_, W, nodes_, scene_.friction_coefficient, FcOptions());
      },
      std::string());
}

void CondensedGatheredStep::SetUpContactSolver(
    const std::function<std::unique_ptr<::contact::internal::CoulombStep>()>& make,
    std::string error) {
  if (rank_ == 0) {
    if (error.empty()) try {
        coulomb_ = make();
      } catch (const std::exception& e) {
        error = e.what();
      }
    x_free_.resize(num_unknowns_);
    u_contact_.resize(num_unknowns_);
    gap0_.resize(static_cast<Eigen::Index>(nodes_.size()));
  }
  ThrowFromRankZero(comm_, error);
}

ncp::fc::Options CondensedGatheredStep::FcOptions() const {
  ncp::fc::Options fc;  // as the serial step: the hybrid, the scene's Newton limits
  fc.max_iterations = scene_.dynamics.ncp.max_iterations;
  fc.log_to_stderr = scene_.dynamics.ncp.log_to_stderr;
  // The contact Newton over the ranks: GMRES's dot products two reductions per iteration
  // (classical Gram-Schmidt twice) instead of k + 1 (modified; the serial step's, kept on
  // one rank, where nothing is reduced).
  int ranks = 1;
  MPI_Comm_size(comm_, &ranks);
  fc.krylov_classical_gram_schmidt = distributed() && ranks > 1;
  return fc;
}

bool CondensedGatheredStep::MultiplyW() {
  ScatterContact(rhs_);
  if (!SolveS(rhs_, y_, 0.0)) return false;
  GatherContact(y_, nullptr);
  return true;
}

// diag(W)_i ~ m_max / M_ii of the contact unknown's dof (W_ii = m_max (M^-1)_ii, and
// 1 / M_ii <= (M^-1)_ii for M symmetric positive definite; equal for a diagonal M),
// gathered onto rank 0; rank 0 sets up the serial sparse step's matrix-free CoulombStep
// whose products with W are DelassusProducts'.
void CondensedGatheredStep::SetUpOperator() {
  CONTACT_PETSC_CHECK(MatGetDiagonal(body_.mass_matrix(), y_));
  Eigen::VectorXd m;  // M_ii [kg] of the contact unknowns
  GatherContact(y_, &m);
  std::string error;
  Eigen::VectorXd diagonal;
  if (rank_ == 0) {
    diagonal.resize(num_unknowns_);
    for (int i = 0; i < num_unknowns_; ++i) {
      diagonal(i) = m(i) > 0.0 ? m_max_ / m(i) : 0.0;
      if (!(m(i) > 0.0) && error.empty())
        error = "contact::petsc: a contact unknown has no mass (M_ii = " +
                std::to_string(m(i)) + " kg): the sparse step needs M_ii > 0";
    }
  }
  SetUpContactSolver(
      [&] {
        return std::make_unique<::contact::internal::CoulombStep>(
            dim_,
            [this](const Eigen::VectorXd& F, Eigen::VectorXd* x) {
              products_->Apply(F, x);
            },
            diagonal, nodes_, scene_.friction_coefficient, FcOptions());
      },
      error);
}

// Every rank: its owned contact nodes in the serial node order (the node data's contact
// node index), their free components numbered on its contact unknowns, and its part of
// the contact Newton: the serial sparse step's CoulombStep over them with W applied by
// MultiplyOwned and every global quantity reduced over the ranks (RankReduction; unset
// on one rank: the serial Newton, bit for bit). diag(W)_i ~ m_max / M_ii as in
// SetUpOperator.
void CondensedGatheredStep::SetUpDistributed() {
  std::vector<std::pair<int, int>> owned;  // (serial contact node index, local vertex)
  for (int i = 0; i < body_.NumLocalVertices(); ++i)
    if (body_.Owns(i) && body_.Data(i)[4 * dim_] >= 0)
      owned.emplace_back(static_cast<int>(body_.Data(i)[4 * dim_]), i);
  std::sort(owned.begin(), owned.end());
  for (const auto& [index, vertex] : owned) {
    ContactNode node = body_.ContactFrame(vertex);
    node.node = index;
    for (int a = 0; a < dim_; ++a) {
      if (body_.OwnedIndex(vertex, a) < 0) continue;
      node.dofs[a] = static_cast<int>(owned_unknowns_.size());
      owned_unknowns_.push_back(body_.OwnedIndex(vertex, a));
    }
    nodes_.push_back(node);
    node_index_.push_back(index);
  }
  const int local = static_cast<int>(owned_unknowns_.size());
  MPI_Allreduce(&local, &num_unknowns_, 1, MPI_INT, MPI_SUM, comm_);
  // M_ii [kg] of the owned contact unknowns; the smallest over the ranks decides for all.
  CONTACT_PETSC_CHECK(MatGetDiagonal(body_.mass_matrix(), y_));
  Eigen::VectorXd m, diagonal(local);
  ReadOwned(y_, &m);
  // bad: over the ranks, how many M_ii are not > 0 (NaN included) and the smallest of
  // them (-inf: only NaNs).
  double bad[2] = {0.0, -std::numeric_limits<double>::infinity()};  // count, -M_ii
  for (int i = 0; i < local; ++i) {
    diagonal(i) = m(i) > 0.0 ? m_max_ / m(i) : 0.0;
    if (!(m(i) > 0.0)) bad[0] += 1.0, bad[1] = std::max(bad[1], -m(i));
  }
  MPI_Allreduce(MPI_IN_PLACE, bad, 2, MPI_DOUBLE, MPI_MAX, comm_);
  if (bad[0] > 0.0)
    throw std::invalid_argument("contact::petsc: a contact unknown has no mass (M_ii = " +
                                (bad[1] > -std::numeric_limits<double>::infinity()
                                     ? std::to_string(-bad[1])
                                     : std::string("nan")) +
                                " kg): the sparse step needs M_ii > 0");
  coulomb_ = std::make_unique<::contact::internal::CoulombStep>(
      dim_, [this](const Eigen::VectorXd& F, Eigen::VectorXd* x) { MultiplyOwned(F, x); },
      diagonal, nodes_, scene_.friction_coefficient, FcOptions(), RankReduction(comm_));
  x_free_.resize(local);
  u_contact_.resize(local);
  gap0_.resize(static_cast<Eigen::Index>(nodes_.size()));
}

void CondensedGatheredStep::ReadOwned(Vec from, Eigen::VectorXd* to) const {
  const PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(from, &x));
  to->resize(static_cast<Eigen::Index>(owned_unknowns_.size()));
  for (size_t i = 0; i < owned_unknowns_.size(); ++i)
    (*to)(static_cast<Eigen::Index>(i)) = x[owned_unknowns_[i]];
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(from, &x));
}

void CondensedGatheredStep::WriteOwned(const Eigen::VectorXd& from, Vec to) {
  CONTACT_PETSC_CHECK(VecZeroEntries(to));
  PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArray(to, &x));
  for (size_t i = 0; i < owned_unknowns_.size(); ++i)
    x[owned_unknowns_[i]] = from(static_cast<Eigen::Index>(i));
  CONTACT_PETSC_CHECK(VecRestoreArray(to, &x));
}

void CondensedGatheredStep::MultiplyOwned(const Eigen::VectorXd& F, Eigen::VectorXd* x) {
  ++owned_products_;
  WriteOwned(F, rhs_);
  if (!SolveS(rhs_, y_, 0.0)) {  // (the KSP's outcome is the same on every rank)
    product_failure_ = failure_;
    x->setConstant(F.size(), std::numeric_limits<double>::quiet_NaN());
    return;
  }
  ReadOwned(y_, x);
}

void CondensedGatheredStep::ScatterContact(Vec to) {
  CONTACT_PETSC_CHECK(VecZeroEntries(to));
  CONTACT_PETSC_CHECK(
      VecScatterBegin(to_contact_, contact_, to, INSERT_VALUES, SCATTER_REVERSE));
  CONTACT_PETSC_CHECK(
      VecScatterEnd(to_contact_, contact_, to, INSERT_VALUES, SCATTER_REVERSE));
}

void CondensedGatheredStep::GatherContact(Vec from, Eigen::VectorXd* to) {
  CONTACT_PETSC_CHECK(
      VecScatterBegin(to_contact_, from, contact_, INSERT_VALUES, SCATTER_FORWARD));
  CONTACT_PETSC_CHECK(
      VecScatterEnd(to_contact_, from, contact_, INSERT_VALUES, SCATTER_FORWARD));
  if (to) ReadContact(to);
}

void CondensedGatheredStep::ReadContact(Eigen::VectorXd* to) const {
  if (rank_ != 0) return;
  const PetscScalar* x = nullptr;
  CONTACT_PETSC_CHECK(VecGetArrayRead(contact_, &x));
  to->resize(num_unknowns_);
  for (int i = 0; i < num_unknowns_; ++i) (*to)(i) = x[i];
  CONTACT_PETSC_CHECK(VecRestoreArrayRead(contact_, &x));
}

// Rank 0: gap0_c = s_c - n_c . u^k_c from the gathered u^k_c; returns the penetration
// of u^k, max(0, max_c n_c . u^k_c - s_c) [m].
double CondensedGatheredStep::SetGaps() {
  double penetration = 0.0;
  for (size_t c = 0; c < nodes_.size(); ++c) {
    const ContactNode& node = nodes_[c];
    double normal_motion = 0.0;
    for (int a = 0; a < 3; ++a)
      if (node.dofs[a] >= 0) normal_motion += node.normal(a) * u_contact_(node.dofs[a]);
    penetration = std::max(penetration, normal_motion - node.gap);
    gap0_(static_cast<Eigen::Index>(c)) = node.gap - normal_motion;
  }
  return penetration;
}

// Rank 0: the serial step's contact problem (coulomb_fc_step.cpp) from the gathered
// -H S^-1 q and the gaps, against the step's scales F [N] and D [m].
bool CondensedGatheredStep::SolveContact(double force, double displacement,
                                         StepRecord* rec) {
  x_free_ = -x_free_;
  ::contact::internal::CoulombStep::Outcome outcome;
  const bool ok = coulomb_->Solve(x_free_, gap0_, force / force_scale_, displacement,
                                  tolerance_, &outcome);
  const ncp::fc::Summary& s = outcome.summary;
  rec->newton_iterations = s.iterations;
  rec->jacobian_evaluations = s.iterations;  // one generalized Jacobian per Newton step
  rec->residual_evaluations = s.iterations + s.backtracks + 1;
  rec->krylov_iterations = std::max(0, s.krylov_iterations);  // -1: dense (no GMRES)
  if (!ok) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer,
                  "natural-map residual %.3e > tolerance %.3e (scaled): ",
                  outcome.natural_map_residual, tolerance_);
    failure_ = buffer + s.message;
    return false;
  }
  force_ = outcome.force;
  contact_result_ = outcome.contact;
  return true;
}

}  // namespace contact::petsc::internal
