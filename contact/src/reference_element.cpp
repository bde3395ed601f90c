#include "reference_element.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

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
  } else {
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
  const bool stiffness = purpose == RulePurpose::kStiffness;
  switch (type) {
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
  switch (type) {
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
