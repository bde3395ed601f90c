// Random sparse P-matrix LCPs with a planted solution.
#include "ncp_collection/random_lcp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ncp_collection/affine_function.hpp"

namespace ncp::collection {
namespace {

// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators",
// OOPSLA 2014): a fixed integer recurrence, so the instance depends only on the seed.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform on [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform integer in [0, bound) (bound << 2^64, so the modulo bias is negligible).
  int Below(int bound) {
    return static_cast<int>(Next() % static_cast<std::uint64_t>(bound));
  }

 private:
  std::uint64_t state_;
};

}  // namespace

TestProblem RandomPLcp(int n, const RandomLcpOptions& options) {
  if (n < 1) {
    throw std::invalid_argument("RandomPLcp: n = " + std::to_string(n) + " < 1");
  }
  if (!(options.diagonal_margin > 0.0)) {
    throw std::invalid_argument(
        "RandomPLcp: diagonal_margin = " + std::to_string(options.diagonal_margin) +
        " must be > 0 for strict diagonal dominance");
  }
  if (!(options.degenerate_fraction >= 0.0 && options.degenerate_fraction <= 1.0) ||
      !(options.active_fraction >= 0.0 && options.active_fraction <= 1.0)) {
    throw std::invalid_argument("RandomPLcp: fractions must lie in [0, 1]");
  }
  SplitMix64 rng(options.seed);
  const int k = std::max(0, std::min(options.offdiagonal_per_row, n - 1));

  // Row i: k distinct off-diagonal columns with values U(-1, 1), then
  // M_ii = sum_j |M_ij| + margin (1 + U(0,1)) > sum_j |M_ij|.
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<size_t>(n) * (k + 1));
  std::vector<int> columns;
  for (int i = 0; i < n; ++i) {
    columns.clear();
    while (static_cast<int>(columns.size()) < k) {
      const int j = rng.Below(n);
      if (j != i && std::find(columns.begin(), columns.end(), j) == columns.end()) {
        columns.push_back(j);
      }
    }
    double offdiagonal_sum = 0.0;
    for (int j : columns) {
      const double value = 2.0 * rng.Uniform() - 1.0;
      offdiagonal_sum += std::abs(value);
      triplets.emplace_back(i, j, value);
    }
    triplets.emplace_back(
        i, i, offdiagonal_sum + options.diagonal_margin * (1.0 + rng.Uniform()));
  }
  SparseMatrix M(n, n);
  M.setFromTriplets(triplets.begin(), triplets.end());

  // Planted complementary pair: for each i one of
  //   degenerate  x*_i = 0,        w*_i = 0
  //   active      x*_i in [1, 2),  w*_i = 0
  //   inactive    x*_i = 0,        w*_i in [1, 2)
  Vector x_star = Vector::Zero(n), w_star = Vector::Zero(n);
  for (int i = 0; i < n; ++i) {
    if (rng.Uniform() < options.degenerate_fraction) continue;
    if (rng.Uniform() < options.active_fraction) {
      x_star(i) = 1.0 + rng.Uniform();
    } else {
      w_star(i) = 1.0 + rng.Uniform();
    }
  }
  Vector q = w_star - M * x_star;  // so that M x* + q = w*

  TestProblem p;
  p.name = std::string("random-plcp") +
           (options.degenerate_fraction > 0 ? "-degenerate" : "") + "-" +
           std::to_string(n);
  p.source =
      "random sparse strictly row diagonally dominant M (a P-matrix, Cottle, Pang and "
      "Stone 1992, sec. 3.3) with a planted solution, seed " +
      std::to_string(options.seed);
  p.F = std::make_unique<AffineFunction>(std::move(M), std::move(q));
  p.lower = Vector::Zero(n);
  p.upper = Vector::Constant(n, std::numeric_limits<double>::infinity());
  p.starts = {{"zero", Vector::Zero(n)}, {"ones", Vector::Ones(n)}};
  p.solutions = {x_star};
  p.notes = "P-matrix LCP: the planted x* is the unique solution";
  return p;
}

}  // namespace ncp::collection
