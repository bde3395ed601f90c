#include "boundary_geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "reference_element.hpp"

namespace contact::internal {

namespace {

// The faces of each element type as cycles of local corner nodes (gmsh numbering); a
// quadratic element has the faces of its linear element.
const std::vector<std::vector<int>>& LocalFaces(ElementType type) {
  static const std::vector<std::vector<int>> triangle = {{0, 1}, {1, 2}, {2, 0}};
  static const std::vector<std::vector<int>> quadrilateral = {
      {0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const std::vector<std::vector<int>> tetrahedron = {
      {0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  static const std::vector<std::vector<int>> hexahedron = {
      {0, 3, 2, 1}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};
  switch (LinearElementOf(type)) {
    case ElementType::kTriangle3:
      return triangle;
    case ElementType::kQuadrilateral4:
      return quadrilateral;
    case ElementType::kTetrahedron4:
      return tetrahedron;
    case ElementType::kHexahedron8:
    default:
      return hexahedron;
  }
}

// True if `facet` lists the corners of the local face `face` of element e in cyclic
// order, in either direction (a quadrilateral given as 0-2-1-3 is a bow tie, not the
// face).
bool IsFaceOf(const Mesh& mesh, int e, const std::vector<int>& face, const int* facet) {
  const int n = static_cast<int>(face.size());
  for (int shift = 0; shift < n; ++shift) {
    bool forward = true, backward = true;
    for (int a = 0; a < n; ++a) {
      forward = forward && facet[a] == mesh.elements(face[(shift + a) % n], e);
      backward = backward && facet[a] == mesh.elements(face[(shift - a + n) % n], e);
    }
    if (forward || backward) return true;
  }
  return false;
}

// The facet's nodes past its corners (mid-edge and centre nodes) are nodes of element e.
bool HasHigherNodes(const Mesh& mesh, int e, const int* facet, int corners, int nodes) {
  const auto element = mesh.elements.col(e);
  for (int a = corners; a < nodes; ++a)
    if (std::find(element.data(), element.data() + element.size(), facet[a]) ==
        element.data() + element.size())
      return false;
  return true;
}

}  // namespace

std::vector<int> FindFacetElements(const Mesh& mesh, const BoundaryFacets& facets,
                                   const std::string& group) {
  // Node -> elements incidence in compressed rows.
  const int num_nodes = mesh.NumNodes();
  const int nen = static_cast<int>(mesh.elements.rows());
  std::vector<int> offsets(num_nodes + 1, 0);
  for (int e = 0; e < mesh.NumElements(); ++e)
    for (int a = 0; a < nen; ++a) ++offsets[mesh.elements(a, e) + 1];
  for (int i = 0; i < num_nodes; ++i) offsets[i + 1] += offsets[i];
  std::vector<int> incident(offsets.back());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (int e = 0; e < mesh.NumElements(); ++e)
    for (int a = 0; a < nen; ++a) incident[fill[mesh.elements(a, e)]++] = e;

  const auto& faces = LocalFaces(mesh.element_type);
  std::vector<int> owner(facets.NumFacets(), -1);
  for (int f = 0; f < facets.NumFacets(); ++f) {
    const int* facet = facets.connectivity.col(f).data();
    auto describe = [&] {
      std::ostringstream text;
      text << "boundary group '" << group << "': facet " << f << " (nodes";
      for (int b = 0; b < facets.connectivity.rows(); ++b) text << ' ' << facet[b];
      text << ")";
      return text.str();
    };
    for (int k = offsets[facet[0]]; k < offsets[facet[0] + 1]; ++k) {
      const int e = incident[k];
      for (const auto& face : faces) {
        const int corners = CornersPerFacet(facets.type);
        if (static_cast<int>(face.size()) != corners || !IsFaceOf(mesh, e, face, facet) ||
            !HasHigherNodes(mesh, e, facet, corners,
                            static_cast<int>(facets.connectivity.rows())))
          continue;
        if (owner[f] >= 0)
          throw std::invalid_argument(describe() + " is an interior face shared by " +
                                      mesh.DescribeElement(owner[f]) + " and " +
                                      mesh.DescribeElement(e) +
                                      "; expected a face on the boundary of the body");
        owner[f] = e;
      }
    }
    if (owner[f] < 0)
      throw std::invalid_argument(describe() +
                                  " is not a face of any element of the mesh");
  }
  return owner;
}

std::vector<std::vector<FacetPoint>> FacetIntegrationPoints(const Mesh& mesh,
                                                            const std::string& group) {
  const BoundaryFacets& facets = mesh.BoundaryGroup(group);
  const std::vector<int> owner = FindFacetElements(mesh, facets, group);
  const QuadratureRule& rule = FacetRule(facets.type);
  const int dim = mesh.dim;
  const int ref_dim = dim - 1;
  const int nodes = NodesPerFacet(facets.type);

  std::vector<std::vector<FacetPoint>> result(facets.NumFacets());
  Eigen::VectorXd N(nodes);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dN(nodes,
                                                                            ref_dim);
  Eigen::MatrixXd X(dim, nodes);
  for (int f = 0; f < facets.NumFacets(); ++f) {
    for (int a = 0; a < nodes; ++a) X.col(a) = mesh.nodes.col(facets.connectivity(a, f));
    std::vector<FacetPoint>& points = result[f];
    Eigen::VectorXd normal_sum = Eigen::VectorXd::Zero(dim);
    for (int q = 0; q < rule.NumPoints(); ++q) {
      EvaluateShape(ref_dim, nodes, rule.points.col(q).data(), N.data(), dN.data());
      const Eigen::MatrixXd tangents = X * dN;  // dim x ref_dim: dx/dxi_k
      Eigen::VectorXd area_normal(dim);         // |area_normal| = surface Jacobian
      if (dim == 2) {
        area_normal << tangents(1, 0), -tangents(0, 0);
      } else {
        area_normal =
            Eigen::Vector3d(tangents.col(0)).cross(Eigen::Vector3d(tangents.col(1)));
      }
      if (!(area_normal.norm() > 0))
        throw std::invalid_argument("boundary group '" + group + "': facet " +
                                    std::to_string(f) +
                                    " is degenerate (zero length/area, expected > 0)");
      FacetPoint point;
      point.N = N;
      point.x = X * N;
      point.weight_dS = rule.weights(q) * area_normal.norm();
      point.normal = area_normal / area_normal.norm();
      normal_sum += rule.weights(q) * area_normal;
      points.push_back(point);
    }
    // Outward: away from the adjacent element's centroid.
    const Eigen::VectorXd facet_centroid = X.rowwise().mean();
    if (normal_sum.dot(facet_centroid - mesh.ElementCentroid(owner[f])) < 0)
      for (FacetPoint& point : points) point.normal = -point.normal;
  }
  return result;
}

}  // namespace contact::internal
