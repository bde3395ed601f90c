#pragma once

#include <algorithm>
#include <vector>

#include "ncp/types.hpp"

namespace ncp::internal {

/// The sparsity pattern (outer and inner indices) of a compressed column-major matrix,
/// kept to tell whether a later matrix has the same one (then a structure built for it is
/// reused).
class SparsePattern {
 public:
  /// Remembers S's pattern (S compressed).
  void Store(const SparseMatrix& S) {
    outer_.assign(S.outerIndexPtr(), S.outerIndexPtr() + S.cols() + 1);
    inner_.assign(S.innerIndexPtr(), S.innerIndexPtr() + S.nonZeros());
  }
  /// True when compressed S has exactly the stored pattern (no allocation).
  bool Matches(const SparseMatrix& S) const {
    const auto cols = static_cast<size_t>(S.cols());
    const auto nnz = static_cast<size_t>(S.nonZeros());
    return S.isCompressed() && outer_.size() == cols + 1 && inner_.size() == nnz &&
           std::equal(S.outerIndexPtr(), S.outerIndexPtr() + cols + 1, outer_.begin()) &&
           std::equal(S.innerIndexPtr(), S.innerIndexPtr() + nnz, inner_.begin());
  }

 private:
  std::vector<int> outer_, inner_;
};

}  // namespace ncp::internal
