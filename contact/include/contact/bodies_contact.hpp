/// \file bodies_contact.hpp
/// Frictionless contact between several elastic bodies (bodies.hpp) coupled by mortar
/// constraints g = g0 + B u (mortar.hpp), static and by central differences. Both solve
/// the mixed complementarity problem (ncp, thesis eq. 12) in the free dofs x and the
/// contact forces lambda (one per constraint):
///     S x + q - B_F' lambda = 0,      0 <= lambda  perp  g_base + B_F x >= 0,
/// with B_F the columns of B at the free dofs and g_base the gap at x = 0:
///   static:  S = K_FF / k, q = -(f - K u_C)_F / k, k = max_i K_ii (scaling only),
///            x = u_F, g_base = g0 + B_C u_C, lambda in units of N / k;
///   step:    M (u^{k+1} - 2 u^k + u^{k-1}) / dt^2 + K u^k = f + B' lambda^{k+1}
///            (thesis eq. 68 with the mortar forces), x = u^{k+1}_F - u^k_F,
///            S = M_FF / m, q = -(M (u^k - u^{k-1}) + dt^2 (f - K u^k))_F / m,
///            m = max_i M_ii, g_base = g0 + B u^k, lambda in units of N dt^2 / m.
/// The Jacobian is constant: Newton ends in the step after the last change of the active
/// set. Dirichlet values are time independent.
/// With friction (some mu_j > 0) the same problem gains the friction forces tau_j on the
/// slip rows s = s_base + T x (mortar.hpp): S x + q - B' lambda - T' tau = 0 and
/// Coulomb's law |tau_j| <= mu_j lambda_j, tau_j s_j <= 0, tau_j = -mu_j lambda_j
/// sign(s_j) when s_j != 0 (the bound with this solve's lambda), solved by ncp::fc in
/// Delassus form (W = H S^-1 H' on the contact rows): static, s_base = T u_C (slip from
/// the reference configuration, one load step); step, s_base = 0 (slip increment over the
/// step).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "contact/bodies.hpp"
#include "contact/contact_system.hpp"
#include "contact/mortar.hpp"
#include "ncp/solver.hpp"

namespace contact {

struct BodiesStaticResult {
  bool converged = false;
  std::string message = "not solved yet";
  Vector u;                 ///< all global dofs, Dirichlet values included [m]
  Vector normal_force;      ///< lambda_j >= 0 per constraint [N]
  Vector tangential_force;  ///< tau_j per constraint, |tau_j| <= mu_j lambda_j [N]
  Vector slip;              ///< s = T u per constraint [m]
  Vector pressure;          ///< lambda_j / D_jj [Pa]
  Vector gap;               ///< g0 + B u per constraint [m]
  int newton_iterations = -1;
  ncp::Summary summary;
};

/// Static equilibrium K u = f + B' lambda with the contact conditions. Every body must be
/// held by its Dirichlet conditions or by contact (else K is singular on a rigid motion
/// and the solve reports the failure). f: global load [N]. ncp.tolerance is relative to
/// the scale of the problem's displacements (max |q|, |u_C|, |g_base|).
BodiesStaticResult SolveBodiesStatic(const BodySystem& system,
                                     const MortarConstraints& constraints,
                                     const Vector& f,
                                     const ncp::Options& ncp = ContactNcpOptions());

enum class BodiesDynamicStatus { kNotRun, kCompleted, kSolverFailure };
const char* ToString(BodiesDynamicStatus status);

struct BodiesDynamicOptions {
  double time_step =
      0.0;        ///< dt [s], > 0 (no stability check: see EstimateCriticalTimeStep)
  int steps = 0;  ///< number of steps, >= 1
  bool lumped_mass = false;  ///< row-sum lumped M instead of the consistent one
  ncp::Options ncp = ContactNcpOptions();
  /// Called after every step with its number k >= 1, u^k (global) and the constraint
  /// forces lambda^k [N]; e.g. to write snapshots.
  std::function<void(int step, const Vector& u, const Vector& normal_force)> on_step;
};

/// State after step k (time t_k = k dt).
struct BodiesStepRecord {
  double time = 0.0;  ///< [s]
  /// Sum of lambda_j over the constraints of each interface [N].
  std::vector<double> interface_force;
  /// Sum of tau_j over the constraints of each interface [N] (0 without friction).
  std::vector<double> interface_tangential_force;
  /// E^{k-1/2} = 1/2 v' M v + 1/2 (u^{k-1})' K u^k, v = (u^k - u^{k-1}) / dt [J]:
  /// without external load it is conserved exactly by central differences away from
  /// contact (see dynamics.hpp).
  double energy = 0.0;
  int newton_iterations = 0;
};

struct BodiesDynamicSummary {
  BodiesDynamicStatus status = BodiesDynamicStatus::kNotRun;
  std::string message = "not run yet";
  std::vector<BodiesStepRecord> records;
  Vector u, velocity;            ///< after the last step, all global dofs [m, m/s]
  double max_penetration = 0.0;  ///< max over steps of -min_j g_j, >= 0 [m]
};

/// Runs the steps from displacement u0 and velocity v0 (global, [m] and [m/s]) under a
/// constant load f [N]; u^{-1} = u0 - dt v0. Throws std::invalid_argument for bad sizes
/// or options.
BodiesDynamicSummary RunBodiesDynamics(const BodySystem& system,
                                       const MortarConstraints& constraints,
                                       const Vector& f, const Vector& u0,
                                       const Vector& v0,
                                       const BodiesDynamicOptions& options);

}  // namespace contact
