// The critical step of central differences with a mass inverse the caller already has
// (RunDynamics factors M once for the whole run).
#pragma once

#include <Eigen/SparseCore>

#include "contact/dynamics_types.hpp"
#include "mass_inverse.hpp"

namespace contact::internal {

/// dt_crit = 2 / omega_max by Lanczos on the pencil (K, M) (see
/// EstimateCriticalTimeStep).
CriticalTimeStep Lanczos(const Eigen::SparseMatrix<double>& K,
                         const Eigen::SparseMatrix<double>& M, MassInverse* mass,
                         double relative_tolerance, int max_iterations);

}  // namespace contact::internal
