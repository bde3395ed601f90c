#include "sparsity_pattern.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace contact::internal {

SparsityPattern::SparsityPattern(const Mesh& mesh)
    : dim(mesh.dim), num_nodes(mesh.NumNodes()) {
  const int nen = static_cast<int>(mesh.elements.rows());
  // Node -> elements incidence (compressed rows).
  std::vector<int> element_offsets(num_nodes + 1, 0);
  for (int e = 0; e < mesh.NumElements(); ++e)
    for (int a = 0; a < nen; ++a) ++element_offsets[mesh.elements(a, e) + 1];
  for (int i = 0; i < num_nodes; ++i) element_offsets[i + 1] += element_offsets[i];
  std::vector<int> incident(element_offsets.back());
  {
    std::vector<int> fill(element_offsets.begin(), element_offsets.end() - 1);
    for (int e = 0; e < mesh.NumElements(); ++e)
      for (int a = 0; a < nen; ++a) incident[fill[mesh.elements(a, e)]++] = e;
  }
  // Neighbours of each node: the sorted, distinct nodes of its elements. A marker array
  // keeps the cost linear in the number of (node, element) incidences.
  neighbor_offsets.assign(num_nodes + 1, 0);
  neighbors.reserve(static_cast<std::size_t>(element_offsets.back()) * 4);
  std::vector<int> last_seen(num_nodes, -1);
  for (int b = 0; b < num_nodes; ++b) {
    const std::size_t begin = neighbors.size();
    for (int k = element_offsets[b]; k < element_offsets[b + 1]; ++k) {
      const int e = incident[k];
      for (int a = 0; a < nen; ++a) {
        const int node = mesh.elements(a, e);
        if (last_seen[node] != b) {
          last_seen[node] = b;
          neighbors.push_back(node);
        }
      }
    }
    std::sort(neighbors.begin() + begin, neighbors.end());
    neighbor_offsets[b + 1] = static_cast<int>(neighbors.size());
  }
  if (NumNonZeros() > std::numeric_limits<int>::max())
    throw std::invalid_argument("mesh too large: the assembled matrix would have " +
                                std::to_string(NumNonZeros()) +
                                " nonzeros, more than the int index limit " +
                                std::to_string(std::numeric_limits<int>::max()));
}

long long SparsityPattern::NumNonZeros() const {
  return static_cast<long long>(dim) * dim * static_cast<long long>(neighbors.size());
}

SparseMatrix SparsityPattern::ZeroMatrix() const {
  const int n = dim * num_nodes;
  SparseMatrix A(n, n);
  A.resizeNonZeros(static_cast<Eigen::Index>(NumNonZeros()));
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  int position = 0;
  for (int b = 0; b < num_nodes; ++b) {
    for (int j = 0; j < dim; ++j) {
      outer[dim * b + j] = position;
      for (int k = neighbor_offsets[b]; k < neighbor_offsets[b + 1]; ++k)
        for (int i = 0; i < dim; ++i) inner[position++] = dim * neighbors[k] + i;
    }
  }
  outer[n] = position;
  std::fill(A.valuePtr(), A.valuePtr() + position, 0.0);
  return A;
}

}  // namespace contact::internal
