/// \file dof_map.hpp
/// Dirichlet conditions by elimination. The dofs split into free (F) and constrained (C)
/// ones; with prescribed values u_C the system K u = f becomes
///     K_FF u_F = f_F - K_FC u_C,     u = Expand(u_F),
/// and likewise for M and for the restriction of any full vector.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact {

/// A prescribed displacement u(x) [m] on the nodes of a boundary group.
struct DirichletCondition {
  /// Boundary group whose nodes are constrained, "fixed" by default.
  std::string group = kFixedGroup;
  /// Constrained components (0 = x, 1 = y, 2 = z); empty means all components.
  std::vector<int> components;
  /// Prescribed displacement u(x) (size dim) at node position x; empty means u = 0.
  std::function<Eigen::VectorXd(const Eigen::VectorXd& x)> displacement;
};

class DofMap {
 public:
  /// All num_dofs dofs free.
  explicit DofMap(int num_dofs = 0);
  /// Constrains the listed dofs (duplicates allowed) to u_full(dof); an empty u_full
  /// means homogeneous conditions. Throws std::invalid_argument for dofs outside [0,
  /// num_dofs) or a u_full of size other than num_dofs.
  DofMap(int num_dofs, const std::vector<int>& constrained_dofs,
         const Vector& u_full = {});

  int NumDofs() const { return static_cast<int>(free_index_.size()); }
  int NumFreeDofs() const { return static_cast<int>(free_dofs_.size()); }
  int NumConstrainedDofs() const { return NumDofs() - NumFreeDofs(); }
  /// Free index of a full dof, -1 if it is constrained.
  int FreeIndex(int dof) const { return free_index_[dof]; }
  bool IsConstrained(int dof) const { return free_index_[dof] < 0; }
  /// Full dof of each free index, increasing.
  const std::vector<int>& FreeDofs() const { return free_dofs_; }
  /// The constrained full dofs, increasing.
  std::vector<int> ConstrainedDofs() const;

  /// Full vector with the prescribed values u_C at constrained dofs and 0 at free ones.
  const Vector& PrescribedValues() const { return prescribed_; }
  /// Replaces the prescribed values by u_full at the constrained dofs (e.g. for a time-
  /// dependent condition); entries at free dofs are ignored.
  void SetPrescribedValues(const Vector& u_full);

  /// A_FF: rows and columns of the free dofs (A square, NumDofs x NumDofs).
  SparseMatrix RestrictMatrix(const SparseMatrix& A) const;
  /// v_F.
  Vector RestrictVector(const Vector& v) const;
  /// f_F - K_FC u_C: the right-hand side of the reduced system K_FF u_F = ... .
  Vector RestrictLoad(const SparseMatrix& K, const Vector& f) const;
  /// The full vector u with u_F = u_free and u_C = the prescribed values.
  Vector Expand(const Vector& u_free) const;
  /// The full vector with u_F = u_free and zeros at the constrained dofs (for velocities,
  /// accelerations or increments under time-independent conditions).
  Vector ExpandHomogeneous(const Vector& u_free) const;
  /// The restriction P (NumFreeDofs x NumDofs) with P v = v_F, so A_FF = P A P^T.
  SparseMatrix RestrictionMatrix() const;

 private:
  void CheckSize(Eigen::Index size, Eigen::Index expected, const char* what) const;
  std::vector<int> free_index_;
  std::vector<int> free_dofs_;
  Vector prescribed_;
};

/// The DofMap of a list of Dirichlet conditions on boundary groups of the mesh
/// (node-major dofs). A node in several groups takes the value of the last condition that
/// constrains the component. Throws std::invalid_argument for a missing group, a
/// component outside [0, dim) or a displacement function returning a vector of size other
/// than dim.
DofMap MakeDofMap(const Mesh& mesh, const std::vector<DirichletCondition>& conditions);

}  // namespace contact
