#include "energy_balance.hpp"

#include <cmath>
#include <cstdio>

namespace contact::internal {

EnergyBalance::EnergyBalance(const Eigen::VectorXd& u, const Eigen::VectorXd& u_previous,
                             const Eigen::VectorXd& Ku, const Eigen::VectorXd& Mdu,
                             double dt)
    : kinetic0(0.5 * (u - u_previous).dot(Mdu) / (dt * dt)),
      energy0(kinetic0 + 0.5 * u_previous.dot(Ku)),
      strain0(0.5 * u.dot(Ku)) {}

void EnergyBalance::AddStepWork(int dim, const std::vector<ContactNode>& nodes,
                                const Eigen::VectorXd& f, const Eigen::VectorXd& r,
                                const Eigen::VectorXd& u_next,
                                const Eigen::VectorXd& u_previous) {
  AddExternalWork(0.5 * (f.dot(u_next) - f.dot(u_previous)));
  AddContactWork(dim, nodes, r, u_next, u_previous);
}

void EnergyBalance::AddExternalWork(double dw_ext) {
  external_work += dw_ext;
  work_scale += std::abs(dw_ext);
}

void EnergyBalance::AddContactWork(int dim, const std::vector<ContactNode>& nodes,
                                   const Eigen::VectorXd& r,
                                   const Eigen::VectorXd& u_next,
                                   const Eigen::VectorXd& u_previous) {
  double dw_normal = 0.0;
  for (const ContactNode& node : nodes) {
    Eigen::Vector3d rc = Eigen::Vector3d::Zero(), sc = Eigen::Vector3d::Zero();
    for (int a = 0; a < dim; ++a) {
      if (node.dofs[a] < 0) continue;  // constrained component: no motion, no work
      rc(a) = r(node.dofs[a]);
      sc(a) = 0.5 * (u_next(node.dofs[a]) - u_previous(node.dofs[a]));
    }
    const double rn = rc.dot(node.normal), sn = sc.dot(node.normal);
    dw_normal += rn * sn;
    friction_dissipation -= rc.dot(sc) - rn * sn;
  }
  normal_work += dw_normal;
}

void EnergyBalance::AddDampingWork(const Eigen::VectorXd& c,
                                   const Eigen::VectorXd& u_next,
                                   const Eigen::VectorXd& u_previous) {
  damping_dissipation += 0.5 * (c.dot(u_next) - c.dot(u_previous));
}

void EnergyBalance::Record(const Eigen::VectorXd& du, const Eigen::VectorXd& Mdu,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& u_next,
                           const Eigen::VectorXd& Ku_next, double dt,
                           StepRecord* rec) const {
  Record(du.dot(Mdu), u.dot(Ku_next), u_next.dot(Ku_next), dt, rec);
}

void EnergyBalance::Record(double du_Mdu, double u_Ku_next, double u_next_Ku_next,
                           double dt, StepRecord* rec) const {
  rec->kinetic = 0.5 * du_Mdu / (dt * dt);
  const double shadow = rec->kinetic + 0.5 * u_Ku_next;
  rec->strain = 0.5 * u_next_Ku_next;
  rec->external_work = external_work;
  rec->normal_contact_work = normal_work;
  rec->friction_dissipation = friction_dissipation;
  rec->damping_dissipation = damping_dissipation;
  rec->energy_balance_error = shadow - energy0 - external_work - normal_work +
                              friction_dissipation + damping_dissipation;
}

bool EnergyWithinGuard(const StepRecord& rec, double reference, double factor,
                       DynamicSummary* summary) {
  const double energy = rec.kinetic + rec.strain;
  if (std::isfinite(energy) && !(reference > 0.0 && energy > factor * reference))
    return true;
  summary->status = DynamicStatus::kEnergyBlowUp;
  char buffer[200];
  std::snprintf(
      buffer, sizeof buffer,
      "energy blow-up at step %d (t = %.6g s): E = %.3e J against %.3e J of initial "
      "energy and external work",
      rec.step, rec.time, energy, reference);
  summary->message = buffer;
  return false;
}

}  // namespace contact::internal
