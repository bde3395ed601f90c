// Finite-difference obstacle problems, 1D and 2D.
//
// The membrane u on (0,1)^d with u = 0 on the boundary, load f and obstacles l <= u <= r
// solves the variational inequality of Kinderlehrer and Stampacchia (1980), ch. II,
// whose strong form is the pointwise complementarity problem
//     l <= u <= r,  -Lap u - f >= 0 where u = l,  <= 0 where u = r,  = 0 in between.
// On the uniform grid x_i = i h, i = 1..m, h = 1/(m+1), the standard (2d+1)-point
// Laplacian gives the box MCP  l <= u <= r  perp  F(u) = A u - f  with
//     (A u)_k = h^-2 (2d u_k - sum of the neighbours of node k),
// neighbours on the boundary being 0. A is an M-matrix, symmetric positive definite,
// so F is strongly monotone and the MCP has a unique solution (Cottle, Pang and Stone
// 1992, Thm. 3.3.7 for the LCP; Facchinei and Pang 2003, Thm. 2.3.3 for the box).
// The scaling h^-2 keeps F a discretization of the differential operator, so the
// complementarity residual is measured in the same units on every grid: that is what
// makes Newton iteration counts comparable across grids (mesh independence,
// Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2003) 865-888).
#include "ncp_collection/obstacle.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace ncp::collection {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
constexpr double kBandLoad = 40.0;      // amplitude of f for kTwoSidedBand
constexpr double kBandHalfWidth = 0.1;  // |u| <= 0.1 for kTwoSidedBand

// psi(x) = 1/2 - 8 |x - c|^2, the bump of kLowerBump (r2 = |x - c|^2).
double Bump(double r2) { return 0.5 - 8.0 * r2; }

void CheckSize(const char* who, int m, long long max_unknowns) {
  if (m < 1) {
    throw std::invalid_argument(std::string(who) + ": grid size " + std::to_string(m) +
                                " < 1");
  }
  if (max_unknowns > std::numeric_limits<int>::max() / 5) {
    throw std::invalid_argument(std::string(who) + ": grid size " + std::to_string(m) +
                                " too large for int indices");
  }
}

// h^-2 tridiag(-1, 2, -1), m x m, assembled column by column (it is symmetric, so
// column k holds the same entries as row k, in increasing row order).
SparseMatrix Laplacian1D(int m) {
  const double s = static_cast<double>(m + 1) * (m + 1);  // h^-2
  SparseMatrix A(m, m);
  A.reserve(Eigen::VectorXi::Constant(m, 3));
  for (int k = 0; k < m; ++k) {
    if (k > 0) A.insert(k - 1, k) = -s;
    A.insert(k, k) = 2 * s;
    if (k + 1 < m) A.insert(k + 1, k) = -s;
  }
  A.makeCompressed();
  return A;
}

// 5-point Laplacian h^-2 (4 u_k - u_W - u_E - u_S - u_N) on the m x m grid, node
// (i, j) -> k = i + m j. Built directly in compressed column storage (rows ascending:
// S = k - m, W = k - 1, k, E = k + 1, N = k + m) so that 10^6 unknowns assemble fast.
SparseMatrix Laplacian2D(int m) {
  const int n = m * m;
  const double s = static_cast<double>(m + 1) * (m + 1);
  SparseMatrix A(n, n);
  A.reserve(Eigen::VectorXi::Constant(n, 5));
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int k = i + m * j;
      if (j > 0) A.insert(k - m, k) = -s;
      if (i > 0) A.insert(k - 1, k) = -s;
      A.insert(k, k) = 4 * s;
      if (i + 1 < m) A.insert(k + 1, k) = -s;
      if (j + 1 < m) A.insert(k + m, k) = -s;
    }
  }
  A.makeCompressed();
  return A;
}

// F(u) = A u - f evaluated stencil-wise as h^-2 sum_nb (u_k - u_nb) - f_k. Forming the
// differences u_k - u_nb first makes them exact for neighbouring values (Sterbenz), so
// the rounding error of F is about eps h^-2 |u_k - u_nb| ~ eps h^-1 |grad u| instead of
// eps h^-2 |u| for the assembled product A u: with h = 1e-5 (1D, n = 1e5) that is the
// difference between 1e-11 and 1e-6, i.e. between reaching ||Phi|| <= 1e-10 or not.
// The Jacobian is the assembled A (constant).
class GridObstacleFunction : public SquareFunction {
 public:
  GridObstacleFunction(int dimension, int m, SparseMatrix A, Vector load)
      : dimension_(dimension),
        m_(m),
        inverse_h2_(static_cast<double>(m + 1) * (m + 1)),
        A_(std::move(A)),
        load_(std::move(load)) {}

  int NumVariables() const override { return static_cast<int>(load_.size()); }

  bool Evaluate(const Vector& u, Vector* F) override {
    const int m = m_;
    if (dimension_ == 1) {
      for (int i = 0; i < m; ++i) {
        const double west = i > 0 ? u(i - 1) : 0.0, east = i + 1 < m ? u(i + 1) : 0.0;
        (*F)(i) = inverse_h2_ * ((u(i) - west) + (u(i) - east)) - load_(i);
      }
      return true;
    }
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        const int k = i + m * j;
        const double c = u(k);
        const double west = i > 0 ? u(k - 1) : 0.0, east = i + 1 < m ? u(k + 1) : 0.0;
        const double south = j > 0 ? u(k - m) : 0.0, north = j + 1 < m ? u(k + m) : 0.0;
        (*F)(k) =
            inverse_h2_ * (((c - west) + (c - east)) + ((c - south) + (c - north))) -
            load_(k);
      }
    }
    return true;
  }

  bool Jacobian(const Vector& /*u*/, SparseMatrix* J) override {
    *J = A_;
    return true;
  }

 private:
  int dimension_;
  int m_;
  double inverse_h2_;
  SparseMatrix A_;
  Vector load_;
};

TestProblem Assemble(std::string name, int dimension, int m, SparseMatrix A, Vector load,
                     Vector lower, Vector upper, ObstacleKind kind,
                     ObstacleVariable variable) {
  TestProblem p;
  p.name = std::move(name);
  const int n = static_cast<int>(load.size());
  // Starts in the height u; for the gap w = u - l they are shifted below.
  std::vector<StartPoint> starts = {{"zero", Vector::Zero(n)}};
  starts.push_back(kind == ObstacleKind::kLowerBump
                       ? StartPoint{"obstacle", lower.cwiseMax(0.0)}
                       : StartPoint{"ceiling", upper});
  if (variable == ObstacleVariable::kGap) {
    // A (w + l) - f = A w - (f - A l); A l - f evaluated stencil-wise, once.
    Vector residual_at_lower(n);
    GridObstacleFunction(dimension, m, A, load).Evaluate(lower, &residual_at_lower);
    load = -residual_at_lower;
    upper -= lower;  // +inf stays +inf
    for (StartPoint& start : starts) start.x -= lower;
    lower.setZero();
    p.name += "-gap";
  }
  p.F =
      std::make_unique<GridObstacleFunction>(dimension, m, std::move(A), std::move(load));
  p.lower = std::move(lower);
  p.upper = std::move(upper);
  p.starts = std::move(starts);
  if (kind == ObstacleKind::kLowerBump) {
    p.notes =
        "membrane over the bump psi = 1/2 - 8|x - c|^2, f = 0; LCP in u - psi; "
        "unique solution (A is an M-matrix), not known in closed form on the grid";
  } else {
    p.notes =
        "two-sided obstacle -0.1 <= u <= 0.1 with a sign-changing load; both bounds "
        "active; unique solution (A is an M-matrix)";
  }
  return p;
}

}  // namespace

const char* ToString(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::kLowerBump:
      return "bump";
    case ObstacleKind::kTwoSidedBand:
      return "band";
  }
  return "unknown";
}

TestProblem Obstacle1D(int n, ObstacleKind kind, ObstacleVariable variable) {
  CheckSize("Obstacle1D", n, n);
  const double h = 1.0 / (n + 1);
  Vector load(n), lower(n), upper(n);
  for (int i = 0; i < n; ++i) {
    const double x = (i + 1) * h;
    if (kind == ObstacleKind::kLowerBump) {
      load(i) = 0.0;
      lower(i) = Bump((x - 0.5) * (x - 0.5));
      upper(i) = kInf;
    } else {
      load(i) = kBandLoad * std::sin(2 * kPi * x);
      lower(i) = -kBandHalfWidth;
      upper(i) = kBandHalfWidth;
    }
  }
  TestProblem p =
      Assemble(std::string("obstacle1d-") + ToString(kind) + "-" + std::to_string(n), 1,
               n, Laplacian1D(n), std::move(load), std::move(lower), std::move(upper),
               kind, variable);
  p.source =
      "membrane obstacle problem (Kinderlehrer and Stampacchia 1980, ch. II), "
      "3-point finite differences on (0,1)";
  return p;
}

TestProblem Obstacle2D(int m, ObstacleKind kind, ObstacleVariable variable) {
  CheckSize("Obstacle2D", m, static_cast<long long>(m) * m);
  const int n = m * m;
  const double h = 1.0 / (m + 1);
  Vector load(n), lower(n), upper(n);
  for (int j = 0; j < m; ++j) {
    const double y = (j + 1) * h;
    for (int i = 0; i < m; ++i) {
      const double x = (i + 1) * h;
      const int k = i + m * j;
      if (kind == ObstacleKind::kLowerBump) {
        load(k) = 0.0;
        lower(k) = Bump((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5));
        upper(k) = kInf;
      } else {
        load(k) = kBandLoad * std::sin(2 * kPi * x) * std::sin(2 * kPi * y);
        lower(k) = -kBandHalfWidth;
        upper(k) = kBandHalfWidth;
      }
    }
  }
  TestProblem p = Assemble(std::string("obstacle2d-") + ToString(kind) + "-" +
                               std::to_string(m) + "x" + std::to_string(m),
                           2, m, Laplacian2D(m), std::move(load), std::move(lower),
                           std::move(upper), kind, variable);
  p.source =
      "membrane obstacle problem (Kinderlehrer and Stampacchia 1980, ch. II), "
      "5-point finite differences on (0,1)^2";
  return p;
}

// Continuous 1D kLowerBump solution: with f = 0 the membrane is straight off the
// contact set and leaves the obstacle tangentially (u in C^1). The tangent from (0, 0)
// touches psi at a with psi(a) = a psi'(a): with t = a - 1/2 this is
// 1/2 - 8 t^2 = -16 t (t + 1/2), i.e. 8 t^2 + 8 t + 1/2 = 0, t = (-2 + sqrt(3)) / 4.
// The slope is psi'(a) = -16 t = 4 (2 - sqrt(3)); by symmetry the same on the right.
double ExactLowerBump1D(double x) {
  const double t = (-2.0 + std::sqrt(3.0)) / 4.0;
  const double a = 0.5 + t;
  const double slope = -16.0 * t;
  if (x <= a) return slope * x;
  if (x >= 1.0 - a) return slope * (1.0 - x);
  return Bump((x - 0.5) * (x - 0.5));
}

}  // namespace ncp::collection
