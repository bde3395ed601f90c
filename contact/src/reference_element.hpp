// Reference elements: shape functions, their derivatives and the quadrature rules.
//
// Reference domains (gmsh convention): simplices on the unit simplex {xi_k >= 0,
// sum xi_k <= 1}, tensor-product elements on [-1, 1]^d.
//
// Quadrature choices ("full integration"):
//   element         stiffness rule         mass / load rule
//   Triangle3       1 point (exact: B const)  3 points, degree 2 (exact for N_a N_b)
//   Quadrilateral4  2x2 Gauss               2x2 Gauss: N_a N_b det J has degree <= 3 per
//                                           direction (det J of a bilinear map is linear
//                                           in each direction), so exact on any Q4
//   Tetrahedron4    1 point (exact)         4 points, degree 2 (exact)
//   Hexahedron8     2x2x2 Gauss             2x2x2 Gauss: exact on parallelepipeds (det J
//                                           constant); on distorted hexahedra exact for
//                                           the total mass (det J has degree <= 2 per
//                                           direction) but not for every entry of M
//   Line2 facet     2-point Gauss; Triangle3 facet 3 points; Quadrilateral4 facet 2x2.
// Quadratic elements use one rule for stiffness and mass:
//   Triangle6       6 points, degree 4 (Dunavant): exact for N_a N_b and, on straight-
//                   sided elements, for the stiffness (degree 2)
//   Quadrilateral8/9, Hexahedron20/27   3 (x 3 x 3) Gauss, exact to degree 5 per
//   direction Tetrahedron10   14 points, degree 5 (Walkington; gmsh's Gauss5): exact for
//   N_a N_b Line3 facet     3-point Gauss; Triangle6 facet 6 points (degree 4);
//   Quadrilateral8/9
//                   facet 3x3 Gauss.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <type_traits>
#include <vector>

#include "contact/mesh.hpp"

namespace contact::internal {

template <ElementType T>
struct ElementTraits;
template <>
struct ElementTraits<ElementType::kTriangle3> {
  static constexpr int kDim = 2, kNodes = 3;
  static constexpr int kStiffnessPoints = 1;  // size of the stiffness rule
};
template <>
struct ElementTraits<ElementType::kQuadrilateral4> {
  static constexpr int kDim = 2, kNodes = 4;
  static constexpr int kStiffnessPoints = 4;  // size of the stiffness rule
};
template <>
struct ElementTraits<ElementType::kTetrahedron4> {
  static constexpr int kDim = 3, kNodes = 4;
  static constexpr int kStiffnessPoints = 1;  // size of the stiffness rule
};
template <>
struct ElementTraits<ElementType::kHexahedron8> {
  static constexpr int kDim = 3, kNodes = 8;
  static constexpr int kStiffnessPoints = 8;  // size of the stiffness rule
};

template <>
struct ElementTraits<ElementType::kTriangle6> {
  static constexpr int kDim = 2, kNodes = 6;
  static constexpr int kStiffnessPoints = 6;
};
template <>
struct ElementTraits<ElementType::kQuadrilateral8> {
  static constexpr int kDim = 2, kNodes = 8;
  static constexpr int kStiffnessPoints = 9;
};
template <>
struct ElementTraits<ElementType::kQuadrilateral9> {
  static constexpr int kDim = 2, kNodes = 9;
  static constexpr int kStiffnessPoints = 9;
};
template <>
struct ElementTraits<ElementType::kTetrahedron10> {
  static constexpr int kDim = 3, kNodes = 10;
  static constexpr int kStiffnessPoints = 14;
};
template <>
struct ElementTraits<ElementType::kHexahedron20> {
  static constexpr int kDim = 3, kNodes = 20;
  static constexpr int kStiffnessPoints = 27;
};
template <>
struct ElementTraits<ElementType::kHexahedron27> {
  static constexpr int kDim = 3, kNodes = 27;
  static constexpr int kStiffnessPoints = 27;
};

template <ElementType T>
using ElementTag = std::integral_constant<ElementType, T>;

// Calls f(ElementTag<T>{}) for the run-time element type, so the kernels can use
// fixed-size Eigen matrices.
template <class F>
decltype(auto) DispatchElement(ElementType type, F&& f) {
  switch (type) {
    case ElementType::kTriangle3:
      return f(ElementTag<ElementType::kTriangle3>{});
    case ElementType::kQuadrilateral4:
      return f(ElementTag<ElementType::kQuadrilateral4>{});
    case ElementType::kTetrahedron4:
      return f(ElementTag<ElementType::kTetrahedron4>{});
    case ElementType::kTriangle6:
      return f(ElementTag<ElementType::kTriangle6>{});
    case ElementType::kQuadrilateral8:
      return f(ElementTag<ElementType::kQuadrilateral8>{});
    case ElementType::kQuadrilateral9:
      return f(ElementTag<ElementType::kQuadrilateral9>{});
    case ElementType::kTetrahedron10:
      return f(ElementTag<ElementType::kTetrahedron10>{});
    case ElementType::kHexahedron20:
      return f(ElementTag<ElementType::kHexahedron20>{});
    case ElementType::kHexahedron27:
      return f(ElementTag<ElementType::kHexahedron27>{});
    case ElementType::kHexahedron8:
    default:
      return f(ElementTag<ElementType::kHexahedron8>{});
  }
}

// Values N_a(xi) (size nodes) and derivatives dN_a/dxi_k (row-major nodes x ref_dim) of
// the shape functions of an element or facet with `nodes` nodes in `ref_dim` reference
// dimensions. Supported (ref_dim, nodes): (1,2) line, (2,3) triangle, (2,4)
// quadrilateral, (3,4) tetrahedron, (3,8) hexahedron, and the quadratic (1,3), (2,6),
// (2,8), (2,9), (3,10), (3,20), (3,27) of quadratic_element.hpp.
void EvaluateShape(int ref_dim, int nodes, const double* xi, double* N, double* dN_dxi);

struct QuadratureRule {
  Eigen::MatrixXd points;  // ref_dim x number of points
  Eigen::VectorXd weights;
  int NumPoints() const { return static_cast<int>(weights.size()); }
};

enum class RulePurpose { kStiffness, kMass };
// The rules of the table above for a volume element.
const QuadratureRule& ElementRule(ElementType type, RulePurpose purpose);
// The rule for a facet (exact for N_a N_b on affine facets).
const QuadratureRule& FacetRule(FacetType type);

// Shape data of an element type at the points of a rule, in fixed-size matrices.
template <ElementType T>
struct ElementShapeData {
  static constexpr int kDim = ElementTraits<T>::kDim;
  static constexpr int kNodes = ElementTraits<T>::kNodes;
  using ShapeVector = Eigen::Matrix<double, kNodes, 1>;
  using ShapeGradient = Eigen::Matrix<double, kNodes, kDim>;  // dN_a / dxi_k
  std::vector<double> weights;
  std::vector<ShapeVector> N;
  std::vector<ShapeGradient> dN_dxi;

  explicit ElementShapeData(RulePurpose purpose) {
    const QuadratureRule& rule = ElementRule(T, purpose);
    for (int q = 0; q < rule.NumPoints(); ++q) {
      ShapeVector values;
      Eigen::Matrix<double, kNodes, kDim, Eigen::RowMajor> gradient;
      EvaluateShape(kDim, kNodes, rule.points.col(q).data(), values.data(),
                    gradient.data());
      weights.push_back(rule.weights(q));
      N.push_back(values);
      dN_dxi.push_back(gradient);
    }
  }
  int NumPoints() const { return static_cast<int>(weights.size()); }
};

// The shape data is built once per (type, purpose) and shared.
template <ElementType T>
const ElementShapeData<T>& ShapeData(RulePurpose purpose) {
  static const ElementShapeData<T> stiffness(RulePurpose::kStiffness);
  static const ElementShapeData<T> mass(RulePurpose::kMass);
  return purpose == RulePurpose::kStiffness ? stiffness : mass;
}

// Coordinates of the nodes of element e as a dim x nodes matrix.
template <ElementType T>
Eigen::Matrix<double, ElementTraits<T>::kDim, ElementTraits<T>::kNodes>
ElementCoordinates(const Mesh& mesh, int e) {
  Eigen::Matrix<double, ElementTraits<T>::kDim, ElementTraits<T>::kNodes> X;
  for (int a = 0; a < ElementTraits<T>::kNodes; ++a)
    X.col(a) = mesh.nodes.col(mesh.elements(a, e));
  return X;
}

}  // namespace contact::internal
