#include "contact/dof_map.hpp"

#include <stdexcept>
#include <string>

namespace contact {

DofMap::DofMap(int num_dofs) : DofMap(num_dofs, {}, {}) {}

DofMap::DofMap(int num_dofs, const std::vector<int>& constrained_dofs,
               const Vector& u_full) {
  if (num_dofs < 0)
    throw std::invalid_argument("DofMap: num_dofs must be >= 0, got " +
                                std::to_string(num_dofs));
  if (u_full.size() != 0) CheckSize(u_full.size(), num_dofs, "prescribed values u_full");
  free_index_.assign(num_dofs, 0);
  for (const int dof : constrained_dofs) {
    if (dof < 0 || dof >= num_dofs)
      throw std::invalid_argument("DofMap: constrained dof must lie in [0, " +
                                  std::to_string(num_dofs) + "), got " +
                                  std::to_string(dof));
    free_index_[dof] = -1;
  }
  for (int dof = 0; dof < num_dofs; ++dof) {
    if (free_index_[dof] < 0) continue;
    free_index_[dof] = static_cast<int>(free_dofs_.size());
    free_dofs_.push_back(dof);
  }
  prescribed_ = Vector::Zero(num_dofs);
  if (u_full.size() != 0) SetPrescribedValues(u_full);
}

void DofMap::CheckSize(Eigen::Index size, Eigen::Index expected, const char* what) const {
  if (size != expected)
    throw std::invalid_argument(std::string("DofMap: ") + what + " must have size " +
                                std::to_string(expected) + ", got " +
                                std::to_string(size));
}

std::vector<int> DofMap::ConstrainedDofs() const {
  std::vector<int> dofs;
  dofs.reserve(NumConstrainedDofs());
  for (int dof = 0; dof < NumDofs(); ++dof)
    if (free_index_[dof] < 0) dofs.push_back(dof);
  return dofs;
}

void DofMap::SetPrescribedValues(const Vector& u_full) {
  CheckSize(u_full.size(), NumDofs(), "prescribed values u_full");
  for (int dof = 0; dof < NumDofs(); ++dof)
    prescribed_(dof) = free_index_[dof] < 0 ? u_full(dof) : 0.0;
}

SparseMatrix DofMap::RestrictMatrix(const SparseMatrix& A) const {
  CheckSize(A.rows(), NumDofs(), "matrix rows");
  CheckSize(A.cols(), NumDofs(), "matrix columns");
  // Two passes over the compressed columns: count, then copy the free-free entries.
  const int n = NumFreeDofs();
  SparseMatrix R(n, n);
  std::vector<int> counts(n, 0);
  long long nnz = 0;
  for (int c = 0; c < n; ++c) {
    for (SparseMatrix::InnerIterator it(A, free_dofs_[c]); it; ++it)
      if (free_index_[it.row()] >= 0) ++counts[c];
    nnz += counts[c];
  }
  R.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int position = 0;
  for (int c = 0; c < n; ++c) {
    R.outerIndexPtr()[c] = position;
    for (SparseMatrix::InnerIterator it(A, free_dofs_[c]); it; ++it) {
      const int row = free_index_[it.row()];
      if (row < 0) continue;
      R.innerIndexPtr()[position] = row;  // increasing: free_index_ is monotone
      R.valuePtr()[position] = it.value();
      ++position;
    }
  }
  R.outerIndexPtr()[n] = position;
  return R;
}

Vector DofMap::RestrictVector(const Vector& v) const {
  CheckSize(v.size(), NumDofs(), "vector");
  Vector r(NumFreeDofs());
  for (int k = 0; k < NumFreeDofs(); ++k) r(k) = v(free_dofs_[k]);
  return r;
}

Vector DofMap::RestrictLoad(const SparseMatrix& K, const Vector& f) const {
  CheckSize(K.rows(), NumDofs(), "matrix rows");
  CheckSize(K.cols(), NumDofs(), "matrix columns");
  CheckSize(f.size(), NumDofs(), "load vector");
  return RestrictVector(f - K * prescribed_);
}

Vector DofMap::Expand(const Vector& u_free) const {
  Vector u = ExpandHomogeneous(u_free);
  for (int dof = 0; dof < NumDofs(); ++dof)
    if (free_index_[dof] < 0) u(dof) = prescribed_(dof);
  return u;
}

Vector DofMap::ExpandHomogeneous(const Vector& u_free) const {
  CheckSize(u_free.size(), NumFreeDofs(), "free vector");
  Vector u = Vector::Zero(NumDofs());
  for (int k = 0; k < NumFreeDofs(); ++k) u(free_dofs_[k]) = u_free(k);
  return u;
}

SparseMatrix DofMap::RestrictionMatrix() const {
  SparseMatrix P(NumFreeDofs(), NumDofs());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(free_dofs_.size());
  for (int k = 0; k < NumFreeDofs(); ++k) triplets.emplace_back(k, free_dofs_[k], 1.0);
  P.setFromTriplets(triplets.begin(), triplets.end());
  return P;
}

DofMap MakeDofMap(const Mesh& mesh, const std::vector<DirichletCondition>& conditions) {
  std::vector<int> constrained;
  Vector values = Vector::Zero(mesh.NumDofs());
  for (const DirichletCondition& condition : conditions) {
    std::vector<int> components = condition.components;
    if (components.empty())
      for (int i = 0; i < mesh.dim; ++i) components.push_back(i);
    for (const int i : components)
      if (i < 0 || i >= mesh.dim)
        throw std::invalid_argument("DirichletCondition on '" + condition.group +
                                    "': component must lie in [0, " +
                                    std::to_string(mesh.dim) + "), got " +
                                    std::to_string(i));
    for (const int node : mesh.BoundaryGroup(condition.group).Nodes()) {
      Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.dim);
      if (condition.displacement) {
        u = condition.displacement(mesh.nodes.col(node));
        if (u.size() != mesh.dim)
          throw std::invalid_argument("DirichletCondition on '" + condition.group +
                                      "': displacement(x) must have " +
                                      std::to_string(mesh.dim) + " components, got " +
                                      std::to_string(u.size()));
      }
      for (const int i : components) {
        constrained.push_back(mesh.dim * node + i);
        values(mesh.dim * node + i) = u(i);
      }
    }
  }
  return DofMap(mesh.NumDofs(), constrained, values);
}

}  // namespace contact
