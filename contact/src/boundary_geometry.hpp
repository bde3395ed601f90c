// Geometry of boundary facets: integration points, surface measure and outward normals.
#pragma once

#include <string>
#include <vector>

#include "contact/mesh.hpp"

namespace contact::internal {

// Element e contains facet f of the group iff all nodes of f are nodes of e. Returns, for
// every facet of the group, one element containing it; throws std::invalid_argument if a
// facet is not a face of any element.
std::vector<int> FindFacetElements(const Mesh& mesh, const BoundaryFacets& facets,
                                   const std::string& group);

// One integration point of a facet.
struct FacetPoint {
  Eigen::VectorXd N;       // facet shape functions at the point (size nodes per facet)
  Eigen::VectorXd x;       // physical coordinates [m]
  Eigen::VectorXd normal;  // outward unit normal
  double weight_dS = 0;    // quadrature weight times the surface Jacobian [m or m^2]
};

// The integration points of every facet of a group, with outward normals: the facet's
// geometric normal (dx/dxi rotated in 2D, dx/dxi1 x dx/dxi2 in 3D) is flipped if it
// points towards the centroid of the adjacent element. facet_points[f] lists the points
// of facet f.
std::vector<std::vector<FacetPoint>> FacetIntegrationPoints(const Mesh& mesh,
                                                            const std::string& group);

}  // namespace contact::internal
