#include "contact/contact_boundary.hpp"

#include <sstream>
#include <stdexcept>

#include "boundary_geometry.hpp"

namespace contact {
namespace {

// Nodal normals from precomputed facet integration points; `index` maps mesh node ->
// position in the output (-1 if not on the group).
Eigen::MatrixXd AverageNormals(
    const Mesh& mesh, const BoundaryFacets& facets,
    const std::vector<std::vector<internal::FacetPoint>>& points,
    const std::vector<int>& nodes, const std::vector<int>& index,
    const std::string& group) {
  const auto num_nodes = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd normals = Eigen::MatrixXd::Zero(mesh.dim, num_nodes);
  Eigen::VectorXd facet_areas = Eigen::VectorXd::Zero(num_nodes);  // sum_f |int_f n dS|
  for (int f = 0; f < facets.NumFacets(); ++f) {
    Eigen::VectorXd integrated_normal = Eigen::VectorXd::Zero(mesh.dim);  // int_f n dS
    for (const auto& point : points[f])
      integrated_normal += point.weight_dS * point.normal;
    for (int a = 0; a < facets.connectivity.rows(); ++a) {
      normals.col(index[facets.connectivity(a, f)]) += integrated_normal;
      facet_areas(index[facets.connectivity(a, f)]) += integrated_normal.norm();
    }
  }
  for (int k = 0; k < normals.cols(); ++k) {
    const double length = normals.col(k).norm();
    // Facet normals that cancel leave only round-off relative to the facet areas.
    if (!(length > 1e-12 * facet_areas(k))) {
      std::ostringstream message;
      message << "boundary group '" << group << "': the outward normal at node "
              << nodes[k] << " is undefined (the normals of its facets cancel)";
      throw std::invalid_argument(message.str());
    }
    normals.col(k) /= length;
  }
  return normals;
}

std::vector<int> NodeIndex(const Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<int> index(mesh.NumNodes(), -1);
  for (int k = 0; k < static_cast<int>(nodes.size()); ++k) index[nodes[k]] = k;
  return index;
}

// The nodal contact weights w_k = h int N_k dS must be positive for the nodal contact
// conditions to be well posed. They are for linear facets and for the Line3 and
// Quadrilateral9 facets of Triangle6, Quadrilateral8/9 and Hexahedron27; the standard
// Triangle6 facet of Tetrahedron10 has w = 0 at its corners and the serendipity
// Quadrilateral8 facet of Hexahedron20 has w < 0 there (-1/12 of the facet area).
void CheckPositiveWeights(const Mesh& mesh, const ContactBoundary& boundary) {
  const Vector& w = boundary.tributary_area;
  const double scale = w.cwiseAbs().maxCoeff();
  for (int k = 0; k < w.size(); ++k) {
    if (w(k) > 1e-10 * scale) continue;
    std::ostringstream message;
    message << "boundary group '" << boundary.group << "': contact on "
            << ToString(FacetTypeOf(mesh.element_type)) << " facets of "
            << ToString(mesh.element_type) << " elements is not supported: node "
            << boundary.nodes[static_cast<std::size_t>(k)]
            << " has the nodal contact weight int N dS = " << w(k)
            << " (expected > 0); use Hexahedron27, Hexahedron8 or Tetrahedron4 elements "
               "in 3D contact";
    throw std::invalid_argument(message.str());
  }
}

}  // namespace

SparseMatrix ContactBoundary::LumpedBoundaryMatrix() const {
  SparseMatrix A(NumNodes(), NumNodes());
  A.reserve(Eigen::VectorXi::Ones(NumNodes()));
  for (int k = 0; k < NumNodes(); ++k) A.insert(k, k) = tributary_area(k);
  A.makeCompressed();
  return A;
}

ContactBoundary MakeContactBoundary(const ElasticBody& body, const std::string& group) {
  const Mesh& mesh = body.mesh();
  const BoundaryFacets& facets = mesh.BoundaryGroup(group);
  if (facets.NumFacets() == 0)
    throw std::invalid_argument("empty contact set: boundary group '" + group +
                                "' has 0 facets (expected at least 1)");
  const auto points = internal::FacetIntegrationPoints(mesh, group);

  ContactBoundary boundary;
  boundary.group = group;
  boundary.nodes = facets.Nodes();
  boundary.contact_index = NodeIndex(mesh, boundary.nodes);
  const int num_contact = boundary.NumNodes();
  const double h = body.IntegrationFactor();

  // A_kl = h int N_k N_l dS, assembled from facet contributions (triplets: the boundary
  // is one dimension lower, so their number is small).
  std::vector<Eigen::Triplet<double>> triplets;
  const int nodes_per_facet = static_cast<int>(facets.connectivity.rows());
  triplets.reserve(static_cast<std::size_t>(facets.NumFacets()) * nodes_per_facet *
                   nodes_per_facet);
  for (int f = 0; f < facets.NumFacets(); ++f) {
    Eigen::MatrixXd Ae = Eigen::MatrixXd::Zero(nodes_per_facet, nodes_per_facet);
    for (const auto& point : points[f])
      Ae += h * point.weight_dS * point.N * point.N.transpose();
    for (int b = 0; b < nodes_per_facet; ++b)
      for (int a = 0; a < nodes_per_facet; ++a)
        triplets.emplace_back(boundary.contact_index[facets.connectivity(a, f)],
                              boundary.contact_index[facets.connectivity(b, f)],
                              Ae(a, b));
  }
  boundary.boundary_matrix.resize(num_contact, num_contact);
  boundary.boundary_matrix.setFromTriplets(triplets.begin(), triplets.end());
  boundary.tributary_area = boundary.boundary_matrix * Vector::Ones(num_contact);
  CheckPositiveWeights(mesh, boundary);
  boundary.normals =
      AverageNormals(mesh, facets, points, boundary.nodes, boundary.contact_index, group);
  return boundary;
}

Eigen::MatrixXd OutwardNodalNormals(const Mesh& mesh, const std::string& group) {
  const BoundaryFacets& facets = mesh.BoundaryGroup(group);
  const std::vector<int> nodes = facets.Nodes();
  return AverageNormals(mesh, facets, internal::FacetIntegrationPoints(mesh, group),
                        nodes, NodeIndex(mesh, nodes), group);
}

}  // namespace contact
