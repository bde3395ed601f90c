/// \file problem.hpp
/// The local frictional contact problem in Delassus form (FCLIB "local", Siconos
/// FrictionContactProblem): find contact forces r and relative velocities u with
///     u = W r + q,
/// and for every contact alpha (components ordered normal, tangent 1[, tangent 2])
///     u_hat = u + (mu |u_T|, 0[, 0]),   C*_mu  ∋  u_hat  ⟂  r  ∈  C_mu,
///     C_mu = { r : |r_T| <= mu r_N }  (the Coulomb cone; C*_mu its dual).
/// W is symmetric positive semidefinite (often singular). Units are whatever the file
/// uses: r is an impulse or a force and u a velocity, W = H' M^-1 H their compliance.
#pragma once

#include <string>

#include "ncp/types.hpp"

namespace ncp::fc {

struct FrictionProblem {
  int dimension = 3;     ///< 2 (normal + 1 tangent) or 3 (normal + 2 tangents)
  int num_contacts = 0;  ///< n_c; W is (dimension n_c) x (dimension n_c)
  SparseMatrix W;        ///< Delassus operator
  Vector q;              ///< free relative velocity, size dimension n_c
  Vector mu;             ///< friction coefficient per contact, >= 0
  std::string name;      ///< where it came from (file name), for reports

  int size() const { return dimension * num_contacts; }
  /// Throws std::invalid_argument (expected vs actual) unless the sizes agree, every
  /// entry is finite and every mu >= 0.
  void Validate() const;
};

}  // namespace ncp::fc
