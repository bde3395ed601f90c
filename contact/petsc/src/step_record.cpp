#include "step_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace contact::petsc::internal {

StepGather::StepGather(MPI_Comm comm, int dim, int num_contact_nodes)
    : comm_(comm), dim_(dim), num_contact_nodes_(num_contact_nodes) {
  int size = 1;
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size);
  counts_.resize(static_cast<size_t>(size));
  offsets_.resize(counts_.size());
}

void StepGather::Gather(const RankStepPart& part, const std::vector<NodeResult>& nodes,
                        GatheredStep* out) {
  send_.assign(part.sum, part.sum + RankStepPart::kNumSums);
  send_.insert(send_.end(), part.max, part.max + RankStepPart::kNumMaxima);
  for (const NodeResult& n : nodes) {
    send_.push_back(n.index);
    send_.push_back(n.normal_force);
    send_.push_back(n.gap);
    for (int a = 0; a < dim_ - 1; ++a) send_.push_back(n.tangent_force(a));
    for (int a = 0; a < dim_ - 1; ++a) send_.push_back(n.slip(a));
    for (const Eigen::Vector3d* v : {&n.r, &n.u_next, &n.u_previous})
      for (int a = 0; a < dim_; ++a) send_.push_back((*v)(a));
  }
  const int count = static_cast<int>(send_.size());
  MPI_Gather(&count, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, comm_);
  int total = 0;
  if (rank_ == 0)
    for (size_t r = 0; r < counts_.size(); ++r) offsets_[r] = total, total += counts_[r];
  receive_.resize(static_cast<size_t>(total));
  MPI_Gatherv(send_.data(), count, MPI_DOUBLE, receive_.data(), counts_.data(),
              offsets_.data(), MPI_DOUBLE, 0, comm_);
  if (rank_ != 0) return;
  const Eigen::Index N = num_contact_nodes_;
  ContactSystem::Result& contact = out->contact;
  contact.normal_force.setZero(N);
  contact.gap.setZero(N);
  contact.tangent_force.setZero(dim_ - 1, N);
  contact.slip.setZero(dim_ - 1, N);
  for (Eigen::VectorXd* v : {&out->r, &out->u_next, &out->u_previous})
    v->setZero(dim_ * N);
  out->parts.resize(counts_.size());
  const size_t width = static_cast<size_t>(NodeWidth());
  for (size_t rank = 0; rank < counts_.size(); ++rank) {
    const double* d = &receive_[static_cast<size_t>(offsets_[rank])];
    RankStepPart& part_of_rank = out->parts[rank];
    std::copy(d, d + RankStepPart::kNumSums, part_of_rank.sum);
    std::copy(d + RankStepPart::kNumSums, d + RankStepPart::kWidth, part_of_rank.max);
    const size_t end = static_cast<size_t>(counts_[rank]);
    for (size_t k = RankStepPart::kWidth; k + width <= end; k += width) {
      const double* n = d + k;
      const auto c = static_cast<Eigen::Index>(n[0]);
      contact.normal_force(c) = n[1];
      contact.gap(c) = n[2];
      for (int a = 0; a < dim_ - 1; ++a)
        contact.tangent_force(a, c) = n[3 + a], contact.slip(a, c) = n[dim_ + 2 + a];
      const double* components = n + 2 * dim_ + 1;
      for (int a = 0; a < dim_; ++a) {
        out->r(dim_ * c + a) = components[a];
        out->u_next(dim_ * c + a) = components[dim_ + a];
        out->u_previous(dim_ * c + a) = components[2 * dim_ + a];
      }
    }
  }
}

StepRecorder::StepRecorder(const Scene& scene, StepMethod method,
                           const std::vector<ContactNode>& nodes,
                           const Eigen::VectorXd& lambda0,
                           const ::contact::internal::EnergyBalance& energy, double m_max)
    : dim_(scene.dim),
      method_(method),
      dt_(scene.dynamics.dt),
      tolerance_(scene.dynamics.ncp.tolerance),
      friction_(scene.friction_coefficient),
      blowup_factor_(scene.dynamics.energy_blowup_factor),
      m_max_(m_max),
      force_scale_(m_max / (dt_ * dt_)),
      nodes_(nodes),
      lambda_(lambda0),
      energy_(energy) {
  for (size_t c = 0; c < nodes_.size(); ++c) {
    gap0_max_ = std::max(gap0_max_, std::abs(nodes_[c].gap));
    for (int a = 0; a < 3; ++a)
      nodes_[c].dofs[a] = nodes_[c].dofs[a] >= 0 ? dim_ * static_cast<int>(c) + a : -1;
  }
}

::contact::internal::StepScales StepRecorder::Scales(double f_max, double Ku_max,
                                                     double du_max,
                                                     double penetration) const {
  return ::contact::internal::StepScalesFromMaxima(f_max, Ku_max, contact_force_max_,
                                                   du_max, penetration, m_max_, dt_);
}

bool StepRecorder::Record(GatheredStep* step, long num_steps, StepRecord* rec,
                          DynamicSummary* summary) {
  // The parts summed (and maximized) in rank order.
  RankStepPart all;
  for (const RankStepPart& part : step->parts) {
    for (int s = 0; s < RankStepPart::kNumSums; ++s) all.sum[s] += part.sum[s];
    for (int m = 0; m < RankStepPart::kNumMaxima; ++m)
      all.max[m] = std::max(all.max[m], part.max[m]);
  }
  if (all.sum[RankStepPart::kNonFinite] > 0.0) {
    summary->status = DynamicStatus::kSolverFailure;
    summary->message = "step " + std::to_string(rec->step) +
                       " (t = " + std::to_string(rec->time) +
                       " s): non-finite values in the " + ToString(method_) + " step";
    return false;
  }
  // The step's scales and the accuracy asked for (step_accuracy.hpp).
  const ::contact::internal::StepScales scales =
      Scales(all.max[RankStepPart::kF], all.max[RankStepPart::kKu],
             all.max[RankStepPart::kDu], all.max[RankStepPart::kPenetration]);
  ::contact::internal::AskedAccuracyMaxima maxima;
  maxima.Q = all.max[RankStepPart::kQ];
  maxima.Mdu = all.max[RankStepPart::kMdu];
  maxima.u_next = all.max[RankStepPart::kUNext];
  maxima.gap0 = gap0_max_;
  ::contact::internal::SetAskedAccuracy(tolerance_, scales, maxima, dt_, rec);
  // The accuracy reached, per contact node in the serial order, against the bound the
  // step solved with (system units); the equilibrium residual of the other free dofs is r
  // itself (no contact force there).
  if (friction_ <= 0.0)
    bound_.resize(0);
  else if (method_ == StepMethod::kExplicit)
    bound_ = (friction_ / force_scale_) * lambda_.cwiseMax(0.0);
  else
    bound_ = friction_ * step->contact.normal_force.cwiseMax(0.0);
  ::contact::internal::MeasureStepAccuracy(dim_, nodes_, step->r, step->contact,
                                           force_scale_, step->u_next, bound_, &residual_,
                                           rec);
  rec->equilibrium_residual =
      std::max(rec->equilibrium_residual, all.max[RankStepPart::kRFree]);
  rec->accurate = ::contact::internal::StepIsAccurate(*rec);
  contact_force_max_ = (step->r - residual_).lpNorm<Eigen::Infinity>();
  // Energies (energy_balance.hpp).
  energy_.AddExternalWork(
      0.5 * (all.sum[RankStepPart::kFUNext] - all.sum[RankStepPart::kFUPrevious]));
  energy_.AddContactWork(dim_, nodes_, step->r, step->u_next, step->u_previous);
  energy_.Record(all.sum[RankStepPart::kDuMdu], all.sum[RankStepPart::kUKuNext],
                 all.sum[RankStepPart::kUNextKuNext], dt_, rec);
  // Forces, as dynamics.cpp MeasureStep.
  lambda_ = force_scale_ * step->contact.normal_force;
  rec->normal_force_sum = lambda_.sum();
  rec->tangent_force_sum = 0.0;
  for (Eigen::Index c = 0; c < step->contact.tangent_force.cols(); ++c)
    rec->tangent_force_sum += force_scale_ * step->contact.tangent_force.col(c).norm();
  rec->active_nodes = static_cast<int>((lambda_.array() > rec->force_accuracy).count());
  rec->solver_status = "converged";
  // The summary (dynamics.cpp Accumulate) and the guards, in the serial order.
  summary->max_penetration = std::max(summary->max_penetration, rec->max_penetration);
  summary->max_equilibrium_residual =
      std::max(summary->max_equilibrium_residual, rec->equilibrium_residual);
  summary->max_complementarity_residual =
      std::max(summary->max_complementarity_residual, rec->complementarity_residual);
  summary->max_friction_residual =
      std::max(summary->max_friction_residual, rec->friction_residual);
  if (!rec->accurate && summary->inaccurate_steps++ == 0) first_inaccurate_ = *rec;
  summary->energy_balance_error =
      std::max(summary->energy_balance_error, std::abs(rec->energy_balance_error));
  summary->steps = rec->step;
  if (!::contact::internal::EnergyWithinGuard(*rec, energy_.BlowUpReference(),
                                              blowup_factor_, summary))
    return false;
  if (all.sum[RankStepPart::kStopRequested] > 0.0 && rec->step < num_steps) {
    ::contact::internal::SetInterrupted(*rec, num_steps, summary);
    return false;
  }
  return true;
}

void StepRecorder::Finish(DynamicSummary* summary) const {
  ::contact::internal::SetFinalStatus(first_inaccurate_, summary);
}

}  // namespace contact::petsc::internal
