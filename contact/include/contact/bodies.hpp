/// \file bodies.hpp
/// Several elastic bodies in one system. Each body keeps its own mesh, material and
/// Dirichlet conditions; the bodies' dofs are stacked body after body,
///     global dof = offset[b] + dim * node + component,
/// so the stiffness and mass of the system are block diagonal, K = diag(K_0, K_1, ...),
/// M = diag(M_0, M_1, ...), and the bodies are coupled only by contact constraints
/// (mortar.hpp). All bodies share one spatial dimension and, in 2D, one thickness.
#pragma once

#include <string>
#include <vector>

#include "contact/dof_map.hpp"
#include "contact/elastic_body.hpp"
#include "contact/types.hpp"

namespace contact {

/// One body of a scene with several bodies.
struct Body {
  std::string name;  ///< unique, used in messages and output
  ElasticBody body;
  /// Its Dirichlet conditions on its own boundary groups (empty: a free body).
  std::vector<DirichletCondition> dirichlet;
};

/// The block system of all bodies (see the file comment).
struct BodySystem {
  int dim = 0;
  /// First global dof of body b; offset.back() is the total number of dofs.
  std::vector<int> offset;
  SparseMatrix stiffness;  ///< K [N/m], block diagonal
  SparseMatrix mass;       ///< consistent M [kg], block diagonal
  Vector lumped_mass;      ///< row-sum lumped masses [kg], one per global dof
  DofMap dofs;             ///< all bodies' Dirichlet conditions on the global dofs

  int NumBodies() const { return static_cast<int>(offset.size()) - 1; }
  int NumDofs() const { return offset.empty() ? 0 : offset.back(); }
  /// Global dof of (body, node, component).
  int GlobalDof(int body, int node, int component) const {
    return offset[static_cast<size_t>(body)] + dim * node + component;
  }
  /// The part of a global vector that belongs to body b (its own node-major layout).
  Vector BodyPart(const Vector& global, int body) const;
};

/// Assembles the block system. Throws std::invalid_argument naming the body for an empty
/// list, duplicate or empty names, bodies of different dimensions or, in 2D, different
/// thicknesses, and for Dirichlet conditions on missing groups (MakeDofMap's message).
BodySystem AssembleBodies(const std::vector<Body>& bodies);

/// Index of the body called `name`; throws std::invalid_argument naming the bodies if
/// none is.
int FindBody(const std::vector<Body>& bodies, const std::string& name);

}  // namespace contact
