// The accuracy of a dynamic step in physical units: the scales it is solved against and
// what it reached, recomputed from the state (contact/dynamics_types.hpp,
// kAccuracySlack).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "contact/dynamics.hpp"
#include "contact/dynamics_types.hpp"

namespace contact::internal {

/// The scales a step is solved against, in newtons and metres.
struct StepScales {
  double force = 0.0;         ///< F [N]
  double displacement = 0.0;  ///< D [m]
};

/// F = max(|f^k|_inf, |K u^k|_inf, |r^k|_inf) and D = max(|u^k - u^{k-1}|_inf, F dt^2 /
/// m_max, max_c -gap_c) with the fallbacks of dynamics_types.hpp (kAccuracySlack)
/// (contact_force_max = |r^k|_inf [N]).
StepScales ComputeStepScales(const Eigen::VectorXd& f, const Eigen::VectorXd& Ku,
                             double contact_force_max, const Eigen::VectorXd& du_previous,
                             const std::vector<ContactNode>& nodes,
                             const Eigen::VectorXd& u, double m_max, double dt);
/// The same from the maxima: f_max = |f^k|_inf, Ku_max = |K u^k|_inf [N], du_max =
/// |u^k - u^{k-1}|_inf [m], penetration = max_c (n_c . u^k_c - s_c) [m] (for a caller
/// that reduces them over MPI ranks).
StepScales StepScalesFromMaxima(double f_max, double Ku_max, double contact_force_max,
                                double du_max, double penetration, double m_max,
                                double dt);

/// The same scales from the maxima that enter them (a run on MPI ranks reduces each over
/// the ranks): f_max = |f^k|_inf, Ku_max = |K u^k|_inf, contact_force_max = |r^k|_inf
/// [N]; du_max = |u^k - u^{k-1}|_inf [m]; penetration = max(0, max_c (n_c . u^k_c -
/// s_c)) [m]; m_max [kg]; dt [s].
StepScales StepScalesFromMaxima(double f_max, double Ku_max, double contact_force_max,
                                double du_max, double penetration, double m_max,
                                double dt);

/// The maxima SetAskedAccuracy takes from its vectors: |Q|_inf, |M du|_inf [N, kg m],
/// |u^{k+1}|_inf and |s|_inf [m].
struct AskedAccuracyMaxima {
  double Q = 0.0, Mdu = 0.0, u_next = 0.0, gap0 = 0.0;
};

/// The accuracy a step is asked for, into rec->force_accuracy [N] and
/// rec->displacement_accuracy [m]: tolerance times the scales plus the round-off of the
/// terms of r = M du / dt^2 + Q (Q = Q^k, Mdu = M du) and of the positions (u^{k+1}, the
/// gaps s_c).
void SetAskedAccuracy(double tolerance, const StepScales& scales,
                      const Eigen::VectorXd& Q, const Eigen::VectorXd& Mdu, double dt,
                      const Eigen::VectorXd& u_next, const Eigen::VectorXd& gap0,
                      StepRecord* rec);
/// The same from the maxima (a run on MPI ranks reduces each over the ranks).
void SetAskedAccuracy(double tolerance, const StepScales& scales,
                      const AskedAccuracyMaxima& maxima, double dt, StepRecord* rec);

/// Accuracy of a completed step, recomputed from the state in newtons and metres (the
/// residuals, penetration and `accurate` of rec; rec's asked accuracies must be set).
/// r = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k - f^k [N]; contact and bound in system
/// units (times force_scale for newtons). *residual = r minus the contact forces.
void MeasureStepAccuracy(int dim, const std::vector<ContactNode>& nodes,
                         const Eigen::VectorXd& r, const ContactSystem::Result& contact,
                         double force_scale, const Eigen::VectorXd& u_next,
                         const Eigen::VectorXd& bound, Eigen::VectorXd* residual,
                         StepRecord* rec);

/// rec->accurate from rec's measures and asked accuracies: every measure within
/// kAccuracySlack times its accuracy.
bool StepIsAccurate(const StepRecord& rec);

/// The status of a run that went to the end (summary->status still kNotRun): completed,
/// or kAccuracyNotReached naming the first inaccurate step and how many missed.
void SetFinalStatus(const StepRecord& first_inaccurate, DynamicSummary* summary);

/// A run stopped on request (DynamicOptions::stop_requested) after the step of rec, of
/// num_steps: kInterrupted and its message.
void SetInterrupted(const StepRecord& rec, long num_steps, DynamicSummary* summary);

}  // namespace contact::internal
