// The critical step of central differences with a mass inverse the caller already has
// (RunDynamics factors M once for the whole run).
#pragma once

#include <Eigen/SparseCore>
#include <functional>

#include "contact/dynamics.hpp"
#include "contact/dynamics_types.hpp"
#include "mass_inverse.hpp"

namespace contact::internal {

/// The vector operations of the Lanczos iteration on the pencil (K, M), on this
/// process's part of the vectors (all of them in one process; on MPI ranks the owned
/// free dofs, contact/petsc/).
struct LanczosOperators {
  long long global_size = 0;  ///< n, the free dofs of the whole body
  /// Per local entry, its index in the serial free-dof numbering (the start vector's
  /// entry depends on it: LanczosStartEntry).
  std::function<long long(Eigen::Index)> global_index;
  /// y = K x, y = M x (the start only), x = M^-1 b on the local parts.
  std::function<void(const Eigen::VectorXd&x, Eigen::VectorXd*y)> multiply_K, multiply_M;
  std::function<void(const Eigen::VectorXd& b, Eigen::VectorXd* x)> solve_M;
  /// x' y over the whole body, the same value on every process.
  std::function<double(const Eigen::VectorXd& x, const Eigen::VectorXd& y)> dot;
};

/// Entry i (serial free-dof index) of the start vector: alternating in sign every two
/// entries (rich in high-frequency modes), scaled by 1 + 1e-3 (i mod 7).
double LanczosStartEntry(long long i);

/// dt_crit = 2 / omega_max by Lanczos on the pencil (K, M) through `op` (see
/// EstimateCriticalTimeStep); local_size entries on this process.
CriticalTimeStep Lanczos(const LanczosOperators& op, Eigen::Index local_size,
                         double relative_tolerance, int max_iterations);

/// The stability check of central differences on an estimate of dt_crit: sets
/// summary->critical_time_step; true if options.dt <= dt_crit or
/// allow_unstable_time_step, else false with kRefusedUnstable and a message naming both
/// steps and the scene key. Throws std::invalid_argument if dt_crit is not a positive
/// finite number (K or M out of the range of double precision). (dynamics.cpp)
bool AcceptCriticalStep(const CriticalTimeStep& crit, const DynamicOptions& options,
                        DynamicSummary* summary);

/// dt_crit = 2 / omega_max by Lanczos on the pencil (K, M) (see
/// EstimateCriticalTimeStep).
CriticalTimeStep Lanczos(const Eigen::SparseMatrix<double>& K,
                         const Eigen::SparseMatrix<double>& M, MassInverse* mass,
                         double relative_tolerance, int max_iterations);

}  // namespace contact::internal
