#include "delassus.hpp"

#include <algorithm>

namespace contact::internal {

DelassusOperator::DelassusOperator(const DynamicModel& model, MassInverse* mass, double m_max,
                                   bool normal_only, bool matrix_free)
    : mass_(mass), m_max_(m_max), condensed_(model.contact_nodes) {
  const int dim = model.dim;
  const Eigen::Index n = model.M.rows();
  // H, and the nodes renumbered onto the contact unknowns.
  std::vector<Eigen::Triplet<double>> h;
  int rows = 0;
  for (ContactNode& node : condensed_) {
    if (normal_only) {
      for (int a = 0; a < dim; ++a)
        if (node.dofs[a] >= 0) h.emplace_back(rows, node.dofs[a], node.normal(a));
      node.dofs[0] = rows++;
      node.dofs[1] = node.dofs[2] = -1;
      node.normal = Eigen::Vector3d::UnitX();
      node.tangent1.setZero();
      node.tangent2.setZero();
      CompleteContactFrame(dim, &node);
      continue;
    }
    for (int a = 0; a < dim; ++a) {
      if (node.dofs[a] < 0) continue;
      h.emplace_back(rows, node.dofs[a], 1.0);
      node.dofs[a] = rows++;
    }
  }
  H_.resize(rows, n);
  H_.setFromTriplets(h.begin(), h.end());
  // diag(H S^-1 H') with S^-1 replaced by m_max / (row sums of M).
  const Eigen::VectorXd row_sums = model.M * Eigen::VectorXd::Ones(n);
  lumped_diagonal_ = H_.cwiseAbs2() * (m_max_ * row_sums.cwiseInverse());
  if (matrix_free) return;
  // W = H (S^-1 H'), in blocks of columns of H' (at most ~256 MB of right-hand sides).
  const Eigen::SparseMatrix<double> Ht = H_.transpose();
  W_.resize(rows, rows);
  Eigen::MatrixXd block, solved;
  const int width = static_cast<int>(std::clamp<Eigen::Index>((1 << 25) / std::max<Eigen::Index>(n, 1), 1, 256));
  for (int first = 0; first < rows; first += width) {
    const int count = std::min(width, rows - first);
    block = Eigen::MatrixXd(Ht.middleCols(first, count));
    mass_->Solve(block, &solved);
    solved *= m_max_;  // S^-1 = m_max M^-1
    W_.middleCols(first, count) = H_ * solved;
  }
  W_ = 0.5 * (W_ + W_.transpose());
}

}  // namespace contact::internal
