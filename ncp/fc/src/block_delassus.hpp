// W in block-compressed-row form (one d x d block per nonzero contact pair, the diagonal
// blocks always present) and the Newton matrix J = A + B W on that fixed block pattern.
// The pattern is built once (constructor); new values of W on the same pattern (a scaled
// W, SetScaledValues) and every later Jacobian are written in place.
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
  /// The blocks of row a: k in [RowBegin(a), RowEnd(a)), W_ab = BlockAt(k), b =
  /// Column(k).
  int RowBegin(int a) const { return row_ptr_[a]; }
  int RowEnd(int a) const { return row_ptr_[a + 1]; }
  int Column(int k) const { return block_col_[k]; }
  const Block& BlockAt(int k) const { return blocks_[k]; }
  /// sum_b W_ab r_b over the blocks of row a (d entries, padded to 3 with zeros).
  Eigen::Vector3d RowTimes(int a, const Vector& r) const;
  /// *W = scale W0 entry by entry and the blocks likewise, for W0 the W given to the
  /// constructor (*W has its pattern). False (nothing changed) when an entry is not
  /// finite.
  bool SetScaledValues(double scale, const SparseMatrix& W0, SparseMatrix* W);
  /// J = A + B W with A, B block diagonal (one Block per contact); every entry of every
  /// block is stored, zeros included, so J's sparsity pattern never changes: the first
  /// call builds it, later calls (with the same J) write the values in place.
  void AssembleJacobian(const std::vector<Block>& A, const std::vector<Block>& B,
                        SparseMatrix* J);

 private:
  /// jacobian_slot_: the position in J's value array of entry (i, j) of block k.
  void BuildJacobianPattern(SparseMatrix* J);

  int d_, num_contacts_;
  std::vector<int> row_ptr_, block_col_, diagonal_;
  std::vector<Block> blocks_;
  std::vector<Block> blocks0_;      // the blocks of the W given to the constructor
  double scale_ = 1.0;              // blocks_ = scale_ blocks0_
  std::vector<int> jacobian_slot_;  // d^2 per block, (i, j) column-major
  const double* jacobian_values_ = nullptr;  // J's value array when the slots were set
};

}  // namespace ncp::fc::internal
