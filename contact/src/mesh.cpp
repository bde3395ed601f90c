#include "contact/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "boundary_geometry.hpp"
#include "reference_element.hpp"

namespace contact {

const char* ToString(ElementType type) {
  switch (type) {
    case ElementType::kTriangle3:
      return "Triangle3";
    case ElementType::kQuadrilateral4:
      return "Quadrilateral4";
    case ElementType::kTetrahedron4:
      return "Tetrahedron4";
    case ElementType::kHexahedron8:
      return "Hexahedron8";
    case ElementType::kTriangle6:
      return "Triangle6";
    case ElementType::kQuadrilateral8:
      return "Quadrilateral8";
    case ElementType::kQuadrilateral9:
      return "Quadrilateral9";
    case ElementType::kTetrahedron10:
      return "Tetrahedron10";
    case ElementType::kHexahedron20:
      return "Hexahedron20";
    case ElementType::kHexahedron27:
      return "Hexahedron27";
  }
  return "unknown";
}

const char* ToString(FacetType type) {
  switch (type) {
    case FacetType::kLine2:
      return "Line2";
    case FacetType::kTriangle3:
      return "Triangle3";
    case FacetType::kQuadrilateral4:
      return "Quadrilateral4";
    case FacetType::kLine3:
      return "Line3";
    case FacetType::kTriangle6:
      return "Triangle6";
    case FacetType::kQuadrilateral8:
      return "Quadrilateral8";
    case FacetType::kQuadrilateral9:
      return "Quadrilateral9";
  }
  return "unknown";
}

ElementType LinearElementOf(ElementType type) {
  switch (type) {
    case ElementType::kTriangle6:
      return ElementType::kTriangle3;
    case ElementType::kQuadrilateral8:
    case ElementType::kQuadrilateral9:
      return ElementType::kQuadrilateral4;
    case ElementType::kTetrahedron10:
      return ElementType::kTetrahedron4;
    case ElementType::kHexahedron20:
    case ElementType::kHexahedron27:
      return ElementType::kHexahedron8;
    default:
      return type;
  }
}

int ElementOrder(ElementType type) { return LinearElementOf(type) == type ? 1 : 2; }

int Dimension(ElementType type) {
  const ElementType linear = LinearElementOf(type);
  return (linear == ElementType::kTriangle3 || linear == ElementType::kQuadrilateral4)
             ? 2
             : 3;
}

int NodesPerElement(ElementType type) {
  switch (type) {
    case ElementType::kTriangle3:
      return 3;
    case ElementType::kQuadrilateral4:
    case ElementType::kTetrahedron4:
      return 4;
    case ElementType::kHexahedron8:
      return 8;
    case ElementType::kTriangle6:
      return 6;
    case ElementType::kQuadrilateral8:
      return 8;
    case ElementType::kQuadrilateral9:
      return 9;
    case ElementType::kTetrahedron10:
      return 10;
    case ElementType::kHexahedron20:
      return 20;
    case ElementType::kHexahedron27:
      return 27;
  }
  return 0;
}

int CornersPerElement(ElementType type) { return NodesPerElement(LinearElementOf(type)); }

int NodesPerFacet(FacetType type) {
  switch (type) {
    case FacetType::kLine2:
      return 2;
    case FacetType::kTriangle3:
      return 3;
    case FacetType::kQuadrilateral4:
      return 4;
    case FacetType::kLine3:
      return 3;
    case FacetType::kTriangle6:
      return 6;
    case FacetType::kQuadrilateral8:
      return 8;
    case FacetType::kQuadrilateral9:
      return 9;
  }
  return 0;
}

int CornersPerFacet(FacetType type) {
  switch (type) {
    case FacetType::kLine2:
    case FacetType::kLine3:
      return 2;
    case FacetType::kTriangle3:
    case FacetType::kTriangle6:
      return 3;
    default:
      return 4;
  }
}

FacetType FacetTypeOf(ElementType type) {
  switch (type) {
    case ElementType::kTriangle3:
    case ElementType::kQuadrilateral4:
      return FacetType::kLine2;
    case ElementType::kTetrahedron4:
      return FacetType::kTriangle3;
    case ElementType::kHexahedron8:
      return FacetType::kQuadrilateral4;
    case ElementType::kTriangle6:
    case ElementType::kQuadrilateral8:
    case ElementType::kQuadrilateral9:
      return FacetType::kLine3;
    case ElementType::kTetrahedron10:
      return FacetType::kTriangle6;
    case ElementType::kHexahedron20:
      return FacetType::kQuadrilateral8;
    case ElementType::kHexahedron27:
      return FacetType::kQuadrilateral9;
  }
  return FacetType::kLine2;
}

std::vector<int> BoundaryFacets::Nodes() const {
  std::vector<int> nodes(connectivity.data(), connectivity.data() + connectivity.size());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

bool Mesh::HasBoundaryGroup(const std::string& name) const {
  return boundary_groups.count(name) > 0;
}

const BoundaryFacets& Mesh::BoundaryGroup(const std::string& name) const {
  const auto it = boundary_groups.find(name);
  if (it == boundary_groups.end()) {
    std::string available;
    for (const auto& [group_name, facets] : boundary_groups)
      available += (available.empty() ? "'" : ", '") + group_name + "'";
    throw std::invalid_argument(
        "mesh has no boundary group '" + name +
        "' (expected a physical group of dimension " + std::to_string(dim - 1) +
        " named '" + name +
        "'); available groups: " + (available.empty() ? std::string("none") : available));
  }
  return it->second;
}

Eigen::VectorXd Mesh::ElementCentroid(int element) const {
  Eigen::VectorXd centroid = Eigen::VectorXd::Zero(dim);
  for (int a = 0; a < elements.rows(); ++a) centroid += nodes.col(elements(a, element));
  return centroid / static_cast<double>(elements.rows());
}

std::string Mesh::DescribeElement(int element) const {
  std::string text = "element " + std::to_string(element);
  if (static_cast<int>(element_tags.size()) == NumElements())
    text += " (source tag " + std::to_string(element_tags[element]) + ")";
  return text;
}

namespace {

std::string FormatPoint(const Eigen::VectorXd& x) {
  std::ostringstream out;
  out.precision(6);
  out << '(';
  for (int k = 0; k < x.size(); ++k) out << (k ? ", " : "") << x(k);
  out << ')';
  return out.str();
}

// det(dx/dxi) at every integration point (stiffness and mass rules) must be positive.
template <ElementType T>
void CheckOrientation(const Mesh& mesh) {
  using Traits = internal::ElementTraits<T>;
  for (const internal::RulePurpose purpose :
       {internal::RulePurpose::kStiffness, internal::RulePurpose::kMass}) {
    const auto& shape = internal::ShapeData<T>(purpose);
    for (int e = 0; e < mesh.NumElements(); ++e) {
      const auto X = internal::ElementCoordinates<T>(mesh, e);
      for (int q = 0; q < shape.NumPoints(); ++q) {
        const Eigen::Matrix<double, Traits::kDim, Traits::kDim> J = X * shape.dN_dxi[q];
        const double det = J.determinant();
        if (!(det > 0)) {
          std::ostringstream message;
          message << "inverted element: " << mesh.DescribeElement(e)
                  << " has Jacobian determinant det(dx/dxi) = " << det
                  << " (expected > 0) at integration point " << q << "; element centroid "
                  << FormatPoint(mesh.ElementCentroid(e));
          throw std::invalid_argument(message.str());
        }
      }
    }
  }
}

// Repeated nodes within an element (a collapsed quad keeps det J > 0 at its Gauss points
// but leaves a hole), the same node set twice, and nodes of no element (zero rows of K,
// M).
void CheckConnectivity(const Mesh& mesh) {
  std::set<std::vector<int>> node_sets;
  std::vector<char> used(static_cast<size_t>(mesh.NumNodes()), 0);
  for (int e = 0; e < mesh.NumElements(); ++e) {
    std::vector<int> nodes(mesh.elements.col(e).data(),
                           mesh.elements.col(e).data() + mesh.elements.rows());
    for (int node : nodes) used[static_cast<size_t>(node)] = 1;
    std::sort(nodes.begin(), nodes.end());
    if (std::adjacent_find(nodes.begin(), nodes.end()) != nodes.end())
      throw std::invalid_argument(
          "invalid mesh: degenerate element: " + mesh.DescribeElement(e) +
          " repeats node " +
          std::to_string(*std::adjacent_find(nodes.begin(), nodes.end())));
    if (!node_sets.insert(nodes).second)
      throw std::invalid_argument(
          "invalid mesh: duplicate element: " + mesh.DescribeElement(e) +
          " has the same nodes as an earlier element");
  }
  const auto unused = std::find(used.begin(), used.end(), 0);
  if (unused != used.end())
    throw std::invalid_argument(
        "invalid mesh: unused node " + std::to_string(unused - used.begin()) + " at " +
        FormatPoint(mesh.nodes.col(unused - used.begin())) + " belongs to no element");
}

}  // namespace

void ValidateMesh(const Mesh& mesh) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("invalid mesh: " + what);
  };
  if (mesh.dim != 2 && mesh.dim != 3)
    fail("dim must be 2 or 3, got " + std::to_string(mesh.dim));
  if (Dimension(mesh.element_type) != mesh.dim)
    fail(std::string("element type ") + ToString(mesh.element_type) + " is " +
         std::to_string(Dimension(mesh.element_type)) +
         "D but mesh.dim = " + std::to_string(mesh.dim));
  if (mesh.nodes.rows() != mesh.dim)
    fail("nodes must be dim x N = " + std::to_string(mesh.dim) + " x N, got " +
         std::to_string(mesh.nodes.rows()) + " rows");
  if (mesh.NumNodes() == 0 || mesh.NumElements() == 0)
    fail("expected at least one node and one element, got " +
         std::to_string(mesh.NumNodes()) + " nodes and " +
         std::to_string(mesh.NumElements()) + " elements");
  if (!mesh.nodes.allFinite()) fail("node coordinates contain NaN or Inf");
  if (mesh.elements.rows() != NodesPerElement(mesh.element_type))
    fail(std::string("elements of type ") + ToString(mesh.element_type) + " need " +
         std::to_string(NodesPerElement(mesh.element_type)) + " rows, got " +
         std::to_string(mesh.elements.rows()));
  if (!mesh.element_tags.empty() &&
      static_cast<int>(mesh.element_tags.size()) != mesh.NumElements())
    fail("element_tags must be empty or have one entry per element (" +
         std::to_string(mesh.NumElements()) + "), got " +
         std::to_string(mesh.element_tags.size()));
  if (mesh.elements.minCoeff() < 0 || mesh.elements.maxCoeff() >= mesh.NumNodes())
    fail("element node indices must lie in [0, " + std::to_string(mesh.NumNodes()) +
         "), got range [" + std::to_string(mesh.elements.minCoeff()) + ", " +
         std::to_string(mesh.elements.maxCoeff()) + "]");
  const FacetType facet_type = FacetTypeOf(mesh.element_type);
  for (const auto& [name, facets] : mesh.boundary_groups) {
    if (facets.type != facet_type)
      fail("boundary group '" + name + "' has facets of type " + ToString(facets.type) +
           " but elements of type " + ToString(mesh.element_type) +
           " need facets of type " + ToString(facet_type));
    if (facets.connectivity.rows() != NodesPerFacet(facet_type))
      fail("boundary group '" + name + "' connectivity needs " +
           std::to_string(NodesPerFacet(facet_type)) + " rows, got " +
           std::to_string(facets.connectivity.rows()));
    if (facets.NumFacets() > 0 && (facets.connectivity.minCoeff() < 0 ||
                                   facets.connectivity.maxCoeff() >= mesh.NumNodes()))
      fail("boundary group '" + name + "' has node indices outside [0, " +
           std::to_string(mesh.NumNodes()) + ")");
  }
  CheckConnectivity(mesh);
  internal::DispatchElement(
      mesh.element_type, [&](auto tag) { CheckOrientation<decltype(tag)::value>(mesh); });
}

double BoundaryMeasure(const Mesh& mesh, const std::string& group) {
  double measure = 0;
  for (const auto& points : internal::FacetIntegrationPoints(mesh, group))
    for (const auto& point : points) measure += point.weight_dS;
  return measure;
}

double DomainMeasure(const Mesh& mesh) {
  return internal::DispatchElement(mesh.element_type, [&](auto tag) {
    constexpr ElementType T = decltype(tag)::value;
    const auto& shape = internal::ShapeData<T>(internal::RulePurpose::kMass);
    double measure = 0;
    for (int e = 0; e < mesh.NumElements(); ++e) {
      const auto X = internal::ElementCoordinates<T>(mesh, e);
      for (int q = 0; q < shape.NumPoints(); ++q)
        measure += shape.weights[q] * (X * shape.dN_dxi[q]).determinant();
    }
    return measure;
  });
}

}  // namespace contact
