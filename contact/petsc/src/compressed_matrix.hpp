// A parallel AIJ matrix without the entries that are exactly zero.
//
// contact::ElasticBody assembles the consistent mass on the stiffness matrix's pattern
// (every pair of nodes of a cell couples all dim x dim components), but a finite-element
// mass couples equal components only: M = M_s (x) I_dim, two thirds of the stored
// entries of a 3D M are exact zeros. A sparse factorization of M takes them as entries
// (its elimination graph couples the components of a node), so its factor holds dim
// times the entries of the factors of the dim decoupled blocks, and every solve with it
// works through them. Dropping the zeros from the pattern makes the graph dim disjoint
// copies of M_s's (with the Dirichlet components' rows removed): the same matrix, whose
// factor the solver's ordering finds block by block.
#pragma once

#include <petscmat.h>

namespace contact::petsc::internal {

/// Collective. A new MATAIJ matrix with A's values and row and column layout, holding
/// only A's entries that are not exactly zero (every diagonal entry is kept); A's
/// symmetry and positive definiteness flags carry over. The caller destroys it.
Mat CopyWithoutZeros(Mat A);

}  // namespace contact::petsc::internal
