/// \file random_lcp.hpp
/// Random sparse LCPs with a P-matrix and a planted solution.
#pragma once

#include <cstdint>

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

struct RandomLcpOptions {
  /// Off-diagonal nonzeros per row of M (distinct random columns), clipped to n - 1.
  int offdiagonal_per_row = 4;
  /// M_ii = sum_j |M_ij| + margin * (1 + U(0,1)): strict row diagonal dominance.
  double diagonal_margin = 1.0;
  /// Fraction of indices with x*_i = w*_i = 0 (degenerate pairs).
  double degenerate_fraction = 0.0;
  /// Fraction of the remaining indices with x*_i > 0 (the others have w*_i > 0).
  double active_fraction = 0.5;
  std::uint64_t seed = 20240607;
};

/// LCP  x >= 0, w = M x + q >= 0, x'w = 0  with M sparse, strictly row diagonally
/// dominant with positive diagonal, hence a P-matrix (every principal submatrix is again
/// strictly diagonally dominant with positive diagonal, so its determinant is positive;
/// Cottle, Pang and Stone 1992, sec. 3.3), so the solution is unique (CPS Thm. 3.3.7).
/// A complementary pair (x*, w*) is drawn first and q = w* - M x*, so x* is the solution.
/// Deterministic for a given seed on every platform (SplitMix64, no <random>
/// distributions). Starts "zero" and "ones".
TestProblem RandomPLcp(int n, const RandomLcpOptions& options = RandomLcpOptions());

}  // namespace ncp::collection
