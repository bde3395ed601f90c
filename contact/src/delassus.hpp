// The Delassus operator of a step over the contact unknowns, shared by the condensed step
// methods (condensed_step.cpp: eq. 94 on W^-1; coulomb_fc_step.cpp: ncp::fc on W).
//
// With H mapping the free displacements to the contact unknowns x_c = H du, the step
// equation S du + q = H' F (S = M / m_max, F the contact forces conjugate to x_c) gives
//     du = S^-1 (H' F - q),   x_c = W F - H S^-1 q,   W = H S^-1 H'.
// With friction, H selects every free component of every contact node (the condensed
// nodes keep their frames); normal-only (frictionless), one row n_c' per node (the
// condensed node has normal e_x and no tangent): W is dim^2 times smaller. Matrix-free
// (the sparse step, for contact sets too large for a dense W): W is not formed; Apply()
// multiplies by it with one solve with M, Diagonal() approximates its diagonal.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "contact/dynamics_types.hpp"
#include "mass_inverse.hpp"

namespace contact::internal {

class DelassusOperator {
 public:
  /// W formed once from one solve with M^-1 (`mass`, which must outlive this) per row of
  /// H, symmetrized, unless matrix_free. S^-1 = m_max M^-1.
  DelassusOperator(const DynamicModel& model, MassInverse* mass, double m_max,
                   bool normal_only, bool matrix_free = false);

  const Eigen::SparseMatrix<double>& H() const { return H_; }
  /// W (empty when matrix-free).
  const Eigen::MatrixXd& W() const { return W_; }
  /// x = W F = H S^-1 H' F by one solve with M (x may not alias F).
  void Apply(const Eigen::VectorXd& F, Eigen::VectorXd* x) {
    spread_.noalias() = H_.transpose() * F;
    SolveS(spread_, &solved_);
    x->noalias() = H_ * solved_;
  }
  /// Matrix-free: diag(W) estimated by probing (the scaling of the matrix-free solve, not
  /// part of the solution). The contact nodes are colored so that two nodes of a color
  /// share no neighbor in M's graph (greedy; about 25 colors on a structured Hex8 face,
  /// whatever its size), and one product with W per color and component gives W_ii plus
  /// the entries of W between node i and the other nodes of its color, which decay
  /// geometrically with the distance (M^-1 of linear elements: by about 2 - sqrt 3 per
  /// edge); exact for a lumped M (one color).
  const Eigen::VectorXd& ProbedDiagonal() const { return diagonal_; }
  /// Products with W the probing took.
  int probes() const { return probes_; }
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
  void ProbeDiagonal(const DynamicModel& model);

  Eigen::VectorXd diagonal_;
  int probes_ = 0;
  std::vector<ContactNode> condensed_;
  Eigen::VectorXd spread_, solved_;  // buffers of Apply
};

}  // namespace contact::internal
