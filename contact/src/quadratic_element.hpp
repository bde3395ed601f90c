// Quadratic reference elements: node layouts, shape functions and quadrature rules.
//
// Shape functions (xi on the reference domains of reference_element.hpp):
//   simplices (Triangle6, Tetrahedron10) in barycentric coordinates L_i:
//     corner i: N = L_i (2 L_i - 1),   mid-edge (i, j): N = 4 L_i L_j;
//   Lagrange tensor products (Line3, Quadrilateral9, Hexahedron27), node at c in
//   {-1, 0, 1}^d: N = prod_k l_(c_k)(xi_k) with l_-1 = xi (xi - 1) / 2, l_0 = 1 - xi^2,
//   l_1 = xi (xi + 1) / 2;
//   serendipity (Quadrilateral8, Hexahedron20): corner c in {-1, 1}^d:
//     N = prod_k (1 + c_k xi_k) / 2^d * (sum_k c_k xi_k - d + 1);
//   mid-edge with c_m = 0: N = (1 - xi_m^2) prod_(k != m) (1 + c_k xi_k) / 2^(d-1).
// Derivatives are carried along exactly (forward-mode, first order).
#pragma once

#include <vector>

#include "contact/mesh.hpp"

namespace contact::internal {

// For each node of a quadratic element or facet with `nodes` nodes in `ref_dim`
// reference dimensions (gmsh order): the local corners whose mean is the node's
// reference position ({a} for corner a, two corners for a mid-edge node, four for a
// face centre, all for a volume centre). Empty for linear elements.
const std::vector<std::vector<int>>& NodeCorners(int ref_dim, int nodes);

// Reference coordinates of the nodes (ref_dim x nodes, column-major), for every element
// and facet of reference_element.hpp.
std::vector<double> ReferenceNodes(int ref_dim, int nodes);

// Shape functions of the quadratic elements and facets; false if (ref_dim, nodes) is not
// one of them.
bool EvaluateQuadraticShape(int ref_dim, int nodes, const double* xi, double* N,
                            double* dN_dxi);

// The permutation of all nodes that maps the corners by `corner_map` (node a -> node
// result[a]), mid-edge/face nodes following their corners.
std::vector<int> ExtendCornerPermutation(int ref_dim, int nodes,
                                         const std::vector<int>& corner_map);

}  // namespace contact::internal
