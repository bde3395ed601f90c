/// \file obstacle.hpp
/// Obstacle problems for an elastic membrane on (0,1)^d, d = 1 or 2, discretized by
/// finite differences (3-point / 5-point Laplacian on a uniform grid, homogeneous
/// Dirichlet boundary):
///     l(x) <= u(x) <= r(x)  perp  F(u) = -Lap_h u - f,
/// the discrete form of the variational inequality of Kinderlehrer and Stampacchia
/// (1980), ch. II. The unknowns are the interior nodal values; sizes are chosen freely,
/// e.g. 1000 x 1000 gives 10^6 unknowns.
#pragma once

#include "ncp_collection/test_problem.hpp"

namespace ncp::collection {

enum class ObstacleKind {
  /// Membrane pulled over a bump: f = 0, lower obstacle psi(x) = 1/2 - 8 |x - c|^2
  /// (c the centre of the domain), no upper obstacle. An LCP in the shifted variable
  /// u - psi. In 1D the continuous solution is known: u = psi on [a, 1 - a] and linear
  /// tangents outside, a = 1/2 - (2 - sqrt(3))/4 ~= 0.4330.
  kLowerBump,
  /// Two-sided obstacle (a genuine box MCP): f = 40 sin(2 pi x) in 1D and
  /// f = 40 sin(2 pi x) sin(2 pi y) in 2D, -0.1 <= u <= 0.1. Both bounds are active on
  /// sets of positive measure.
  kTwoSidedBand,
};

const char* ToString(ObstacleKind kind);

/// The unknown the problem is written in.
enum class ObstacleVariable {
  /// The membrane's height u: l <= u <= r perp A u - f.
  kHeight,
  /// The gap to the lower obstacle w = u - l: 0 <= w <= r - l perp A w - (f - A l), with
  /// A l - f computed once. The same solution shifted, but better conditioned in floating
  /// point: an iterate w is stored to eps |w|, which vanishes on the contact set, where u
  /// is stored to eps |u|; the rows' round-off eps h^-2 |u| (above 1e-10 from h ~ 1e-3
  /// on)
  /// becomes eps h^-2 |w|.
  kGap,
};

/// 1D: n interior nodes, h = 1 / (n + 1). Starts "zero" and "obstacle" (kLowerBump,
/// u0 = max(psi, 0)) or "ceiling" (kTwoSidedBand, u0 = 0.1), given in the chosen variable
/// (kGap: w0 = u0 - l; name suffix "-gap").
TestProblem Obstacle1D(int n, ObstacleKind kind = ObstacleKind::kLowerBump,
                       ObstacleVariable variable = ObstacleVariable::kHeight);

/// 2D: m x m interior nodes, h = 1 / (m + 1), n = m^2 unknowns in lexicographic order
/// (index i + m j for the node (x_i, y_j)). Same starts as the 1D problem.
TestProblem Obstacle2D(int m, ObstacleKind kind = ObstacleKind::kLowerBump,
                       ObstacleVariable variable = ObstacleVariable::kHeight);

/// The exact solution of the continuous 1D kLowerBump problem at x in [0, 1].
double ExactLowerBump1D(double x);

}  // namespace ncp::collection
