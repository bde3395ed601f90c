// W in block-compressed-row form (one d x d block per nonzero contact pair, the diagonal
// blocks always present) and the Newton matrix J = A + B W on that fixed block pattern.
#pragma once

#include <vector>

#include "local_laws.hpp"
#include "ncp/fc/problem.hpp"

namespace ncp::fc::internal {

class BlockDelassus {
 public:
  explicit BlockDelassus(const FrictionProblem& problem);

  /// Diagonal block of contact a.
  const Block& Diagonal(int a) const { return blocks_[diagonal_[a]]; }
  /// sum_b W_ab r_b over the blocks of row a (d entries, padded to 3 with zeros).
  Eigen::Vector3d RowTimes(int a, const Vector& r) const;
  /// J = A + B W with A, B block diagonal (one Block per contact); every entry of every
  /// block is stored, zeros included, so J's sparsity pattern never changes.
  void AssembleJacobian(const std::vector<Block>& A, const std::vector<Block>& B,
                        SparseMatrix* J) const;

 private:
  int d_, num_contacts_;
  std::vector<int> row_ptr_, block_col_, diagonal_;
  std::vector<Block> blocks_;
};

}  // namespace ncp::fc::internal
