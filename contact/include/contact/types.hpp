/// \file types.hpp
/// Linear-algebra types of the contact module. They coincide with the ncp types
/// (ncp/types.hpp) so that matrices assembled here feed the complementarity solver as is.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace contact {

using Vector = Eigen::VectorXd;
/// Column-major compressed sparse matrix with int indices (same as ncp::SparseMatrix).
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using DenseMatrix = Eigen::MatrixXd;

}  // namespace contact
