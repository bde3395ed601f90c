// Energy bookkeeping of central differences (contact/dynamics.hpp): the exact discrete
// balance
//     E^{k+1/2} - E^{-1/2} = W_ext + W_contact,   E^{k+1/2} = 1/2 v' M v + 1/2 (u^k)' K
//     u^{k+1}, v = (u^{k+1} - u^k) / dt,
// with the work increments over the half span (u^{k+1} - u^{k-1}) / 2 and W_contact split
// into its normal part and the friction dissipation (>= 0). All energies in joules.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "contact/dynamics.hpp"
#include "contact/dynamics_types.hpp"

namespace contact::internal {

struct EnergyBalance {
  double kinetic0 = 0.0;  ///< 1/2 v' M v at the start, v = (u^0 - u^{-1}) / dt
  double energy0 = 0.0;   ///< shadow energy E^{-1/2} = kinetic0 + 1/2 (u^{-1})' K u^0
  double strain0 = 0.0;   ///< 1/2 (u^0)' K u^0
  double external_work = 0.0, normal_work = 0.0, friction_dissipation = 0.0;
  double damping_dissipation = 0.0;  ///< D = sum of c^k . s, c^k = C v^k (damping.hpp)
  double work_scale = 0.0;           ///< sum of |external work increments|

  EnergyBalance() = default;  ///< zero (a checkpoint fills it)
  /// At the start: Ku = K u^0, Mdu = M (u^0 - u^{-1}).
  EnergyBalance(const Eigen::VectorXd& u, const Eigen::VectorXd& u_previous,
                const Eigen::VectorXd& Ku, const Eigen::VectorXd& Mdu, double dt);

  /// Adds the work of step k: W_ext += f^k . s, W_normal += sum_c (r_c . n_c)(s_c . n_c),
  /// dissipation -= sum_c (r_c . s_c - (r_c . n_c)(s_c . n_c)), s = (u^{k+1} - u^{k-1}) /
  /// 2, r = the contact forces [N] (nonzero at the contact nodes only).
  void AddStepWork(int dim, const std::vector<ContactNode>& nodes,
                   const Eigen::VectorXd& f, const Eigen::VectorXd& r,
                   const Eigen::VectorXd& u_next, const Eigen::VectorXd& u_previous);
  /// Its parts: W_ext += dw_ext = 1/2 (f^k . u^{k+1} - f^k . u^{k-1}) [J], and the
  /// contact nodes' work (r, u_next, u_previous indexed by the nodes' dofs).
  void AddExternalWork(double dw_ext);
  void AddContactWork(int dim, const std::vector<ContactNode>& nodes,
                      const Eigen::VectorXd& r, const Eigen::VectorXd& u_next,
                      const Eigen::VectorXd& u_previous);

  /// D += c . (u^{k+1} - u^{k-1}) / 2 for the damping force c = C v^k [N].
  void AddDampingWork(const Eigen::VectorXd& c, const Eigen::VectorXd& u_next,
                      const Eigen::VectorXd& u_previous);

  /// The energies of rec after step k: kinetic 1/2 du' M du / dt^2 (Mdu = M du), strain
  /// 1/2 (u^{k+1})' K u^{k+1} (Ku_next = K u^{k+1}), the cumulative works and the balance
  /// error E^{k+1/2} - E^{-1/2} - W_ext - W_normal + dissipation + D.
  void Record(const Eigen::VectorXd& du, const Eigen::VectorXd& Mdu,
              const Eigen::VectorXd& u, const Eigen::VectorXd& u_next,
              const Eigen::VectorXd& Ku_next, double dt, StepRecord* rec) const;
  /// The same from the products: du_Mdu = du' M du [kg m^2], u_Ku_next = (u^k)' K u^{k+1}
  /// and u_next_Ku_next = (u^{k+1})' K u^{k+1} [J] (a run on MPI ranks sums them over the
  /// ranks).
  void Record(double du_Mdu, double u_Ku_next, double u_next_Ku_next, double dt,
              StepRecord* rec) const;

  /// What the blow-up guard compares kinetic + strain energy with: the initial kinetic
  /// and strain energy and all external work that entered.
  double BlowUpReference() const { return kinetic0 + strain0 + work_scale; }
};

/// The blow-up guard after a recorded step: true if kinetic + strain energy of rec is
/// finite and within `factor` times `reference` (EnergyBalance::BlowUpReference; no test
/// while the reference is 0); else false, and summary gets kEnergyBlowUp and a message.
bool EnergyWithinGuard(const StepRecord& rec, double reference, double factor,
                       DynamicSummary* summary);

}  // namespace contact::internal
