#include "contact/mesh_generation.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "contact/quadratic_mesh.hpp"
#include "gmsh_model.hpp"
#include "text_format.hpp"

namespace contact {

const char* ToString(Side side) {
  switch (side) {
    case Side::kXMin:
      return "xmin";
    case Side::kXMax:
      return "xmax";
    case Side::kYMin:
      return "ymin";
    case Side::kYMax:
      return "ymax";
    case Side::kZMin:
      return "zmin";
    case Side::kZMax:
      return "zmax";
  }
  return "unknown";
}

const char* GroupName(BoundaryRole role) {
  switch (role) {
    case BoundaryRole::kFixed:
      return kFixedGroup;
    case BoundaryRole::kLoad:
      return kLoadGroup;
    case BoundaryRole::kContact:
      return kContactGroup;
    case BoundaryRole::kNone:
      break;
  }
  return "";
}

std::string CheckGridLimits(const std::vector<double>& size,
                            const std::vector<double>& cells) {
  const auto str = internal::FormatShort;
  double count = 1, h_min = std::numeric_limits<double>::infinity(), h_max = 0;
  for (std::size_t k = 0; k < size.size() && k < cells.size(); ++k) {
    if (!(size[k] > 0 && size[k] <= kMaxGridExtent))
      return "size " + str(size[k]) + " m lies outside (0, " + str(kMaxGridExtent) +
             "] m";
    if (!(cells[k] >= 1 && cells[k] <= kMaxGeneratedCells))
      return "cells " + str(cells[k]) + " lies outside [1, " + str(kMaxGeneratedCells) +
             "]";
    count *= cells[k];
    h_min = std::min(h_min, size[k] / cells[k]);
    h_max = std::max(h_max, size[k] / cells[k]);
  }
  if (count > kMaxGeneratedCells)
    return str(count) + " cells exceed the limit of " + str(kMaxGeneratedCells);
  if (h_min < kMinCellSize)
    return "cells of edge " + str(h_min) + " m are below the limit of " +
           str(kMinCellSize) + " m";
  if (h_max > kMaxCellAspectRatio * h_min)
    return "cells of aspect ratio " + str(h_max / h_min) + " (edges " + str(h_max) +
           " m and " + str(h_min) + " m) exceed the limit of " + str(kMaxCellAspectRatio);
  return "";
}

namespace {

template <std::size_t Dim>
void CheckGeometry(const char* who, const std::array<double, Dim>& origin,
                   const std::array<double, Dim>& size,
                   const std::array<int, Dim>& cells) {
  static const char* axis = "xyz";
  for (std::size_t k = 0; k < Dim; ++k) {
    if (!std::isfinite(origin[k]))
      throw std::invalid_argument(std::string(who) + ": origin[" + std::to_string(k) +
                                  "] must be finite");
    if (!(std::isfinite(size[k]) && size[k] > 0))
      throw std::invalid_argument(std::string(who) + ": size along " + axis[k] +
                                  " must be finite and > 0, got " +
                                  std::to_string(size[k]));
    if (cells[k] < 1)
      throw std::invalid_argument(std::string(who) + ": cells along " + axis[k] +
                                  " must be >= 1, got " + std::to_string(cells[k]));
    if (std::abs(origin[k]) > kMaxGridExtent)
      throw std::invalid_argument(std::string(who) + ": |origin[" + std::to_string(k) +
                                  "]| = " + internal::FormatShort(std::abs(origin[k])) +
                                  " m exceeds " + internal::FormatShort(kMaxGridExtent) +
                                  " m");
  }
  const std::string limits =
      CheckGridLimits(std::vector<double>(size.begin(), size.end()),
                      std::vector<double>(cells.begin(), cells.end()));
  if (!limits.empty()) throw std::invalid_argument(std::string(who) + ": " + limits);
}

// Physical groups "fixed"/"load"/"contact" of dimension dim - 1 from the side roles;
// side_entities maps each side to its gmsh curve (2D) or surface (3D).
void AddBoundaryGroups(int dim, const std::map<Side, BoundaryRole>& roles,
                       const std::map<Side, int>& side_entities) {
  for (const BoundaryRole role :
       {BoundaryRole::kFixed, BoundaryRole::kLoad, BoundaryRole::kContact}) {
    std::vector<int> entities;
    for (const auto& [side, side_role] : roles)
      if (side_role == role) entities.push_back(side_entities.at(side));
    if (entities.empty()) continue;
    const int group = gmsh::model::addPhysicalGroup(dim - 1, entities);
    gmsh::model::setPhysicalName(dim - 1, group, GroupName(role));
  }
}

void CheckSides(const char* who, const std::map<Side, BoundaryRole>& roles, int dim) {
  for (const auto& [side, role] : roles)
    if (dim == 2 && (side == Side::kZMin || side == Side::kZMax))
      throw std::invalid_argument(
          std::string(who) + ": side " + ToString(side) +
          " does not exist in 2D (expected xmin, xmax, ymin or ymax)");
}

// gmsh places transfinite nodes by integrating the curve parametrization, off the exact
// grid by ~1e-12 relative. Structured meshes get their nodes snapped back to the grid
// origin_k + size_k i / cells_k, so that they coincide with MakeStructuredBoxMesh.
void SnapToGrid(Mesh* mesh, const double* origin, const double* size, const int* cells) {
  for (int i = 0; i < mesh->NumNodes(); ++i)
    for (int k = 0; k < mesh->dim; ++k) {
      const double t = (mesh->nodes(k, i) - origin[k]) / size[k] * cells[k];
      const double line = std::round(t);
      if (std::abs(t - line) < 1e-6)
        mesh->nodes(k, i) = origin[k] + size[k] * line / cells[k];
    }
}

template <std::size_t Dim>
Mesh FinishGeneratedMesh(const std::string& context, const std::string& msh_output_path,
                         MeshTopology topology, const std::array<double, Dim>& origin,
                         const std::array<double, Dim>& size,
                         const std::array<int, Dim>& cells) {
  gmsh::model::mesh::generate(static_cast<int>(Dim));
  if (!msh_output_path.empty()) gmsh::write(msh_output_path);
  Mesh mesh = internal::ExtractGmshMesh(context);
  if (topology == MeshTopology::kStructured)
    SnapToGrid(&mesh, origin.data(), size.data(), cells.data());
  internal::OrientElementsPositively(&mesh);
  return mesh;
}

}  // namespace

Mesh MakeRectangleMesh(const RectangleMeshOptions& options) {
  if (ElementOrder(options.element_type) == 2 && Dimension(options.element_type) == 2) {
    RectangleMeshOptions linear = options;
    linear.element_type = LinearElementOf(options.element_type);
    return MakeQuadraticMesh(MakeRectangleMesh(linear), options.element_type);
  }
  const char* who = "MakeRectangleMesh";
  CheckGeometry<2>(who, options.origin, options.size, options.cells);
  CheckSides(who, options.side_roles, 2);
  if (Dimension(options.element_type) != 2)
    throw std::invalid_argument(
        std::string(who) + ": element_type must be kTriangle3 or kQuadrilateral4, got " +
        ToString(options.element_type));
  const bool quads = options.element_type == ElementType::kQuadrilateral4;
  // Plain variables, not structured bindings: a lambda below captures them (C++17 clang
  // refuses).
  const double x0 = options.origin[0], y0 = options.origin[1];
  const double x1 = x0 + options.size[0], y1 = y0 + options.size[1];
  const int nx = options.cells[0], ny = options.cells[1];
  const double h = std::min(options.size[0] / nx, options.size[1] / ny);

  Mesh mesh;
  {
    internal::GmshSession session("contact_rectangle");
    internal::CallGmsh(who, /*input_error=*/false, [&] {
      namespace geo = gmsh::model::geo;
      const int p0 = geo::addPoint(x0, y0, 0, h), p1 = geo::addPoint(x1, y0, 0, h);
      const int p2 = geo::addPoint(x1, y1, 0, h), p3 = geo::addPoint(x0, y1, 0, h);
      const std::map<Side, int> sides = {{Side::kYMin, geo::addLine(p0, p1)},
                                         {Side::kXMax, geo::addLine(p1, p2)},
                                         {Side::kYMax, geo::addLine(p2, p3)},
                                         {Side::kXMin, geo::addLine(p3, p0)}};
      // Counter-clockwise loop: surface normal +z, positively oriented elements.
      const int loop = geo::addCurveLoop({sides.at(Side::kYMin), sides.at(Side::kXMax),
                                          sides.at(Side::kYMax), sides.at(Side::kXMin)});
      const int surface = geo::addPlaneSurface({loop});
      if (options.topology == MeshTopology::kStructured) {
        geo::mesh::setTransfiniteCurve(sides.at(Side::kYMin), nx + 1);
        geo::mesh::setTransfiniteCurve(sides.at(Side::kYMax), nx + 1);
        geo::mesh::setTransfiniteCurve(sides.at(Side::kXMin), ny + 1);
        geo::mesh::setTransfiniteCurve(sides.at(Side::kXMax), ny + 1);
        geo::mesh::setTransfiniteSurface(surface, "Left");
      }
      if (quads) geo::mesh::setRecombine(2, surface);
      geo::synchronize();
      const int body = gmsh::model::addPhysicalGroup(2, {surface});
      gmsh::model::setPhysicalName(2, body, "body");
      AddBoundaryGroups(2, options.side_roles, sides);
      mesh = FinishGeneratedMesh(who, options.msh_output_path, options.topology,
                                 options.origin, options.size, options.cells);
    });
  }
  ValidateMesh(mesh);
  return mesh;
}

Mesh MakeQuarterDiskMesh(const QuarterDiskMeshOptions& o) {
  const char* who = "MakeQuarterDiskMesh";
  const double R = o.radius;
  if (o.order != 1 && o.order != 2)
    throw std::invalid_argument(std::string(who) +
                                ": order must be 1 (Triangle3) or 2 "
                                "(Triangle6), got " +
                                std::to_string(o.order));
  if (!(R > 0) || !(o.contact_size > 0) || !(o.max_size >= o.contact_size) ||
      !(o.refined_radius > 0) || !(o.contact_extent > 0 && o.contact_extent < R))
    throw std::invalid_argument(
        std::string(who) +
        ": need radius > 0, 0 < contact_size <= max_size, refined_radius > 0 "
        "and 0 < contact_extent < radius");
  Mesh mesh;
  {
    internal::GmshSession session("contact_quarter_disk");
    internal::CallGmsh(who, /*input_error=*/false, [&] {
      namespace geo = gmsh::model::geo;
      const double xs = o.contact_extent, ys = R - std::sqrt(R * R - xs * xs);
      const int origin = geo::addPoint(0, 0, 0), split = geo::addPoint(xs, ys, 0);
      const int right = geo::addPoint(R, R, 0), centre = geo::addPoint(0, R, 0);
      // Counter-clockwise: arc up to (R, R), cut back to (0, R), symmetry line down.
      const int contact_arc = geo::addCircleArc(origin, centre, split);
      const int free_arc = geo::addCircleArc(split, centre, right);
      const int cut = geo::addLine(right, centre);
      const int symmetry = geo::addLine(centre, origin);
      const int surface = geo::addPlaneSurface(
          {geo::addCurveLoop({contact_arc, free_arc, cut, symmetry})});
      geo::synchronize();
      gmsh::model::setPhysicalName(1, gmsh::model::addPhysicalGroup(1, {contact_arc}),
                                   kContactGroup);
      gmsh::model::setPhysicalName(1, gmsh::model::addPhysicalGroup(1, {cut}),
                                   kLoadGroup);
      gmsh::model::setPhysicalName(1, gmsh::model::addPhysicalGroup(1, {symmetry}),
                                   kFixedGroup);
      gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, {surface}),
                                   "body");
      namespace field = gmsh::model::mesh::field;
      const int distance = field::add("Distance");
      field::setNumbers(distance, "PointsList", {static_cast<double>(origin)});
      const int threshold = field::add("Threshold");
      field::setNumber(threshold, "InField", distance);
      field::setNumber(threshold, "SizeMin", o.contact_size);
      field::setNumber(threshold, "SizeMax", o.max_size);
      field::setNumber(threshold, "DistMin", o.refined_radius);
      field::setNumber(threshold, "DistMax",
                       o.refined_radius + 4.0 * (o.max_size - o.contact_size));
      field::setAsBackgroundMesh(threshold);
      // (gmsh 4.8 crashes with Mesh.Algorithm = 8 and a Threshold field: default
      // algorithm.)
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::model::mesh::generate(2);
      // Order 2: gmsh places the mid-side nodes of the arcs on the circle.
      if (o.order == 2) gmsh::model::mesh::setOrder(2);
      mesh = internal::ExtractGmshMesh(who);
      internal::OrientElementsPositively(&mesh);
    });
  }
  ValidateMesh(mesh);
  return mesh;
}

Mesh MakeBoxMesh(const BoxMeshOptions& options) {
  if (ElementOrder(options.element_type) == 2 && Dimension(options.element_type) == 3) {
    BoxMeshOptions linear = options;
    linear.element_type = LinearElementOf(options.element_type);
    return MakeQuadraticMesh(MakeBoxMesh(linear), options.element_type);
  }
  const char* who = "MakeBoxMesh";
  CheckGeometry<3>(who, options.origin, options.size, options.cells);
  if (Dimension(options.element_type) != 3)
    throw std::invalid_argument(
        std::string(who) + ": element_type must be kTetrahedron4 or kHexahedron8, got " +
        ToString(options.element_type));
  const bool hexes = options.element_type == ElementType::kHexahedron8;
  const bool structured = options.topology == MeshTopology::kStructured;
  if (hexes && !structured)
    throw std::invalid_argument(
        std::string(who) +
        ": unstructured hexahedral meshes are not supported; expected "
        "topology kStructured for kHexahedron8 (or use kTetrahedron4)");
  const double h =
      std::min({options.size[0] / options.cells[0], options.size[1] / options.cells[1],
                options.size[2] / options.cells[2]});

  Mesh mesh;
  {
    internal::GmshSession session("contact_box");
    internal::CallGmsh(who, /*input_error=*/false, [&] {
      namespace geo = gmsh::model::geo;
      // Corner c has coordinate origin_k + size_k * bit_k(c), bits (x, y, z) = (1, 2, 4).
      int corner[8];
      for (int c = 0; c < 8; ++c)
        corner[c] = geo::addPoint(options.origin[0] + ((c & 1) ? options.size[0] : 0),
                                  options.origin[1] + ((c & 2) ? options.size[1] : 0),
                                  options.origin[2] + ((c & 4) ? options.size[2] : 0), h);
      // The 12 edges, c -> c + bit; edges along axis k get cells[k] + 1 nodes.
      std::map<std::pair<int, int>, int> edge;
      for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 3; ++k) {
          const int bit = 1 << k;
          if (c & bit) continue;
          const int line = geo::addLine(corner[c], corner[c + bit]);
          edge[{c, c + bit}] = line;
          if (structured) geo::mesh::setTransfiniteCurve(line, options.cells[k] + 1);
        }
      auto signed_edge = [&](int a, int b) {
        return a < b ? edge.at({a, b}) : -edge.at({b, a});
      };
      // Faces as corner cycles with outward normals (right-hand rule).
      const std::vector<std::pair<Side, std::array<int, 4>>> faces = {
          {Side::kZMin, {0, 2, 3, 1}}, {Side::kZMax, {4, 5, 7, 6}},
          {Side::kYMin, {0, 1, 5, 4}}, {Side::kYMax, {2, 6, 7, 3}},
          {Side::kXMin, {0, 4, 6, 2}}, {Side::kXMax, {1, 3, 7, 5}}};
      std::map<Side, int> sides;
      std::vector<int> surfaces;
      for (const auto& [side, cycle] : faces) {
        std::vector<int> loop;
        for (int i = 0; i < 4; ++i)
          loop.push_back(signed_edge(cycle[i], cycle[(i + 1) % 4]));
        const int surface = geo::addPlaneSurface({geo::addCurveLoop(loop)});
        if (structured) geo::mesh::setTransfiniteSurface(surface, "Left");
        if (hexes) geo::mesh::setRecombine(2, surface);
        sides[side] = surface;
        surfaces.push_back(surface);
      }
      const int volume = geo::addVolume({geo::addSurfaceLoop(surfaces)});
      if (structured) geo::mesh::setTransfiniteVolume(volume);
      geo::synchronize();
      if (hexes) gmsh::model::mesh::setRecombine(3, volume);
      const int body = gmsh::model::addPhysicalGroup(3, {volume});
      gmsh::model::setPhysicalName(3, body, "body");
      AddBoundaryGroups(3, options.side_roles, sides);
      mesh = FinishGeneratedMesh(who, options.msh_output_path, options.topology,
                                 options.origin, options.size, options.cells);
    });
  }
  ValidateMesh(mesh);
  return mesh;
}

namespace {

/// The node numbering of a structured nx x ny x nz grid of hexahedra: node (i, j, k) is
/// i + (nx + 1) (j + (ny + 1) k), element (i, j, k) is i + nx (j + ny k).
struct StructuredGrid {
  int nx, ny, nz;
  int Node(int i, int j, int k) const { return i + (nx + 1) * (j + (ny + 1) * k); }
};

/// Node (i, j, k) at origin + size * (i / nx, j / ny, k / nz).
void PlaceGridNodes(const BoxMeshOptions& options, const StructuredGrid& g, Mesh* mesh) {
  for (int k = 0; k <= g.nz; ++k)
    for (int j = 0; j <= g.ny; ++j)
      for (int i = 0; i <= g.nx; ++i) {
        const int n = g.Node(i, j, k);
        mesh->nodes(0, n) = options.origin[0] + options.size[0] * i / g.nx;
        mesh->nodes(1, n) = options.origin[1] + options.size[1] * j / g.ny;
        mesh->nodes(2, n) = options.origin[2] + options.size[2] * k / g.nz;
      }
}

/// The hexahedra in gmsh's node order (bottom face counterclockwise seen from +z, then
/// the top face), tagged 1, 2, ...
void ConnectGridHexahedra(const StructuredGrid& g, Mesh* mesh) {
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const int e = i + g.nx * (j + g.ny * k);
        mesh->elements.col(e) << g.Node(i, j, k), g.Node(i + 1, j, k),
            g.Node(i + 1, j + 1, k), g.Node(i, j + 1, k), g.Node(i, j, k + 1),
            g.Node(i + 1, j, k + 1), g.Node(i + 1, j + 1, k + 1), g.Node(i, j + 1, k + 1);
        mesh->element_tags[e] = static_cast<std::size_t>(e) + 1;
      }
}

/// The quadrilaterals of a side (a plane i = const, or j, k), ordered so that the normal
/// by the right-hand rule points out of the box.
std::vector<std::array<int, 4>> SideQuadrilaterals(const StructuredGrid& g, Side side) {
  std::vector<std::array<int, 4>> quads;
  switch (side) {
    case Side::kXMin:
    case Side::kXMax: {
      const int i = side == Side::kXMin ? 0 : g.nx;
      for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j) {
          std::array<int, 4> q = {g.Node(i, j, k), g.Node(i, j + 1, k),
                                  g.Node(i, j + 1, k + 1),
                                  g.Node(i, j, k + 1)};  // y then z: normal +x
          if (side == Side::kXMin) std::swap(q[1], q[3]);
          quads.push_back(q);
        }
      break;
    }
    case Side::kYMin:
    case Side::kYMax: {
      const int j = side == Side::kYMin ? 0 : g.ny;
      for (int k = 0; k < g.nz; ++k)
        for (int i = 0; i < g.nx; ++i) {
          std::array<int, 4> q = {g.Node(i, j, k), g.Node(i, j, k + 1),
                                  g.Node(i + 1, j, k + 1),
                                  g.Node(i + 1, j, k)};  // z then x: normal +y
          if (side == Side::kYMin) std::swap(q[1], q[3]);
          quads.push_back(q);
        }
      break;
    }
    case Side::kZMin:
    case Side::kZMax: {
      const int k = side == Side::kZMin ? 0 : g.nz;
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
          std::array<int, 4> q = {g.Node(i, j, k), g.Node(i + 1, j, k),
                                  g.Node(i + 1, j + 1, k),
                                  g.Node(i, j + 1, k)};  // x then y: normal +z
          if (side == Side::kZMin) std::swap(q[1], q[3]);
          quads.push_back(q);
        }
      break;
    }
  }
  return quads;
}

/// The side quadrilaterals into the boundary group of each side's role.
void AddGridSideGroups(const std::map<Side, BoundaryRole>& side_roles,
                       const StructuredGrid& g, Mesh* mesh) {
  for (const auto& [side, role] : side_roles) {
    if (role == BoundaryRole::kNone) continue;
    BoundaryFacets& group = mesh->boundary_groups[GroupName(role)];
    group.type = FacetType::kQuadrilateral4;
    const auto quads = SideQuadrilaterals(g, side);
    const Eigen::Index old = group.connectivity.cols();
    group.connectivity.conservativeResize(4,
                                          old + static_cast<Eigen::Index>(quads.size()));
    for (std::size_t f = 0; f < quads.size(); ++f)
      for (int a = 0; a < 4; ++a) group.connectivity(a, old + f) = quads[f][a];
  }
}

}  // namespace

Mesh MakeStructuredBoxMesh(const BoxMeshOptions& options) {
  const char* who = "MakeStructuredBoxMesh";
  CheckGeometry<3>(who, options.origin, options.size, options.cells);
  if (options.element_type != ElementType::kHexahedron8 ||
      options.topology != MeshTopology::kStructured)
    throw std::invalid_argument(
        std::string(who) + ": only structured kHexahedron8 meshes, got element_type " +
        ToString(options.element_type) +
        (options.topology == MeshTopology::kStructured ? std::string(" (structured)")
                                                       : std::string(" (unstructured)")));
  const StructuredGrid grid{options.cells[0], options.cells[1], options.cells[2]};
  const long long num_nodes =
      static_cast<long long>(grid.nx + 1) * (grid.ny + 1) * (grid.nz + 1);
  const long long num_elements = static_cast<long long>(grid.nx) * grid.ny * grid.nz;
  if (3 * num_nodes > std::numeric_limits<int>::max())
    throw std::invalid_argument(std::string(who) + ": too many dofs for int indices: " +
                                std::to_string(3 * num_nodes));
  Mesh mesh;
  mesh.dim = 3;
  mesh.element_type = ElementType::kHexahedron8;
  mesh.nodes.resize(3, num_nodes);
  PlaceGridNodes(options, grid, &mesh);
  mesh.elements.resize(8, num_elements);
  mesh.element_tags.resize(num_elements);
  ConnectGridHexahedra(grid, &mesh);
  AddGridSideGroups(options.side_roles, grid, &mesh);
  return mesh;
}

}  // namespace contact
