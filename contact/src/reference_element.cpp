#include "reference_element.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "quadratic_element.hpp"

namespace contact::internal {
namespace {

// Reference corner coordinates of the tensor-product elements (gmsh order).
constexpr double kQuadCorners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
constexpr double kHexCorners[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

QuadratureRule Gauss2TensorRule(int dim) {
  const double g = 1.0 / std::sqrt(3.0);
  const int n = 1 << dim;
  QuadratureRule rule;
  rule.points.resize(dim, n);
  rule.weights = Eigen::VectorXd::Ones(n);
  for (int q = 0; q < n; ++q)
    for (int k = 0; k < dim; ++k) rule.points(k, q) = ((q >> k) & 1) ? g : -g;
  return rule;
}

QuadratureRule SimplexCentroidRule(int dim) {
  QuadratureRule rule;
  rule.points = Eigen::MatrixXd::Constant(dim, 1, 1.0 / (dim + 1));
  rule.weights = Eigen::VectorXd::Constant(1, dim == 2 ? 1.0 / 2.0 : 1.0 / 6.0);
  return rule;
}

// Degree-2 rules: triangle (1/6,1/6),(2/3,1/6),(1/6,2/3), weights 1/6 (Strang & Fix);
// tetrahedron with a = (5 + 3 sqrt 5)/20, b = (5 - sqrt 5)/20, weights 1/24.
QuadratureRule SimplexDegree2Rule(int dim) {
  QuadratureRule rule;
  if (dim == 2) {
    rule.points.resize(2, 3);
    rule.points << 1.0 / 6, 2.0 / 3, 1.0 / 6,  //
        1.0 / 6, 1.0 / 6, 2.0 / 3;
    rule.weights = Eigen::VectorXd::Constant(3, 1.0 / 6.0);
  } else {
    const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
    const double b = (5.0 - std::sqrt(5.0)) / 20.0;
    rule.points.resize(3, 4);
    rule.points << b, a, b, b,  //
        b, b, a, b,             //
        b, b, b, a;
    rule.weights = Eigen::VectorXd::Constant(4, 1.0 / 24.0);
  }
  return rule;
}

// 3-point Gauss-Legendre in each of dim directions (exact to degree 5 per direction).
QuadratureRule Gauss3TensorRule(int dim) {
  const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  int n = 1;
  for (int k = 0; k < dim; ++k) n *= 3;
  QuadratureRule rule;
  rule.points.resize(dim, n);
  rule.weights = Eigen::VectorXd::Ones(n);
  for (int q = 0; q < n; ++q)
    for (int k = 0, rest = q; k < dim; ++k, rest /= 3) {
      rule.points(k, q) = g[rest % 3];
      rule.weights(q) *= w[rest % 3];
    }
  return rule;
}

// Points with barycentric coordinates (b, a, a, ...) and its permutations ("S31" / "S21"
// orbits), and (a, a, b, b) ("S22"), appended with weight w.
void AddOrbit(const std::vector<double>& barycentric, double w, QuadratureRule* rule) {
  std::vector<double> l = barycentric;
  std::sort(l.begin(), l.end());
  const int dim = static_cast<int>(l.size()) - 1;
  do {
    const Eigen::Index q = rule->weights.size();
    rule->points.conservativeResize(dim, q + 1);
    rule->weights.conservativeResize(q + 1);
    for (int k = 0; k < dim; ++k) rule->points(k, q) = l[static_cast<size_t>(k + 1)];
    rule->weights(q) = w;
  } while (std::next_permutation(l.begin(), l.end()));
}

// Degree 4 on the triangle, 6 points (Dunavant 1985), weights for area 1/2.
QuadratureRule TriangleDegree4Rule() {
  QuadratureRule rule;
  rule.points.resize(2, 0);
  const double a = 0.445948490915965, b = 0.091576213509771;
  AddOrbit({1 - 2 * a, a, a}, 0.5 * 0.223381589678011, &rule);
  AddOrbit({1 - 2 * b, b, b}, 0.5 * 0.109951743655322, &rule);
  return rule;
}

// Degree 5 on the tetrahedron, 14 points with positive weights (Walkington 2000, also
// gmsh's and Keast's), weights for volume 1/6.
QuadratureRule TetrahedronDegree5Rule() {
  QuadratureRule rule;
  rule.points.resize(3, 0);
  const double a1 = 0.0927352503108912264, a2 = 0.3108859192633006097;
  const double c = 0.0455037041256496494;
  AddOrbit({1 - 3 * a1, a1, a1, a1}, 0.0734930431163619495 / 6, &rule);
  AddOrbit({1 - 3 * a2, a2, a2, a2}, 0.1126879257180158508 / 6, &rule);
  AddOrbit({c, c, 0.5 - c, 0.5 - c}, 0.0425460207770814664 / 6, &rule);
  return rule;
}

}  // namespace

void EvaluateShape(int ref_dim, int nodes, const double* xi, double* N, double* dN) {
  if (ref_dim == 1 && nodes == 2) {
    N[0] = 0.5 * (1 - xi[0]);
    N[1] = 0.5 * (1 + xi[0]);
    dN[0] = -0.5;
    dN[1] = 0.5;
  } else if (ref_dim == 2 && nodes == 3) {
    N[0] = 1 - xi[0] - xi[1];
    N[1] = xi[0];
    N[2] = xi[1];
    const double d[6] = {-1, -1, 1, 0, 0, 1};
    for (int i = 0; i < 6; ++i) dN[i] = d[i];
  } else if (ref_dim == 2 && nodes == 4) {
    for (int a = 0; a < 4; ++a) {
      const double sx = kQuadCorners[a][0], sy = kQuadCorners[a][1];
      N[a] = 0.25 * (1 + sx * xi[0]) * (1 + sy * xi[1]);
      dN[2 * a + 0] = 0.25 * sx * (1 + sy * xi[1]);
      dN[2 * a + 1] = 0.25 * sy * (1 + sx * xi[0]);
    }
  } else if (ref_dim == 3 && nodes == 4) {
    N[0] = 1 - xi[0] - xi[1] - xi[2];
    N[1] = xi[0];
    N[2] = xi[1];
    N[3] = xi[2];
    const double d[12] = {-1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int i = 0; i < 12; ++i) dN[i] = d[i];
  } else if (ref_dim == 3 && nodes == 8) {
    for (int a = 0; a < 8; ++a) {
      const double sx = kHexCorners[a][0], sy = kHexCorners[a][1], sz = kHexCorners[a][2];
      const double fx = 1 + sx * xi[0], fy = 1 + sy * xi[1], fz = 1 + sz * xi[2];
      N[a] = 0.125 * fx * fy * fz;
      dN[3 * a + 0] = 0.125 * sx * fy * fz;
      dN[3 * a + 1] = 0.125 * fx * sy * fz;
      dN[3 * a + 2] = 0.125 * fx * fy * sz;
    }
  } else if (!EvaluateQuadraticShape(ref_dim, nodes, xi, N, dN)) {
    throw std::logic_error("EvaluateShape: no element with reference dimension " +
                           std::to_string(ref_dim) + " and " + std::to_string(nodes) +
                           " nodes");
  }
}

const QuadratureRule& ElementRule(ElementType type, RulePurpose purpose) {
  static const QuadratureRule tri1 = SimplexCentroidRule(2);
  static const QuadratureRule tri3 = SimplexDegree2Rule(2);
  static const QuadratureRule tet1 = SimplexCentroidRule(3);
  static const QuadratureRule tet4 = SimplexDegree2Rule(3);
  static const QuadratureRule quad4 = Gauss2TensorRule(2);
  static const QuadratureRule hex8 = Gauss2TensorRule(3);
  static const QuadratureRule tri6 = TriangleDegree4Rule();
  static const QuadratureRule tet14 = TetrahedronDegree5Rule();
  static const QuadratureRule quad9 = Gauss3TensorRule(2);
  static const QuadratureRule hex27 = Gauss3TensorRule(3);
  const bool stiffness = purpose == RulePurpose::kStiffness;
  switch (type) {
    case ElementType::kTriangle6:
      return tri6;
    case ElementType::kQuadrilateral8:
    case ElementType::kQuadrilateral9:
      return quad9;
    case ElementType::kTetrahedron10:
      return tet14;
    case ElementType::kHexahedron20:
    case ElementType::kHexahedron27:
      return hex27;
    case ElementType::kTriangle3:
      return stiffness ? tri1 : tri3;
    case ElementType::kQuadrilateral4:
      return quad4;
    case ElementType::kTetrahedron4:
      return stiffness ? tet1 : tet4;
    case ElementType::kHexahedron8:
    default:
      return hex8;
  }
}

const QuadratureRule& FacetRule(FacetType type) {
  static const QuadratureRule line2 = Gauss2TensorRule(1);
  static const QuadratureRule tri3 = SimplexDegree2Rule(2);
  static const QuadratureRule quad4 = Gauss2TensorRule(2);
  static const QuadratureRule line3 = Gauss3TensorRule(1);
  static const QuadratureRule tri6 = TriangleDegree4Rule();
  static const QuadratureRule quad9 = Gauss3TensorRule(2);
  switch (type) {
    case FacetType::kLine3:
      return line3;
    case FacetType::kTriangle6:
      return tri6;
    case FacetType::kQuadrilateral8:
    case FacetType::kQuadrilateral9:
      return quad9;
    case FacetType::kLine2:
      return line2;
    case FacetType::kTriangle3:
      return tri3;
    case FacetType::kQuadrilateral4:
    default:
      return quad4;
  }
}

}  // namespace contact::internal
