#include "gmsh_model.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

#include "quadratic_element.hpp"
#include "reference_element.hpp"

namespace contact::internal {
namespace {

std::mutex& GmshMutex() {
  static std::mutex mutex;
  return mutex;
}

// gmsh element type numbers (gmsh manual, section "MSH file format").
constexpr int kGmshLine2 = 1;
constexpr int kGmshTriangle3 = 2;
constexpr int kGmshQuadrilateral4 = 3;
constexpr int kGmshTetrahedron4 = 4;
constexpr int kGmshHexahedron8 = 5;
constexpr int kGmshLine3 = 8;
constexpr int kGmshTriangle6 = 9;
constexpr int kGmshQuadrilateral9 = 10;
constexpr int kGmshTetrahedron10 = 11;
constexpr int kGmshHexahedron27 = 12;
constexpr int kGmshQuadrilateral8 = 16;
constexpr int kGmshHexahedron20 = 17;

// gmsh's volume element types and ours (the node orders coincide, mesh.hpp).
constexpr std::pair<int, ElementType> kVolumeTypes[] = {
    {kGmshTriangle3, ElementType::kTriangle3},
    {kGmshQuadrilateral4, ElementType::kQuadrilateral4},
    {kGmshTetrahedron4, ElementType::kTetrahedron4},
    {kGmshHexahedron8, ElementType::kHexahedron8},
    {kGmshTriangle6, ElementType::kTriangle6},
    {kGmshQuadrilateral8, ElementType::kQuadrilateral8},
    {kGmshQuadrilateral9, ElementType::kQuadrilateral9},
    {kGmshTetrahedron10, ElementType::kTetrahedron10},
    {kGmshHexahedron20, ElementType::kHexahedron20},
    {kGmshHexahedron27, ElementType::kHexahedron27}};

int GmshType(FacetType type) {
  switch (type) {
    case FacetType::kLine3:
      return kGmshLine3;
    case FacetType::kTriangle6:
      return kGmshTriangle6;
    case FacetType::kQuadrilateral8:
      return kGmshQuadrilateral8;
    case FacetType::kQuadrilateral9:
      return kGmshQuadrilateral9;
    case FacetType::kLine2:
      return kGmshLine2;
    case FacetType::kTriangle3:
      return kGmshTriangle3;
    case FacetType::kQuadrilateral4:
      return kGmshQuadrilateral4;
  }
  return -1;
}

std::string DescribeGmshType(int gmsh_type) {
  std::string name;
  int dim = 0, order = 0, num_nodes = 0, num_primary = 0;
  std::vector<double> local_coordinates;
  gmsh::model::mesh::getElementProperties(gmsh_type, name, dim, order, num_nodes,
                                          local_coordinates, num_primary);
  return "'" + name + "' (gmsh type " + std::to_string(gmsh_type) + ", order " +
         std::to_string(order) + ", " + std::to_string(num_nodes) + " nodes)";
}

/// The one supported volume element type among gmsh's element blocks of dimension dim
/// (index into types); throws on unsupported, mixed or missing elements.
std::size_t ChooseVolumeElements(
    const std::string& source, int dim, const std::vector<int>& types,
    const std::vector<std::vector<std::size_t>>& element_tags) {
  int chosen = -1;
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (element_tags[t].empty()) continue;
    bool supported = false;
    for (const auto& [gmsh_type, type] : kVolumeTypes)
      supported = supported || (gmsh_type == types[t] && Dimension(type) == dim);
    if (!supported)
      throw std::invalid_argument(
          source + ": unsupported element type " + DescribeGmshType(types[t]) + " (" +
          std::to_string(element_tags[t].size()) +
          " elements); supported are 3- and 6-node triangles, "
          "4-, 8- and 9-node quadrilaterals in 2D, 4- and 10-node "
          "tetrahedra, 8-, 20- and 27-node hexahedra in 3D");
    if (chosen >= 0)
      throw std::invalid_argument(source + ": unsupported mixed element types " +
                                  DescribeGmshType(types[chosen]) + " and " +
                                  DescribeGmshType(types[t]) +
                                  "; expected a single element type");
    chosen = static_cast<int>(t);
  }
  if (chosen < 0)
    throw std::invalid_argument(source + ": contains no " + std::to_string(dim) +
                                "D elements");
  return static_cast<std::size_t>(chosen);
}

ElementType ElementTypeOfGmsh(int gmsh_type) {
  for (const auto& [code, type] : kVolumeTypes)
    if (code == gmsh_type) return type;
  return ElementType::kHexahedron8;
}

/// The nodes of the volume elements into mesh->nodes, numbered 0, 1, ... by increasing
/// gmsh tag; returns tag -> node index. A 2D mesh must lie in the plane z = 0.
std::map<std::size_t, int> ReadElementNodes(const std::string& source,
                                            const std::vector<std::size_t>& element_nodes,
                                            Mesh* mesh) {
  const int dim = mesh->dim;
  std::vector<std::size_t> node_tags;
  std::vector<double> coordinates, parametric;
  gmsh::model::mesh::getNodes(node_tags, coordinates, parametric, -1, -1, false, false);
  // Tags may be sparse (any value up to 2^64 - 1): maps sized by the number of nodes,
  // never by the largest tag. Sorted, so that nodes are numbered by increasing tag.
  std::map<std::size_t, std::size_t> position_of_tag;  // tag -> position in node_tags
  for (std::size_t k = 0; k < node_tags.size(); ++k) position_of_tag[node_tags[k]] = k;
  std::map<std::size_t, int>
      index_of_tag;  // tag -> node index, for the nodes of elements
  for (const std::size_t tag : element_nodes) {
    if (!position_of_tag.count(tag))
      throw std::invalid_argument(source + ": element refers to missing node tag " +
                                  std::to_string(tag));
    index_of_tag[tag] = 0;
  }
  if (index_of_tag.size() >
      static_cast<std::size_t>(std::numeric_limits<int>::max() / dim))
    throw std::invalid_argument(source + ": " + std::to_string(index_of_tag.size()) +
                                " nodes exceed the int index range of the dofs");
  int num_nodes = 0;
  for (auto& [tag, index] : index_of_tag) index = num_nodes++;
  mesh->nodes.resize(dim, num_nodes);
  double max_abs_z = 0, extent = 0;
  for (const auto& [tag, node] : index_of_tag) {
    const double* x = &coordinates[3 * position_of_tag.at(tag)];
    for (int k = 0; k < dim; ++k) {
      mesh->nodes(k, node) = x[k];
      extent = std::max(extent, std::abs(x[k]));
    }
    max_abs_z = std::max(max_abs_z, std::abs(x[2]));
  }
  if (dim == 2 && max_abs_z > 1e-10 * std::max(1.0, extent))
    throw std::invalid_argument(
        source + ": a 2D mesh must lie in the plane z = 0, got |z| up to " +
        std::to_string(max_abs_z));
  return index_of_tag;
}

/// The facets of one physical group of dimension dim - 1 as node indices appended to
/// *connectivity; every facet must have the facet type of the elements and nodes of them.
void AppendGroupFacets(const std::string& source, const Mesh& mesh, int group_dim,
                       int group_tag, const std::string& name,
                       const std::map<std::size_t, int>& index_of_tag,
                       std::vector<int>* connectivity) {
  const FacetType facet_type = FacetTypeOf(mesh.element_type);
  std::vector<int> entities;
  gmsh::model::getEntitiesForPhysicalGroup(group_dim, group_tag, entities);
  for (const int entity : entities) {
    std::vector<int> facet_types;
    std::vector<std::vector<std::size_t>> facet_tags, facet_node_tags;
    gmsh::model::mesh::getElements(facet_types, facet_tags, facet_node_tags, group_dim,
                                   entity);
    for (std::size_t t = 0; t < facet_types.size(); ++t) {
      if (facet_tags[t].empty()) continue;
      if (facet_types[t] != GmshType(facet_type))
        throw std::invalid_argument(
            source + ": boundary group '" + name + "' has unsupported facet type " +
            DescribeGmshType(facet_types[t]) + "; " + ToString(mesh.element_type) +
            " elements need facets of type " + DescribeGmshType(GmshType(facet_type)));
      for (const std::size_t tag : facet_node_tags[t]) {
        if (!index_of_tag.count(tag))
          throw std::invalid_argument(source + ": boundary group '" + name +
                                      "' uses node tag " + std::to_string(tag) +
                                      ", which belongs to no " +
                                      std::to_string(mesh.dim) + "D element");
        connectivity->push_back(index_of_tag.at(tag));
      }
    }
  }
}

/// Boundary groups: the physical groups of dimension dim - 1, merged by name (a group
/// without a name is named by its tag).
void ReadBoundaryGroups(const std::string& source,
                        const std::map<std::size_t, int>& index_of_tag, Mesh* mesh) {
  const FacetType facet_type = FacetTypeOf(mesh->element_type);
  const int facet_nodes = NodesPerFacet(facet_type);
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, mesh->dim - 1);
  std::map<std::string, std::vector<int>> connectivity_by_name;
  for (const auto& [group_dim, group_tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(group_dim, group_tag, name);
    if (name.empty()) name = std::to_string(group_tag);
    AppendGroupFacets(source, *mesh, group_dim, group_tag, name, index_of_tag,
                      &connectivity_by_name[name]);
  }
  for (const auto& [name, connectivity] : connectivity_by_name) {
    BoundaryFacets facets;
    facets.type = facet_type;
    facets.connectivity = Eigen::Map<const Eigen::MatrixXi>(
        connectivity.data(), facet_nodes,
        static_cast<Eigen::Index>(connectivity.size()) / facet_nodes);
    mesh->boundary_groups[name] = std::move(facets);
  }
}

}  // namespace

GmshSession::GmshSession(const std::string& model_name) {
  GmshMutex().lock();
  try {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    // Never ask on standard input: gmsh's questions (e.g. "Do you really want to
    // continue?" before a very large mesh) take their default answer.
    gmsh::option::setNumber("General.NoPopup", 1);
    gmsh::model::add(model_name);
  } catch (const std::string& what) {
    GmshMutex().unlock();
    throw std::runtime_error("gmsh initialization failed: " + what);
  }
}

GmshSession::~GmshSession() {
  try {
    gmsh::finalize();
  } catch (...) {
    // finalize must not throw out of a destructor; gmsh state is reset on the next
    // initialize anyway.
  }
  GmshMutex().unlock();
}

void ThrowGmshError(const std::string& context, bool input_error,
                    const std::string& what) {
  std::string last;
  try {
    gmsh::logger::getLastError(last);
  } catch (...) {
  }
  std::string message = context + ": gmsh error: " + what;
  if (!last.empty() && last != what) message += " (" + last + ")";
  if (input_error) throw std::invalid_argument(message);
  throw std::runtime_error(message);
}

Mesh ExtractGmshMesh(const std::string& source) {
  Mesh mesh;
  const int dim = gmsh::model::getDimension();
  if (dim != 2 && dim != 3)
    throw std::invalid_argument(source + ": expected a 2D or 3D mesh, got dimension " +
                                std::to_string(dim));
  mesh.dim = dim;

  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, dim, -1);
  const std::size_t chosen = ChooseVolumeElements(source, dim, types, element_tags);
  mesh.element_type = ElementTypeOfGmsh(types[chosen]);
  const int nen = NodesPerElement(mesh.element_type);

  const std::map<std::size_t, int> index_of_tag =
      ReadElementNodes(source, element_nodes[chosen], &mesh);
  const std::size_t num_elements = element_tags[chosen].size();
  mesh.elements.resize(nen, static_cast<Eigen::Index>(num_elements));
  for (std::size_t e = 0; e < num_elements; ++e)
    for (int a = 0; a < nen; ++a)
      mesh.elements(a, e) = index_of_tag.at(element_nodes[chosen][nen * e + a]);
  mesh.element_tags = element_tags[chosen];

  ReadBoundaryGroups(source, index_of_tag, &mesh);
  return mesh;
}

void OrientElementsPositively(Mesh* mesh) {
  DispatchElement(mesh->element_type, [&](auto tag) {
    constexpr ElementType T = decltype(tag)::value;
    constexpr int kDim = ElementTraits<T>::kDim;
    constexpr int kNodes = ElementTraits<T>::kNodes;
    // Reference centroid: (1/3, 1/3), (1/4, 1/4, 1/4) or the origin.
    const ElementType kLinear = LinearElementOf(T);
    double xi[3] = {0, 0, 0};
    if (kLinear == ElementType::kTriangle3 || kLinear == ElementType::kTetrahedron4)
      for (int k = 0; k < kDim; ++k) xi[k] = 1.0 / (kDim + 1);
    double N[kNodes];
    Eigen::Matrix<double, kNodes, kDim, Eigen::RowMajor> dN;
    EvaluateShape(kDim, kNodes, xi, N, dN.data());
    const Eigen::Matrix<double, kNodes, kDim> dN_dxi = dN;
    // Mirror the reference element: a permutation of the corners with opposite
    // orientation, the mid-edge and mid-face nodes following their corners.
    std::vector<int> corners(static_cast<std::size_t>(CornersPerElement(T)));
    for (std::size_t a = 0; a < corners.size(); ++a) corners[a] = static_cast<int>(a);
    if (kLinear == ElementType::kTriangle3 || kLinear == ElementType::kTetrahedron4) {
      std::swap(corners[1], corners[2]);
    } else if (kLinear == ElementType::kQuadrilateral4) {
      std::swap(corners[1], corners[3]);
    } else {
      std::swap(corners[1], corners[3]);
      std::swap(corners[5], corners[7]);
    }
    const std::vector<int> mirror = ExtendCornerPermutation(kDim, kNodes, corners);
    for (int e = 0; e < mesh->NumElements(); ++e) {
      const auto X = ElementCoordinates<T>(*mesh, e);
      if ((X * dN_dxi).determinant() >= 0) continue;
      const Eigen::VectorXi column = mesh->elements.col(e);
      for (int a = 0; a < kNodes; ++a)
        mesh->elements(a, e) = column(mirror[static_cast<std::size_t>(a)]);
    }
  });
}

}  // namespace contact::internal
