#include "contact/quadratic_mesh.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadratic_element.hpp"

namespace contact {
namespace {

// New nodes keyed by their sorted corner (mesh node) sets, each at the corners' mean.
class HigherNodes {
 public:
  explicit HigherNodes(const Mesh& linear) : linear_(linear) {
    for (int i = 0; i < linear.NumNodes(); ++i) positions_.push_back(linear.nodes.col(i));
  }

  // The node at the mean of the mesh nodes `corners` (created on first request).
  int NodeOf(std::vector<int> corners) {
    if (corners.size() == 1) return corners[0];
    std::sort(corners.begin(), corners.end());
    const auto it = index_.find(corners);
    if (it != index_.end()) return it->second;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(linear_.dim);
    for (const int c : corners) x += linear_.nodes.col(c);
    positions_.push_back(x / static_cast<double>(corners.size()));
    const int node = static_cast<int>(positions_.size()) - 1;
    index_.emplace(std::move(corners), node);
    return node;
  }

  // The nodes of an element or facet with `nodes` nodes in `ref_dim` reference
  // dimensions, given its corners.
  std::vector<int> Nodes(int ref_dim, int nodes, const int* corner_nodes) {
    std::vector<int> result;
    for (const auto& local : internal::NodeCorners(ref_dim, nodes)) {
      std::vector<int> corners;
      for (const int a : local) corners.push_back(corner_nodes[a]);
      result.push_back(NodeOf(corners));
    }
    return result;
  }

  Eigen::MatrixXd Positions() const {
    Eigen::MatrixXd x(linear_.dim, static_cast<Eigen::Index>(positions_.size()));
    for (std::size_t i = 0; i < positions_.size(); ++i)
      x.col(static_cast<Eigen::Index>(i)) = positions_[i];
    return x;
  }

 private:
  const Mesh& linear_;
  std::vector<Eigen::VectorXd> positions_;
  std::map<std::vector<int>, int> index_;
};

}  // namespace

Mesh MakeQuadraticMesh(const Mesh& linear, ElementType quadratic) {
  if (ElementOrder(quadratic) != 2 || LinearElementOf(quadratic) != linear.element_type)
    throw std::invalid_argument(
        std::string("MakeQuadraticMesh: cannot make ") + ToString(quadratic) +
        " elements from " + ToString(linear.element_type) +
        " (expected Triangle6 from Triangle3, Quadrilateral8/9 from Quadrilateral4, "
        "Tetrahedron10 from Tetrahedron4, Hexahedron20/27 from Hexahedron8)");
  ValidateMesh(linear);
  Mesh mesh;
  mesh.dim = linear.dim;
  mesh.element_type = quadratic;
  mesh.element_tags = linear.element_tags;
  HigherNodes higher(linear);
  const int nen = NodesPerElement(quadratic);
  mesh.elements.resize(nen, linear.NumElements());
  for (int e = 0; e < linear.NumElements(); ++e) {
    const std::vector<int> nodes =
        higher.Nodes(linear.dim, nen, linear.elements.col(e).data());
    for (int a = 0; a < nen; ++a) mesh.elements(a, e) = nodes[static_cast<size_t>(a)];
  }
  const FacetType facet_type = FacetTypeOf(quadratic);
  const int facet_nodes = NodesPerFacet(facet_type);
  for (const auto& [name, group] : linear.boundary_groups) {
    BoundaryFacets facets;
    facets.type = facet_type;
    facets.connectivity.resize(facet_nodes, group.NumFacets());
    for (int f = 0; f < group.NumFacets(); ++f) {
      const std::vector<int> nodes =
          higher.Nodes(linear.dim - 1, facet_nodes, group.connectivity.col(f).data());
      for (int a = 0; a < facet_nodes; ++a)
        facets.connectivity(a, f) = nodes[static_cast<size_t>(a)];
    }
    mesh.boundary_groups[name] = std::move(facets);
  }
  mesh.nodes = higher.Positions();
  ValidateMesh(mesh);
  return mesh;
}

}  // namespace contact
