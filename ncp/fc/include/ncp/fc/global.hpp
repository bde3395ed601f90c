/// \file global.hpp
/// The global frictional contact problem (Siconos GlobalFrictionContactProblem, FCLIB
/// "global"): find velocities v, contact forces r and relative velocities u with
///     M v = q + H r,    u = H' v + b,
/// and the Coulomb law of problem.hpp between u and r at every contact. M (n x n) is the
/// mass (or iteration) matrix, H (n x m, m = dimension n_c) maps contact forces to
/// generalized forces. (FCLIB names q and b f and w.)
///
/// With M invertible, v = M^-1 (q + H r) and u = W r + q_local with the Delassus operator
///     W = H' M^-1 H,   q_local = H' M^-1 q + b,
/// the local problem of problem.hpp (Siconos' gfc3d_reformulation_local_problem). This
/// module solves global problems that way: ReduceToLocal, ncp::fc::Solve, GlobalVelocity.
#pragma once

#include <string>

#include "ncp/fc/problem.hpp"
#include "ncp/types.hpp"

namespace ncp::fc {

struct GlobalFrictionProblem {
  int dimension = 3;     ///< 2 or 3
  int num_contacts = 0;  ///< n_c; m = dimension n_c
  SparseMatrix M;        ///< n x n, invertible (symmetric positive definite in mechanics)
  SparseMatrix H;        ///< n x m
  Vector q;              ///< size n (FCLIB f)
  Vector b;              ///< size m (FCLIB w)
  Vector mu;             ///< size n_c, >= 0
  std::string name;

  int num_dofs() const { return static_cast<int>(M.rows()); }
  int size() const { return dimension * num_contacts; }
  /// Throws std::invalid_argument (expected vs actual) unless the sizes agree, every
  /// entry is finite and every mu >= 0.
  void Validate() const;
};

/// W = H' M^-1 H, q_local = H' M^-1 q + b, mu and name as given. M is factored by sparse
/// LU; throws std::runtime_error (naming the problem) when M is singular.
FrictionProblem ReduceToLocal(const GlobalFrictionProblem& problem);

/// v = M^-1 (q + H r). Throws std::runtime_error when M is singular.
Vector GlobalVelocity(const GlobalFrictionProblem& problem, const Vector& r);

/// The global residual at (v, r): ||M v - q - H r||_2 / (1 + ||q||_2) (the equation of
/// motion, 0 for v = GlobalVelocity(r) up to round-off), and the natural-map error of the
/// contact law at u = H' v + b, ||r - P_C(r - u_hat)||_2 / (1 + ||b||_2). Neither uses W.
struct GlobalResidual {
  double motion = 0.0;
  double contact = 0.0;
};
GlobalResidual ComputeGlobalResidual(const GlobalFrictionProblem& problem,
                                     const Vector& v, const Vector& r);

}  // namespace ncp::fc
