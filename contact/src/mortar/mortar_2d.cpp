// Dual mortar constraints between 2D bodies (contact/mortar.hpp): segment pairing by an
// R-tree, projection along the slave segment normal, exact Gauss integration.
#include <algorithm>
#include <array>
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/box.hpp>
#include <boost/geometry/geometries/point.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "contact/contact_boundary.hpp"
#include "contact/mortar.hpp"

namespace contact {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using Point = bg::model::point<double, 2, bg::cs::cartesian>;
using Box = bg::model::box<Point>;

/// A straight boundary segment of one body: its two mesh nodes, their reference
/// positions, its length and its outward unit normal.
struct Segment {
  std::array<int, 2> node{};
  Eigen::Vector2d a, b, normal;
  double length = 0.0;
};

/// The segments of a group, with outward normals oriented like the nodal normals.
std::vector<Segment> Segments(const Mesh& mesh, const std::string& group) {
  const BoundaryFacets& facets = mesh.BoundaryGroup(group);
  const std::vector<int> nodes = facets.Nodes();
  const Eigen::MatrixXd nodal = OutwardNodalNormals(mesh, group);
  std::map<int, int> column;
  for (size_t k = 0; k < nodes.size(); ++k) column[nodes[k]] = static_cast<int>(k);
  std::vector<Segment> segments;
  for (int f = 0; f < facets.NumFacets(); ++f) {
    Segment s;
    s.node = {facets.connectivity(0, f), facets.connectivity(1, f)};
    s.a = mesh.nodes.col(s.node[0]).head<2>();
    s.b = mesh.nodes.col(s.node[1]).head<2>();
    s.length = (s.b - s.a).norm();
    const Eigen::Vector2d t = (s.b - s.a) / s.length;
    s.normal = Eigen::Vector2d(t.y(), -t.x());
    const Eigen::Vector2d average =
        nodal.col(column[s.node[0]]).head<2>() + nodal.col(column[s.node[1]]).head<2>();
    if (s.normal.dot(average) < 0.0) s.normal = -s.normal;
    segments.push_back(s);
  }
  return segments;
}

Box Bounds(const Segment& s, double margin) {
  return Box(
      Point(std::min(s.a.x(), s.b.x()) - margin, std::min(s.a.y(), s.b.y()) - margin),
      Point(std::max(s.a.x(), s.b.x()) + margin, std::max(s.a.y(), s.b.y()) + margin));
}

/// Integrals of one interface, by slave node: D_jj and the row M_j. of the mortar matrix.
struct SlaveRow {
  double D = 0.0;
  std::map<int, double> M;  // master node -> M_jk
};

/// Adds the integrals over the part of slave segment s that master segment m covers
/// (projected along the slave normal): on the slave parameter xi in [0, 1],
///   N = (1 - xi, xi), Phi = (2 - 3 xi, 3 xi - 1) (dual basis of the linear segment),
/// and the master parameter eta is affine in xi. The integrands are at most quadratic:
/// 2-point Gauss is exact.
void IntegratePair(const Segment& s, const Segment& m, double thickness,
                   double search_distance, std::map<int, SlaveRow>* rows) {
  if (s.normal.dot(m.normal) >= 0.0) return;  // not facing each other
  const Eigen::Vector2d t = (s.b - s.a) / s.length;
  const double xi_c = (m.a - s.a).dot(t) / s.length, xi_d = (m.b - s.a).dot(t) / s.length;
  if (std::abs(xi_d - xi_c) < 1e-12) return;  // master segment along the slave normal
  const double lo = std::max(0.0, std::min(xi_c, xi_d));
  const double hi = std::min(1.0, std::max(xi_c, xi_d));
  if (hi - lo <= 1e-12) return;
  const double d_c = (m.a - s.a).dot(s.normal), d_d = (m.b - s.a).dot(s.normal);
  auto distance = [&](double xi) {
    const double eta = (xi - xi_c) / (xi_d - xi_c);
    return std::abs(d_c + eta * (d_d - d_c));
  };
  if (std::min(distance(lo), distance(hi)) > search_distance) return;
  const double gauss = 1.0 / std::sqrt(3.0);
  for (double g : {-gauss, gauss}) {
    const double xi = lo + 0.5 * (hi - lo) * (1.0 + g);
    const double w = 0.5 * (hi - lo) * s.length * thickness;
    const double eta = (xi - xi_c) / (xi_d - xi_c);
    const double N[2] = {1.0 - xi, xi}, Phi[2] = {2.0 - 3.0 * xi, 3.0 * xi - 1.0};
    const double Nm[2] = {1.0 - eta, eta};
    for (int j = 0; j < 2; ++j) {
      SlaveRow& row = (*rows)[s.node[j]];
      row.D += w * N[j];
      for (int k = 0; k < 2; ++k) row.M[m.node[k]] += w * Phi[j] * Nm[k];
    }
  }
}

void CheckInterface(const std::vector<Body>& bodies, const MortarInterface& in,
                    const std::string& key) {
  const int n = static_cast<int>(bodies.size());
  if (in.slave_body < 0 || in.slave_body >= n || in.master_body < 0 ||
      in.master_body >= n)
    throw std::invalid_argument(key + ": body index out of range [0, " +
                                std::to_string(n) + ")");
  if (in.slave_body == in.master_body)
    throw std::invalid_argument(key + ": slave and master are the same body '" +
                                bodies[static_cast<size_t>(in.slave_body)].name +
                                "' (self contact is not supported)");
  for (int b : {in.slave_body, in.master_body}) {
    const Mesh& mesh = bodies[static_cast<size_t>(b)].body.mesh();
    if (mesh.dim != 2)
      throw std::invalid_argument(key + ": body '" + bodies[static_cast<size_t>(b)].name +
                                  "' is 3D; mortar contact is implemented in 2D only");
    const std::string& group = b == in.slave_body ? in.slave_group : in.master_group;
    try {
      mesh.BoundaryGroup(group);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(key + ": body '" + bodies[static_cast<size_t>(b)].name +
                                  "': " + e.what());
    }
  }
}

/// The slave rows of one interface, keyed by slave node.
std::map<int, SlaveRow> IntegrateInterface(const std::vector<Body>& bodies,
                                           const MortarInterface& in) {
  const ElasticBody& slave = bodies[static_cast<size_t>(in.slave_body)].body;
  const ElasticBody& master = bodies[static_cast<size_t>(in.master_body)].body;
  const std::vector<Segment> slave_segments = Segments(slave.mesh(), in.slave_group);
  const std::vector<Segment> master_segments = Segments(master.mesh(), in.master_group);
  double longest_master = 0.0;
  std::vector<std::pair<Box, int>> boxes;
  for (size_t k = 0; k < master_segments.size(); ++k) {
    longest_master = std::max(longest_master, master_segments[k].length);
    boxes.emplace_back(Bounds(master_segments[k], 0.0), static_cast<int>(k));
  }
  const bgi::rtree<std::pair<Box, int>, bgi::quadratic<16>> tree(boxes.begin(),
                                                                 boxes.end());
  std::map<int, SlaveRow> rows;
  std::vector<std::pair<Box, int>> found;
  for (const Segment& s : slave_segments) {
    const double margin = in.search_distance > 0.0 ? in.search_distance
                                                   : std::max(s.length, longest_master);
    found.clear();
    tree.query(bgi::intersects(Bounds(s, margin)), std::back_inserter(found));
    for (const auto& [box, k] : found) {
      const Segment& m = master_segments[static_cast<size_t>(k)];
      const double distance =
          in.search_distance > 0.0 ? in.search_distance : std::max(s.length, m.length);
      IntegratePair(s, m, slave.IntegrationFactor(), distance, &rows);
    }
  }
  return rows;
}

/// Size of the slave surface: the diagonal of its bounding box [m].
double SurfaceSize(const Mesh& mesh, const std::string& group) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(HUGE_VAL), hi = -lo;
  for (int node : mesh.BoundaryGroup(group).Nodes()) {
    lo = lo.cwiseMin(mesh.nodes.col(node).head<2>());
    hi = hi.cwiseMax(mesh.nodes.col(node).head<2>());
  }
  return (hi - lo).norm();
}

}  // namespace

MortarConstraints AssembleMortar(const std::vector<Body>& bodies,
                                 const BodySystem& system,
                                 const std::vector<MortarInterface>& interfaces) {
  std::vector<Eigen::Triplet<double>> triplets, tangential;
  std::vector<double> friction;
  std::vector<double> gaps, weights;
  std::vector<Eigen::Vector2d> normals;
  MortarConstraints out;
  for (size_t i = 0; i < interfaces.size(); ++i) {
    const MortarInterface& in = interfaces[i];
    const std::string key = "contact pair " + std::to_string(i);
    CheckInterface(bodies, in, key);
    if (!(in.friction >= 0.0) || !std::isfinite(in.friction))
      throw std::invalid_argument(key + ": friction = " + std::to_string(in.friction) +
                                  " (need a finite value >= 0)");
    const Body& slave = bodies[static_cast<size_t>(in.slave_body)];
    const Mesh& slave_mesh = slave.body.mesh();
    const Mesh& master_mesh = bodies[static_cast<size_t>(in.master_body)].body.mesh();
    const Eigen::MatrixXd nodal = OutwardNodalNormals(slave_mesh, in.slave_group);
    const std::vector<int> group_nodes = slave_mesh.BoundaryGroup(in.slave_group).Nodes();
    const double overlap_tolerance = 1e-9 * SurfaceSize(slave_mesh, in.slave_group);
    const std::map<int, SlaveRow> rows = IntegrateInterface(bodies, in);
    for (size_t c = 0; c < group_nodes.size(); ++c) {
      const auto found = rows.find(group_nodes[c]);
      if (found == rows.end() || found->second.D <= 0.0) continue;  // not covered
      const int node = group_nodes[c];
      const SlaveRow& row = found->second;
      const Eigen::Vector2d n = nodal.col(static_cast<Eigen::Index>(c)).head<2>();
      const Eigen::Vector2d t(-n.y(), n.x());
      const int r = static_cast<int>(gaps.size());
      Eigen::Vector2d projected = Eigen::Vector2d::Zero();
      for (int a = 0; a < 2; ++a) {
        triplets.emplace_back(r, system.GlobalDof(in.slave_body, node, a), -n(a));
        tangential.emplace_back(r, system.GlobalDof(in.slave_body, node, a), -t(a));
      }
      for (const auto& [k, Mjk] : row.M) {
        projected += Mjk / row.D * master_mesh.nodes.col(k).head<2>();
        for (int a = 0; a < 2; ++a) {
          triplets.emplace_back(r, system.GlobalDof(in.master_body, k, a),
                                Mjk / row.D * n(a));
          tangential.emplace_back(r, system.GlobalDof(in.master_body, k, a),
                                  Mjk / row.D * t(a));
        }
      }
      const Eigen::Vector2d x = slave_mesh.nodes.col(node).head<2>();
      const double gap = n.dot(projected - x);
      if (gap < -overlap_tolerance) {
        std::ostringstream message;
        message << key << ": bodies '" << slave.name << "' and '"
                << bodies[static_cast<size_t>(in.master_body)].name << "' overlap by "
                << -gap << " m at node " << node << " (" << x.x() << ", " << x.y()
                << ") of group '" << in.slave_group << "' of '" << slave.name
                << "' (tolerance " << overlap_tolerance << " m)";
        throw std::invalid_argument(message.str());
      }
      gaps.push_back(gap);
      weights.push_back(row.D);
      friction.push_back(in.friction);
      normals.push_back(n);
      out.interface.push_back(static_cast<int>(i));
      out.slave_body.push_back(in.slave_body);
      out.slave_node.push_back(node);
    }
    if (std::find(out.interface.begin(), out.interface.end(), static_cast<int>(i)) ==
        out.interface.end())
      throw std::invalid_argument(key + ": no node of group '" + in.slave_group +
                                  "' of body '" + slave.name + "' faces group '" +
                                  in.master_group + "' of body '" +
                                  bodies[static_cast<size_t>(in.master_body)].name +
                                  "' within the search distance");
  }
  const int m = static_cast<int>(gaps.size());
  out.B.resize(m, system.NumDofs());
  out.B.setFromTriplets(triplets.begin(), triplets.end());
  out.T.resize(m, system.NumDofs());
  out.T.setFromTriplets(tangential.begin(), tangential.end());
  out.friction = Eigen::Map<const Vector>(friction.data(), m);
  out.initial_gap = Eigen::Map<const Vector>(gaps.data(), m);
  out.weight = Eigen::Map<const Vector>(weights.data(), m);
  out.normals.resize(2, m);
  for (int j = 0; j < m; ++j) out.normals.col(j) = normals[static_cast<size_t>(j)];
  return out;
}

}  // namespace contact
