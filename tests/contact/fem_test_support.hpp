// Helpers shared by the contact FEM tests: meshes with distorted interiors, rigid-body
// modes, linear displacement fields.
#pragma once

#include <contact/mesh.hpp>
#include <contact/types.hpp>
#include <random>
#include <vector>

namespace contact::testing {

// Moves every node strictly inside the bounding box of the mesh (the interior of a
// generated rectangle or box) by a uniform random offset in [-fraction h, fraction h] per
// coordinate (fixed seed). fraction < 0.25 keeps structured quadrilaterals/hexahedra
// valid.
inline void PerturbInteriorNodes(Mesh* mesh, double h, double fraction,
                                 unsigned seed = 7) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> offset(-fraction * h, fraction * h);
  const Eigen::VectorXd lower = mesh->nodes.rowwise().minCoeff();
  const Eigen::VectorXd upper = mesh->nodes.rowwise().maxCoeff();
  const double tolerance = 1e-9 * (upper - lower).norm();
  for (int i = 0; i < mesh->NumNodes(); ++i) {
    const Eigen::VectorXd x = mesh->nodes.col(i);
    const bool interior = ((x - lower).array() > tolerance).all() &&
                          ((upper - x).array() > tolerance).all();
    if (interior)
      for (int k = 0; k < mesh->dim; ++k) mesh->nodes(k, i) += offset(generator);
  }
}

// Node-major dof vector of the field u(x) = a + B x.
inline Vector LinearField(const Mesh& mesh, const Eigen::VectorXd& a,
                          const Eigen::MatrixXd& B) {
  Vector u(mesh.NumDofs());
  for (int i = 0; i < mesh.NumNodes(); ++i)
    u.segment(mesh.dim * i, mesh.dim) = a + B * mesh.nodes.col(i);
  return u;
}

// Columns: the rigid-body motions (translations, then infinitesimal rotations w x x),
// 3 in 2D and 6 in 3D.
inline DenseMatrix RigidBodyModes(const Mesh& mesh) {
  const int dim = mesh.dim;
  const int count = dim == 2 ? 3 : 6;
  DenseMatrix modes = DenseMatrix::Zero(mesh.NumDofs(), count);
  for (int i = 0; i < mesh.NumNodes(); ++i) {
    const Eigen::VectorXd x = mesh.nodes.col(i);
    for (int k = 0; k < dim; ++k) modes(dim * i + k, k) = 1.0;
    if (dim == 2) {
      modes(2 * i + 0, 2) = -x(1);
      modes(2 * i + 1, 2) = x(0);
    } else {
      // rotation about z, x, y
      modes(3 * i + 0, 3) = -x(1);
      modes(3 * i + 1, 3) = x(0);
      modes(3 * i + 1, 4) = -x(2);
      modes(3 * i + 2, 4) = x(1);
      modes(3 * i + 2, 5) = -x(0);
      modes(3 * i + 0, 5) = x(2);
    }
  }
  return modes;
}

}  // namespace contact::testing
