/// \file static_contact.hpp
/// Static contact of a linear elastic body with a rigid obstacle (thesis section 4.3 uses
/// it for the initial state of the dynamic problem):
///     K u = f + sum_c F_c,   0 <= lambda_c perp gap_c >= 0,   friction (Tresca/Coulomb)
/// solved as a ContactSystem with S = K / k, q = -f / k, k = max |K_ii| (scaling only).
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "contact/contact_system.hpp"
#include "ncp/solver.hpp"

namespace contact {

enum class FrictionLaw {
  kFrictionless,
  kTresca,   ///< |tau_c| <= tresca_bound_c (given nodal forces [N])
  kCoulomb,  ///< |tau_c| <= f_c lambda_c, by fixed point on lambda (thesis section 4.2)
};

/// The Newton start of a static solve.
enum class StaticStart {
  kZero,  ///< u = 0: every node at its initial gap
  /// The equilibrium with every candidate node held on the obstacle: K u = f + sum_c F_c
  /// with n_c . u_c = s_c (gap_c = 0) at every node, no friction. There the pressed nodes
  /// (lambda_c > 0) count as closed and the pulled ones as open, so that with the min
  /// function the first Newton step is a primal-dual active-set step from the closed set
  /// - no step cut while a body that only the contact holds moves onto the obstacle.
  /// Costs one sparse Cholesky factorization of K without the normal components; falls
  /// back to kZero (StaticContactResult::closed_start = false) when that matrix is not
  /// positive definite (a body free to move along the obstacle).
  kClosed,
};
const char* ToString(StaticStart start);

/// ncp::Options defaults for the static problem: ContactNcpOptions() with the min
/// function, which from the closed start (StaticStart::kClosed) takes the Newton steps
/// of an active-set method (measured on the 2D Hertz meshes:
/// benchmarks/results/contact/static-hertz/README.md).
ncp::Options StaticContactNcpOptions();

struct StaticContactOptions {
  FrictionLaw friction = FrictionLaw::kFrictionless;
  double friction_coefficient = 0.0;  ///< f_c for kCoulomb
  Eigen::VectorXd tresca_bound;       ///< per contact node [N] for kTresca
  /// Coulomb fixed point stops when max_c |lambda_c^{i+1} - lambda_c^i| <= this * max_c
  /// lambda_c.
  double fixed_point_tolerance = 1e-10;
  int max_fixed_point_iterations = 100;
  /// Start point of the first (or only) complementarity solve; the Coulomb fixed point
  /// starts each later one from the previous solution.
  StaticStart start = StaticStart::kClosed;
  /// Semismooth Newton settings. The scaled equations are displacements, so `tolerance`
  /// is in metres. Default min tie: a touching node counts as closed (see ncp::Options).
  ncp::Options ncp = StaticContactNcpOptions();
};

struct StaticContactResult {
  bool converged = false;
  std::string message = "not solved yet";
  Eigen::VectorXd u;              ///< free dofs, global frame [m]
  Eigen::VectorXd normal_force;   ///< lambda_c >= 0 per contact node [N]
  Eigen::MatrixXd tangent_force;  ///< friction force components along t1 (t2) [N]
  Eigen::VectorXd gap;            ///< s_c - n_c . u_c [m]
  int fixed_point_iterations = 0;
  int newton_iterations = 0;  ///< summed over fixed-point iterations
  /// The solve started from the closed start (options.start = kClosed and its matrix was
  /// positive definite); false: from u = 0.
  bool closed_start = false;
  ncp::Summary last_summary;  ///< of the last complementarity solve
};

/// K and f on the free dofs; `nodes` in the free-dof numbering.
StaticContactResult SolveStaticContact(int dim, const Eigen::SparseMatrix<double>& K,
                                       const Eigen::VectorXd& f,
                                       const std::vector<ContactNode>& nodes,
                                       const StaticContactOptions& options);

/// Frictionless reference: the convex QP  min 1/2 u'Ku - f'u  s.t.  n_c . u_c <= s_c,
/// solved by Ipopt; the multipliers are the normal forces lambda_c.
StaticContactResult SolveStaticContactIpopt(int dim, const Eigen::SparseMatrix<double>& K,
                                            const Eigen::VectorXd& f,
                                            const std::vector<ContactNode>& nodes,
                                            double tolerance = 1e-10);

}  // namespace contact
