#include "delassus.hpp"

#include <algorithm>

namespace contact::internal {

namespace {

// Greedy coloring of the contact nodes such that two nodes of one color are more than two
// edges of M's graph apart (no common neighbor), from one free dof per node.
std::vector<int> ColorContactNodes(const DynamicModel& model, int* num_colors) {
  const auto& M = model.M;
  std::vector<int> node_of_dof(static_cast<size_t>(M.rows()), -1),
      color(model.contact_nodes.size(), -1);
  std::vector<int> first_dof(model.contact_nodes.size(), -1);
  for (size_t c = 0; c < model.contact_nodes.size(); ++c)
    for (int a = 0; a < model.dim; ++a) {
      const int dof = model.contact_nodes[c].dofs[a];
      if (dof < 0) continue;
      node_of_dof[static_cast<size_t>(dof)] = static_cast<int>(c);
      if (first_dof[c] < 0) first_dof[c] = dof;
    }
  std::vector<int> used_by;  // used_by[k] == c: color k taken by a node near c
  *num_colors = 0;
  for (size_t c = 0; c < color.size(); ++c) {
    if (first_dof[c] < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator i(M, first_dof[c]); i; ++i)
      for (Eigen::SparseMatrix<double>::InnerIterator j(M, i.row()); j; ++j) {
        const int other = node_of_dof[static_cast<size_t>(j.row())];
        if (other >= 0 && color[static_cast<size_t>(other)] >= 0)
          used_by[static_cast<size_t>(color[static_cast<size_t>(other)])] =
              static_cast<int>(c);
      }
    int k = 0;
    while (k < *num_colors && used_by[static_cast<size_t>(k)] == static_cast<int>(c)) ++k;
    if (k == *num_colors) used_by.push_back(-1), ++*num_colors;
    color[c] = k;
  }
  return color;
}

}  // namespace

void DelassusOperator::ProbeDiagonal(const DynamicModel& model) {
  int num_colors = 0;
  const std::vector<int> color = ColorContactNodes(model, &num_colors);
  diagonal_.setZero(H_.rows());
  Eigen::VectorXd probe(H_.rows()), product;
  for (int k = 0; k < num_colors; ++k)
    for (int a = 0; a < model.dim; ++a) {
      probe.setZero();
      bool any = false;
      for (size_t c = 0; c < condensed_.size(); ++c)
        if (color[c] == k && condensed_[c].dofs[a] >= 0)
          probe(condensed_[c].dofs[a]) = 1.0, any = true;
      if (!any) continue;
      Apply(probe, &product);
      for (Eigen::Index i = 0; i < probe.size(); ++i)
        if (probe(i) != 0.0) diagonal_(i) = product(i);
      ++probes_;
    }
  diagonal_ = diagonal_.cwiseAbs();
}

DelassusOperator::DelassusOperator(const DynamicModel& model, MassInverse* mass,
                                   double m_max, bool normal_only, bool matrix_free)
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
  if (matrix_free) {
    ProbeDiagonal(model);
    return;
  }
  // W = H (S^-1 H'), in blocks of columns of H' (at most ~256 MB of right-hand sides).
  const Eigen::SparseMatrix<double> Ht = H_.transpose();
  W_.resize(rows, rows);
  Eigen::MatrixXd block, solved;
  const int width = static_cast<int>(
      std::clamp<Eigen::Index>((1 << 25) / std::max<Eigen::Index>(n, 1), 1, 256));
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
