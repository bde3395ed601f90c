// COPS 2.0 problems 15-17 as written in the GAMS model library (torsion.gms SEQ=243,
// jbearing.gms SEQ=244, minsurf.gms SEQ=245; the formulas and data are transcribed, no
// code was copied), as box MCPs  l <= v <= u  perp  grad f(v).
//
// Grid: nodes (i, j), 0 <= i <= nx, 0 <= j <= ny (GAMS's sets 0..%nx%, 0..%ny%), the
// boundary nodes fixed by the .gms (v.fx, or bounds -0 <= v <= 0 in torsion), the
// interior ones the unknowns. Every objective is a sum over the two triangles of each
// cell: the "lower" triangle (i, j), (i+1, j), (i, j+1) for 0 <= i < nx, 0 <= j < ny and
// the "upper" triangle (i, j), (i-1, j), (i, j-1) for 1 <= i <= nx, 1 <= j <= ny.
// References: Dolan and More, COPS (2000); B. M. Averick, R. G. Carter, J. J. More and
// G.-L. Xue, "The MINPACK-2 test problem collection", ANL/MCS-P153-0692 (1992) (torsion,
// journal bearing); R. Glowinski, Numerical Methods for Nonlinear Variational Problems
// (1984) (torsion); G. Capriz and G. Cimatti (1983) (journal bearing); A. Friedman,
// Notices AMS 47 (2000) 854-861 (minimal surface with obstacle).
#include "ncp_collection/cops_bound_constrained.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ncp_collection/affine_function.hpp"
#include "problem_building.hpp"
#include "triplet_jacobian_function.hpp"

namespace ncp::collection {
namespace {

using internal::JacobianEntries;
using internal::kInf;

constexpr double kPi = 3.14159265358979323846;

// The interior unknowns of an (nx + 1) x (ny + 1) node grid.
struct Grid {
  int nx = 0, ny = 0;  // intervals in x and y

  Grid(const char* who, int interior_x, int interior_y)
      : nx(interior_x + 1), ny(interior_y + 1) {
    if (interior_x < 1 || interior_y < 1) {
      throw std::invalid_argument(std::string(who) + ": grid " +
                                  std::to_string(interior_x) + " x " +
                                  std::to_string(interior_y) + " needs >= 1 x 1 nodes");
    }
    if (static_cast<long long>(interior_x) * interior_y >
        std::numeric_limits<int>::max() / 16) {
      throw std::invalid_argument(std::string(who) + ": grid too large for int indices");
    }
  }
  int NumUnknowns() const { return (nx - 1) * (ny - 1); }
  bool Interior(int i, int j) const { return i > 0 && i < nx && j > 0 && j < ny; }
  // Index of the unknown at node (i, j), -1 on the boundary.
  int Unknown(int i, int j) const {
    return Interior(i, j) ? (i - 1) + (nx - 1) * (j - 1) : -1;
  }
  void CheckSize(const char* who, const Vector& v) const {
    if (v.size() != NumUnknowns()) {
      throw std::invalid_argument(std::string(who) + ": v has size " +
                                  std::to_string(v.size()) + ", expected " +
                                  std::to_string(NumUnknowns()));
    }
  }
};

// A quadratic objective with zero boundary values,
//   f(v) = sum_terms weight ((v_a - v_b)/h)^2 + sum_k linear_k v_k,
// whose gradient is F(v) = H v + linear with H = sum_terms 2 weight/h^2 (e_a - e_b)(e_a -
// e_b)' (terms with a boundary node keep only the interior one).
class QuadraticGridObjective {
 public:
  explicit QuadraticGridObjective(int n) : linear_(Vector::Zero(n)) {}

  // weight ((v_a - v_b)/h)^2 for unknowns a, b (-1: a boundary node, value 0).
  void AddSquaredDifference(double weight, int a, int b, double h) {
    squares_.push_back({a, b, weight / (h * h)});
  }
  void AddLinear(double coefficient, int a) {
    if (a >= 0) linear_(a) += coefficient;
  }

  double Value(const Vector& v) const {
    double f = linear_.dot(v);
    for (const Square& s : squares_) {
      const double difference = (s.a >= 0 ? v(s.a) : 0.0) - (s.b >= 0 ? v(s.b) : 0.0);
      f += s.scaled_weight * difference * difference;
    }
    return f;
  }

  // F(v) = H v + linear as an affine function.
  std::unique_ptr<AffineFunction> Gradient() const {
    const int n = static_cast<int>(linear_.size());
    std::vector<Eigen::Triplet<double>> entries;
    for (const Square& s : squares_) {
      const double c = 2 * s.scaled_weight;
      if (s.a >= 0) entries.emplace_back(s.a, s.a, c);
      if (s.b >= 0) entries.emplace_back(s.b, s.b, c);
      if (s.a >= 0 && s.b >= 0) {
        entries.emplace_back(s.a, s.b, -c);
        entries.emplace_back(s.b, s.a, -c);
      }
    }
    SparseMatrix H(n, n);
    H.setFromTriplets(entries.begin(), entries.end());
    return std::make_unique<AffineFunction>(std::move(H), linear_);
  }

 private:
  struct Square {
    int a, b;
    double scaled_weight;  // weight / h^2
  };
  std::vector<Square> squares_;
  Vector linear_;
};

// ---- jbearing (COPS #16) ------------------------------------------------------------
// Domain (0, 2 pi) x (0, 2b), b = 10, eccentricity e = 0.1, hx = 2 pi/nx, hy = 2b/ny,
// wq_i = (1 + e cos(i hx))^3. With v = 0 on the boundary and v >= 0,
//   f(v) = hx hy/12 sum_lower (wq_i + 2 wq_{i+1})
//                  [((v_{i+1,j} - v_{i,j})/hx)^2 + ((v_{i,j+1} - v_{i,j})/hy)^2]
//        + hx hy/12 sum_{0<=i<nx, 0<=j<ny} (2 wq_{i+1} + 2 wq_i)
//                  [((v_{i,j+1} - v_{i+1,j+1})/hx)^2 + ((v_{i+1,j} - v_{i+1,j+1})/hy)^2]
//        - hx hy sum_{i,j} e sin(i hx) v_{i,j}
// (the weight 2 wq_{i+1} + 2 wq_i of the second sum is that of the .gms and of the COPS
// AMPL model bearing.mod). Start v = max(sin(i hx), 0).
QuadraticGridObjective JournalBearingQuadratic(const Grid& g) {
  const double b = 10, e = 0.1;
  const double hx = 2 * kPi / g.nx, hy = 2 * b / g.ny;
  auto wq = [&](int i) { return std::pow(1 + e * std::cos(i * hx), 3); };
  QuadraticGridObjective f(g.NumUnknowns());
  for (int i = 0; i < g.nx; ++i) {
    const double lower = hx * hy / 12 * (wq(i) + 2 * wq(i + 1));
    const double upper = hx * hy / 12 * (2 * wq(i + 1) + 2 * wq(i));
    for (int j = 0; j < g.ny; ++j) {
      f.AddSquaredDifference(lower, g.Unknown(i + 1, j), g.Unknown(i, j), hx);
      f.AddSquaredDifference(lower, g.Unknown(i, j + 1), g.Unknown(i, j), hy);
      f.AddSquaredDifference(upper, g.Unknown(i, j + 1), g.Unknown(i + 1, j + 1), hx);
      f.AddSquaredDifference(upper, g.Unknown(i + 1, j), g.Unknown(i + 1, j + 1), hy);
    }
  }
  for (int i = 0; i <= g.nx; ++i)
    for (int j = 0; j <= g.ny; ++j)
      f.AddLinear(-hx * hy * e * std::sin(i * hx), g.Unknown(i, j));
  return f;
}

// ---- torsion (COPS #15) -------------------------------------------------------------
// Domain (0, 1)^2, hx = 1/nx, hy = 1/ny, area = hx hy/2, c = 5,
//   f(v) = area [ (QL + QU)/2 - c (LL + LU)/3 ],
//   QL = sum_lower ((v_{i+1,j} - v_{i,j})/hx)^2 + ((v_{i,j+1} - v_{i,j})/hy)^2,
//   QU = sum_upper ((v_{i,j} - v_{i-1,j})/hx)^2 + ((v_{i,j} - v_{i,j-1})/hy)^2,
//   LL = sum_lower v_{i+1,j} + v_{i,j} + v_{i,j+1},
//   LU = sum_upper v_{i,j} + v_{i-1,j} + v_{i,j-1},
// subject to -D <= v <= D, D_{ij} = min(min(i, nx - i) hx, min(j, ny - j) hy) (0 on the
// boundary, which fixes v there). Start v = D.
QuadraticGridObjective TorsionQuadratic(const Grid& g) {
  const double hx = 1.0 / g.nx, hy = 1.0 / g.ny, area = 0.5 * hx * hy, c = 5;
  QuadraticGridObjective f(g.NumUnknowns());
  const double linear = -area * c / 3;
  for (int i = 0; i < g.nx; ++i) {
    for (int j = 0; j < g.ny; ++j) {
      f.AddSquaredDifference(area / 2, g.Unknown(i + 1, j), g.Unknown(i, j), hx);
      f.AddSquaredDifference(area / 2, g.Unknown(i, j + 1), g.Unknown(i, j), hy);
      for (int node : {g.Unknown(i + 1, j), g.Unknown(i, j), g.Unknown(i, j + 1)})
        f.AddLinear(linear, node);
    }
  }
  for (int i = 1; i <= g.nx; ++i) {
    for (int j = 1; j <= g.ny; ++j) {
      f.AddSquaredDifference(area / 2, g.Unknown(i, j), g.Unknown(i - 1, j), hx);
      f.AddSquaredDifference(area / 2, g.Unknown(i, j), g.Unknown(i, j - 1), hy);
      for (int node : {g.Unknown(i, j), g.Unknown(i - 1, j), g.Unknown(i, j - 1)})
        f.AddLinear(linear, node);
    }
  }
  return f;
}

double TorsionDistance(const Grid& g, int i, int j) {
  return std::min(std::min(i, g.nx - i) * (1.0 / g.nx),
                  std::min(j, g.ny - j) * (1.0 / g.ny));
}

// ---- minsurf (COPS #17) -------------------------------------------------------------
// Domain (0, 1)^2, hx = 1/nx, hy = 1/ny, area = hx hy/2. Boundary values: v = 0 on
// x = 0, 1, then v = 1 - (2 i hx - 1)^2 on y = 0, 1 (the .gms assigns these last, so
// they hold at the corners). With the triangle area element
//   T(c, a, b) = sqrt(1 + ((v_a - v_c)/hx)^2 + ((v_b - v_c)/hy)^2)
// at the corner c with x-neighbour a and y-neighbour b,
//   f(v) = area [ sum_lower T((i,j), (i+1,j), (i,j+1))
//               + sum_upper T((i,j), (i-1,j), (i,j-1)) ],
// subject to v >= 1 at the nodes with floor(0.25/hx) <= i <= ceil(0.75/hx) and
// floor(0.25/hy) <= j <= ceil(0.75/hy), v >= 0 elsewhere. Start v = 1 - (2 i hx - 1)^2.
// With s = ((v_a - v_c)/hx, (v_b - v_c)/hy), T = sqrt(1 + |s|^2) and ds/d(v_c, v_a, v_b)
// = B = [-1/hx 1/hx 0; -1/hy 0 1/hy]:
//   grad T = B' s / T,   Hess T = B' (I - s s'/T^2) B / T.
class MinimalSurfaceFunction : public internal::TripletJacobianFunction {
 public:
  explicit MinimalSurfaceFunction(const Grid& g)
      : TripletJacobianFunction(g.NumUnknowns()),
        grid_(g),
        hx_(1.0 / g.nx),
        hy_(1.0 / g.ny),
        area_(0.5 * hx_ * hy_) {}

  double BoundaryValue(int i, int j) const {
    if (j == 0 || j == grid_.ny) {
      const double x = 2 * i * hx_ - 1;
      return 1 - x * x;
    }
    return 0.0;
  }

  double Objective(const Vector& v) const {
    double f = 0.0;
    ForEachTriangle(v, [&](const int*, const double*, double T) { f += area_ * T; });
    return f;
  }

  bool Evaluate(const Vector& v, Vector* F) override {
    F->setZero();
    ForEachTriangle(v, [&](const int* node, const double* s, double T) {
      const double ds[3][2] = {{-1 / hx_, -1 / hy_}, {1 / hx_, 0}, {0, 1 / hy_}};
      for (int k = 0; k < 3; ++k)
        if (node[k] >= 0)
          (*F)(node[k]) += area_ * (ds[k][0] * s[0] + ds[k][1] * s[1]) / T;
    });
    return true;
  }

 protected:
  bool AddJacobian(const Vector& v, JacobianEntries* J) override {
    ForEachTriangle(v, [&](const int* node, const double* s, double T) {
      const double ds[3][2] = {{-1 / hx_, -1 / hy_}, {1 / hx_, 0}, {0, 1 / hy_}};
      // (I - s s'/T^2) / T
      const double T3 = T * T * T;
      const double Hs[2][2] = {{(T * T - s[0] * s[0]) / T3, -s[0] * s[1] / T3},
                               {-s[1] * s[0] / T3, (T * T - s[1] * s[1]) / T3}};
      for (int k = 0; k < 3; ++k) {
        if (node[k] < 0) continue;
        for (int m = 0; m < 3; ++m) {
          if (node[m] < 0) continue;
          double value = 0.0;
          for (int p = 0; p < 2; ++p)
            for (int q = 0; q < 2; ++q) value += ds[k][p] * Hs[p][q] * ds[m][q];
          J->Add(node[k], node[m], area_ * value);
        }
      }
    });
    return true;
  }

 private:
  // visit(node[3], s[2], T) for every triangle; node = unknowns of (corner, x-neighbour,
  // y-neighbour), -1 on the boundary.
  template <class Visit>
  void ForEachTriangle(const Vector& v, Visit visit) const {
    auto value = [&](int i, int j) {
      const int k = grid_.Unknown(i, j);
      return k >= 0 ? v(k) : BoundaryValue(i, j);
    };
    auto triangle = [&](int i, int j, int di, int dj) {
      const int node[3] = {grid_.Unknown(i, j), grid_.Unknown(i + di, j),
                           grid_.Unknown(i, j + dj)};
      const double corner = value(i, j);
      const double s[2] = {(value(i + di, j) - corner) / hx_,
                           (value(i, j + dj) - corner) / hy_};
      visit(node, s, std::sqrt(1 + s[0] * s[0] + s[1] * s[1]));
    };
    for (int i = 0; i < grid_.nx; ++i)
      for (int j = 0; j < grid_.ny; ++j) triangle(i, j, 1, 1);
    for (int i = 1; i <= grid_.nx; ++i)
      for (int j = 1; j <= grid_.ny; ++j) triangle(i, j, -1, -1);
  }

  Grid grid_;
  double hx_, hy_, area_;
};

// The interior values value(i, j) as a vector of unknowns.
template <class NodeValue>
Vector OnInterior(const Grid& g, NodeValue value) {
  Vector v(g.NumUnknowns());
  for (int j = 1; j < g.ny; ++j)
    for (int i = 1; i < g.nx; ++i) v(g.Unknown(i, j)) = value(i, j);
  return v;
}

// A problem named e.g. "torsion-25x25" with its source.
TestProblem GridProblem(const char* name, const Grid& g, const char* source) {
  TestProblem p;
  p.name =
      std::string(name) + "-" + std::to_string(g.nx - 1) + "x" + std::to_string(g.ny - 1);
  p.source = source;
  return p;
}

}  // namespace

TestProblem JournalBearing(int interior_x, int interior_y) {
  const Grid g("JournalBearing", interior_x, interior_y);
  TestProblem p = GridProblem(
      "jbearing", g,
      "GAMS model library jbearing.gms (SEQ=244), COPS 2.0 #16 (Dolan and More 2000); "
      "MINPACK-2 (Averick, Carter, More and Xue 1992); Capriz and Cimatti (1983)");
  p.F = JournalBearingQuadratic(g).Gradient();
  internal::MakeStandardNcp(&p);
  const double hx = 2 * kPi / g.nx;
  p.starts = {{"gams", OnInterior(g, [&](int i, int) {
                 return std::max(std::sin(i * hx), 0.0);
               })}};
  p.notes =
      "KKT system of a strictly convex QP (an LCP with a symmetric positive definite "
      "M): unique solution; F = gradient of the .gms objective (not rescaled)";
  return p;
}

TestProblem Torsion(int interior_x, int interior_y) {
  const Grid g("Torsion", interior_x, interior_y);
  TestProblem p = GridProblem(
      "torsion", g,
      "GAMS model library torsion.gms (SEQ=243), COPS 2.0 #15 (Dolan and More 2000); "
      "MINPACK-2 (Averick, Carter, More and Xue 1992); Glowinski (1984)");
  p.F = TorsionQuadratic(g).Gradient();
  p.upper = OnInterior(g, [&](int i, int j) { return TorsionDistance(g, i, j); });
  p.lower = -p.upper;
  p.starts = {{"gams", p.upper}};
  p.notes =
      "KKT system of a strictly convex QP with two-sided bounds |v| <= distance to the "
      "boundary: unique solution; F = gradient of the .gms objective (not rescaled)";
  return p;
}

TestProblem MinimalSurface(int interior_x, int interior_y) {
  const Grid g("MinimalSurface", interior_x, interior_y);
  auto F = std::make_unique<MinimalSurfaceFunction>(g);
  TestProblem p = GridProblem("minsurf", g,
                              "GAMS model library minsurf.gms (SEQ=245), COPS 2.0 #17 "
                              "(Dolan and More 2000); Friedman, Notices AMS 47 (2000)");
  const double hx = 1.0 / g.nx, hy = 1.0 / g.ny;
  p.lower = OnInterior(g, [&](int i, int j) {
    const bool obstacle = i >= std::floor(0.25 / hx) && i <= std::ceil(0.75 / hx) &&
                          j >= std::floor(0.25 / hy) && j <= std::ceil(0.75 / hy);
    return obstacle ? 1.0 : 0.0;
  });
  p.upper = Vector::Constant(g.NumUnknowns(), kInf);
  // 1 - (2 i hx - 1)^2, the boundary values of y = 0
  const Vector start = OnInterior(g, [&](int i, int) { return F->BoundaryValue(i, 0); });
  p.F = std::move(F);
  p.starts = {{"gams", start}};
  p.notes =
      "KKT system of a convex bound-constrained minimization (area of a piecewise linear "
      "surface); the .gms start lies below the obstacle there and is projected onto "
      "[l, u] by the solver; F = gradient of the .gms objective (not rescaled)";
  return p;
}

double JournalBearingObjective(int interior_x, int interior_y, const Vector& v) {
  const Grid g("JournalBearingObjective", interior_x, interior_y);
  g.CheckSize("JournalBearingObjective", v);
  return JournalBearingQuadratic(g).Value(v);
}

double TorsionObjective(int interior_x, int interior_y, const Vector& v) {
  const Grid g("TorsionObjective", interior_x, interior_y);
  g.CheckSize("TorsionObjective", v);
  return TorsionQuadratic(g).Value(v);
}

double MinimalSurfaceObjective(int interior_x, int interior_y, const Vector& v) {
  const Grid g("MinimalSurfaceObjective", interior_x, interior_y);
  g.CheckSize("MinimalSurfaceObjective", v);
  return MinimalSurfaceFunction(g).Objective(v);
}

std::vector<TestProblem> CopsBoundConstrainedProblems() {
  std::vector<TestProblem> problems;
  problems.push_back(JournalBearing());
  problems.push_back(Torsion());
  problems.push_back(MinimalSurface());
  return problems;
}

}  // namespace ncp::collection
