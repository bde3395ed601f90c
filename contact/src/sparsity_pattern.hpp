// The sparsity pattern of the assembled matrices (K and M share it) built from the
// node-to-node graph of the mesh, and the scatter of element matrices into it.
//
// Instead of collecting triplets (16 bytes per element-matrix entry: ~3 GB for a 10^6-dof
// hexahedral mesh) the compressed column structure is built once from the mesh graph in
// O(nnz) and element matrices are added in place: the entry (row node a, column node b)
// of column dof d*b+j sits at outer[d*b+j] + d*k + i, where k is the position of a in the
// sorted neighbour list of b.
#pragma once

#include <algorithm>
#include <vector>

#include "contact/mesh.hpp"
#include "contact/types.hpp"

namespace contact::internal {

struct SparsityPattern {
  int dim = 0;
  int num_nodes = 0;
  // Sorted neighbours (nodes sharing an element, including the node itself) of node b:
  // neighbors[neighbor_offsets[b] .. neighbor_offsets[b + 1]).
  std::vector<int> neighbor_offsets;
  std::vector<int> neighbors;

  explicit SparsityPattern(const Mesh& mesh);

  // dim*N x dim*N matrix with the full structure and zero values.
  SparseMatrix ZeroMatrix() const;
  // Position of node a in the neighbour list of node b (a must be a neighbour of b).
  int NeighborIndex(int b, int a) const {
    const int* begin = neighbors.data() + neighbor_offsets[b];
    const int* end = neighbors.data() + neighbor_offsets[b + 1];
    return static_cast<int>(std::lower_bound(begin, end, a) - begin);
  }
  // Number of structural nonzeros of the dof matrix, dim^2 * neighbors.size().
  long long NumNonZeros() const;
};

// A += the element matrix Ke (dim*nen x dim*nen, local dof dim*a + i) of the element with
// the given nodes. A must have the structure of pattern.ZeroMatrix().
template <class ElementMatrix>
void ScatterElementMatrix(const SparsityPattern& pattern, const int* element_nodes,
                          int nen, const ElementMatrix& Ke, SparseMatrix* A) {
  const int dim = pattern.dim;
  const int* outer = A->outerIndexPtr();
  double* values = A->valuePtr();
  for (int b = 0; b < nen; ++b) {
    const int node_b = element_nodes[b];
    for (int a = 0; a < nen; ++a) {
      const int k = pattern.NeighborIndex(node_b, element_nodes[a]);
      for (int j = 0; j < dim; ++j) {
        double* column = values + outer[dim * node_b + j] + dim * k;
        for (int i = 0; i < dim; ++i) column[i] += Ke(dim * a + i, dim * b + j);
      }
    }
  }
}

// A += Me (x) I_dim: the scalar element matrix Me (nen x nen) on every displacement
// component, e.g. the mass matrix (the off-diagonal component blocks are zero and
// skipped).
template <class ScalarElementMatrix>
void ScatterBlockDiagonalElementMatrix(const SparsityPattern& pattern,
                                       const int* element_nodes, int nen,
                                       const ScalarElementMatrix& Me, SparseMatrix* A) {
  const int dim = pattern.dim;
  const int* outer = A->outerIndexPtr();
  double* values = A->valuePtr();
  for (int b = 0; b < nen; ++b) {
    const int node_b = element_nodes[b];
    for (int a = 0; a < nen; ++a) {
      const int k = pattern.NeighborIndex(node_b, element_nodes[a]);
      for (int j = 0; j < dim; ++j)
        values[outer[dim * node_b + j] + dim * k + j] += Me(a, b);
    }
  }
}

}  // namespace contact::internal
