// The Delassus operator of a step over the contact unknowns, shared by the condensed step
// methods (condensed_step.cpp: eq. 94 on W^-1; coulomb_fc_step.cpp: ncp::fc on W).
//
// With H mapping the free displacements to the contact unknowns x_c = H du, the step
// equation S du + q = H' F (S = M / m_max, F the contact forces conjugate to x_c) gives
//     du = S^-1 (H' F - q),   x_c = W F - H S^-1 q,   W = H S^-1 H'.
// With friction, H selects every free component of every contact node (the condensed nodes
// keep their frames); normal-only (frictionless), one row n_c' per node (the condensed node
// has normal e_x and no tangent): W is dim^2 times smaller.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "contact/dynamics.hpp"
#include "mass_inverse.hpp"

namespace contact::internal {

class DelassusOperator {
 public:
  /// W formed once from one solve with M^-1 (`mass`, which must outlive this) per row of H,
  /// symmetrized. S^-1 = m_max M^-1.
  DelassusOperator(const DynamicModel& model, MassInverse* mass, double m_max, bool normal_only);

  const Eigen::SparseMatrix<double>& H() const { return H_; }
  const Eigen::MatrixXd& W() const { return W_; }
  /// The contact nodes with dofs numbered on the contact unknowns.
  const std::vector<ContactNode>& condensed_nodes() const { return condensed_; }
  /// x = S^-1 b = m_max M^-1 b (no allocation once x is sized).
  void SolveS(const Eigen::VectorXd& b, Eigen::VectorXd* x) {
    mass_->Solve(b, x);
    *x *= m_max_;
  }

 private:
  MassInverse* mass_;
  double m_max_;
  Eigen::SparseMatrix<double> H_;
  Eigen::MatrixXd W_;
  std::vector<ContactNode> condensed_;
};

}  // namespace contact::internal
