#include "block_delassus.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace ncp::fc::internal {

BlockDelassus::BlockDelassus(const FrictionProblem& problem)
    : d_(problem.dimension), num_contacts_(problem.num_contacts) {
  std::vector<std::map<int, Block>> rows(num_contacts_);
  for (int a = 0; a < num_contacts_; ++a) rows[a][a] = Block::Zero();
  for (int k = 0; k < problem.W.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(problem.W, k); it; ++it) {
      auto found =
          rows[it.row() / d_].try_emplace(static_cast<int>(it.col()) / d_, Block::Zero());
      found.first->second(it.row() % d_, it.col() % d_) = it.value();
    }
  row_ptr_.assign(1, 0);
  diagonal_.resize(num_contacts_);
  for (int a = 0; a < num_contacts_; ++a) {
    for (const auto& [b, block] : rows[a]) {
      if (b == a) diagonal_[a] = static_cast<int>(blocks_.size());
      block_col_.push_back(b);
      blocks_.push_back(block);
    }
    row_ptr_.push_back(static_cast<int>(blocks_.size()));
  }
  blocks0_ = blocks_;  // W0's blocks, for SetScaledValues
}

bool BlockDelassus::SetScaledValues(double scale, const SparseMatrix& W0,
                                    SparseMatrix* W) {
  // Contiguous passes (vectorized): W's values, then the blocks from their unscaled copy.
  Eigen::Map<Vector> values(W->valuePtr(), W0.nonZeros());
  values = scale * Eigen::Map<const Vector>(W0.valuePtr(), W0.nonZeros());
  if (!values.allFinite()) {
    values =
        Eigen::Map<const Vector>(W0.valuePtr(), W0.nonZeros()) * scale_;  // (as before)
    return false;
  }
  const Eigen::Index n = 9 * static_cast<Eigen::Index>(blocks_.size());
  if (n > 0)
    Eigen::Map<Vector>(blocks_.front().data(), n) =
        scale * Eigen::Map<const Vector>(blocks0_.front().data(), n);
  scale_ = scale;
  return true;
}

Eigen::Vector3d BlockDelassus::RowTimes(int a, const Vector& r) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k) {
    Eigen::Vector3d rb = Eigen::Vector3d::Zero();
    rb.head(d_) = r.segment(d_ * block_col_[k], d_);
    sum += blocks_[k] * rb;
  }
  return sum;
}

void BlockDelassus::BuildJacobianPattern(SparseMatrix* J) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(blocks_.size() * d_ * d_);
  for (int a = 0; a < num_contacts_; ++a)
    for (int k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k)
      for (int j = 0; j < d_; ++j)
        for (int i = 0; i < d_; ++i)
          entries.emplace_back(d_ * a + i, d_ * block_col_[k] + j, 0.0);
  const int n = d_ * num_contacts_;
  J->resize(n, n);
  J->setFromTriplets(entries.begin(), entries.end());
  J->makeCompressed();
  jacobian_slot_.resize(entries.size());
  for (int a = 0; a < num_contacts_; ++a)
    for (int k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k)
      for (int j = 0; j < d_; ++j) {
        const int column = d_ * block_col_[k] + j;
        const int* begin = J->innerIndexPtr() + J->outerIndexPtr()[column];
        const int* end = J->innerIndexPtr() + J->outerIndexPtr()[column + 1];
        for (int i = 0; i < d_; ++i)
          jacobian_slot_[static_cast<size_t>((k * d_ + j) * d_ + i)] = static_cast<int>(
              std::lower_bound(begin, end, d_ * a + i) - J->innerIndexPtr());
      }
  jacobian_values_ = J->valuePtr();
}

void BlockDelassus::AssembleJacobian(const std::vector<Block>& A,
                                     const std::vector<Block>& B, SparseMatrix* J) {
  if (J->valuePtr() == nullptr || J->valuePtr() != jacobian_values_ || !J->isCompressed())
    BuildJacobianPattern(J);
  double* values = J->valuePtr();
  for (int a = 0; a < num_contacts_; ++a)
    for (int k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k) {
      const int b = block_col_[k];
      Block Jab = B[a] * blocks_[k];
      if (b == a) Jab += A[a];
      const int* slot = jacobian_slot_.data() + static_cast<size_t>(k * d_ * d_);
      for (int j = 0; j < d_; ++j)
        for (int i = 0; i < d_; ++i) values[slot[j * d_ + i]] = Jab(i, j);
    }
}

}  // namespace ncp::fc::internal
