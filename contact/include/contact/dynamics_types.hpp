/// \file dynamics_types.hpp
/// The data of a dynamic contact run (contact/dynamics.hpp): the discretized body on its
/// free dofs, how each step's complementarity system is posed and solved, the options of
/// the run and the record of one step. The integrator and its internal step methods share
/// them.
#pragma once

#include <Eigen/SparseCore>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_system.hpp"
#include "contact/kinematics.hpp"
#include "ncp/solver.hpp"

namespace contact {

/// The critical step of central differences, dt_crit = 2 / omega_max, omega_max^2 the
/// largest eigenvalue of M^-1 K (EstimateCriticalTimeStep, contact/dynamics.hpp).
struct CriticalTimeStep {
  double dt_crit = -1.0;    ///< [s]
  double omega_max = -1.0;  ///< [rad/s]
  int iterations = 0;
  bool converged = false;
};
/// Rayleigh damping C = mass M + stiffness K (contact/src/damping.hpp): modal damping
/// ratio xi(omega) = mass / (2 omega) + stiffness omega / 2.
struct RayleighDamping {
  double mass = 0.0;       ///< a [1/s]
  double stiffness = 0.0;  ///< b [s]
  bool active() const { return mass != 0.0 || stiffness != 0.0; }
};

/// The discretized body on its free dofs.
struct DynamicModel {
  int dim = 0;
  Eigen::SparseMatrix<double> K;  ///< stiffness [N/m], symmetric
  Eigen::SparseMatrix<double>
      M;  ///< mass [kg] (consistent or lumped), symmetric positive definite
  /// External force at time t [N], free dofs; *f arrives sized.
  std::function<void(double t, Eigen::VectorXd* f)> load;
  std::vector<ContactNode> contact_nodes;
  /// Viscous force C v^k with the velocity lagged, v^k = (u^k - u^{k-1}) / dt, added to
  /// the step equation (eq. 68); none by default.
  RayleighDamping damping;
  /// Small or finite strain (contact/kinematics.hpp); null: small strain, K u. Under
  /// finite strain every step evaluates f_int(u^k) where it would form K u^k; the step's
  /// complementarity problem (built from M) is unchanged.
  std::shared_ptr<const BodyKinematics> kinematics;
};

/// How each step's complementarity system is posed and solved: the one choice of the step
/// solver. The semismooth Newton methods (kFull, kCondensed with the lagged bound) take
/// the NCP function and their settings from DynamicOptions::ncp; with friction,
/// kCondensed and kSparse pose it as DynamicOptions::friction_formulation says. (Each
/// method is one class behind the internal interface contact/src/step/step_method.hpp,
/// chosen by MakeStepAlgorithm; a new method is a new file there and one value here.)
enum class StepMethod {
  kFull,       ///< over all free dofs, as the thesis (eq. 82, 90, 94)
  kCondensed,  ///< over the contact unknowns only: the other dofs are eliminated exactly
               ///< with a Cholesky factor of M (CHOLMOD, once); the contact system uses
               ///< the inverse of the Delassus operator W = H M~^-1 H' (dense; H picks
               ///< the free components of the contact nodes, or frictionless only their
               ///< normal displacements), and u is recovered by one more solve per step.
               ///< Same solution as kFull. Set-up: one solve per row of H; each Newton
               ///< iteration factors a dense matrix of that size, so it suits contact
               ///< sets of up to a few thousand unknowns, whatever the size of the body.
  kExplicit,   ///< lumped (diagonal) mass only: every contact node decouples and its step
               ///< is solved in closed form - the normal force closes the predicted gap,
               ///< friction sticks if the trial force is within g_c, else is projected
               ///< onto it (forward-increment Lagrange multipliers, Carpenter, Taylor and
               ///< Katona 1991). Same solution as kFull for a lumped mass; no Newton
               ///< iteration.
  kSparse,     ///< large contact sets, any mass: the problem of kCondensed with implicit
            ///< Coulomb friction (FrictionFormulation::kCoulombFc; f_c = 0 frictionless),
            ///< but W = H M~^-1 H' is never formed - each product with it is one solve
            ///< with the Cholesky factor of M - and each Newton step is solved by GMRES
            ///< (ncp/fc/operator_problem.hpp). No set-up beyond the factor of M, memory
            ///< linear in the contact set; cost per Newton step (GMRES iterations + 2)
            ///< solves with M.
  kIpopt,  ///< frictionless only: the step as the convex QP over all free dofs
           ///< (min 1/2 du' S du + q' du subject to the linearized non-penetration),
           ///< solved by Ipopt's interior-point method (Waechter and Biegler 2006); the
           ///< reference solver of compare_with_ipopt
  kAuto,   ///< the method of least predicted cost per step (StepCostPrediction):
           ///< kExplicit when M is lumped and it solves the same step (frictionless or
  ///< kLaggedBound), else kCondensed or kSparse; kCondensed whenever the friction
  ///< formulation is kLaggedBound with a consistent M
  ///< (DynamicSummary::step_method and predicted_cost tell which ran and why)
};
const char* ToString(StepMethod m);

/// StepMethod::kAuto's prediction of the time of one step [s] of each method it chooses
/// among, from the sizes of the run (free dofs, nonzeros of K, M and of M's Cholesky
/// factor, contact unknowns) and measured rates (contact/src/step/step_method.cpp); < 0:
/// the method cannot take the run. `choice`: the cheapest.
struct StepCostPrediction {
  double explicit_seconds = -1.0, condensed_seconds = -1.0, sparse_seconds = -1.0;
  StepMethod choice = StepMethod::kAuto;
};

/// How a step with friction (f_c > 0) poses Coulomb's law (condensed step only for
/// kCoulombFc).
enum class FrictionFormulation {
  kLaggedBound,  ///< the thesis: Tresca with the lagged bound g_c = f_c lambda_c^k of the
                 ///< previous step (eq. 70) in the mixed NCP of eq. 94 (direction
                 ///< unknowns), solved by ncp with DynamicOptions::ncp
  kCoulombFc,  ///< implicit Coulomb |tau_c| <= f_c lambda_c^{k+1} as the local frictional
               ///< contact problem in Delassus form u = E W E' r + q (contact/src/step/
               ///< coulomb_step.hpp), solved by ncp::fc's hybrid semismooth Newton
};
const char* ToString(FrictionFormulation f);

enum class InitialState {
  kStaticEquilibrium,  ///< u^0 = static frictionless contact equilibrium for f(t0), v =
                       ///< 0, u^{-1} = u^0 (thesis section 4.3)
  kPrescribed,  ///< u^0, v^0 given; u^{-1} = u^0 - dt v^0 + dt^2/2 M^-1 (f(t0) - K u^0)
};

/// One completed step k -> k+1.
struct StepRecord {
  int step = 0;       ///< k + 1
  double time = 0.0;  ///< t_{k+1} [s]
  int newton_iterations = 0, jacobian_evaluations = 0, residual_evaluations = 0;
  /// GMRES iterations over the step's Newton systems (StepMethod::kSparse; 0 otherwise):
  /// each is one solve with M's factor.
  int krylov_iterations = 0;
  double seconds = 0.0;        ///< the whole step [s]
  double solve_seconds = 0.0;  ///< of which the complementarity solve (Newton iterations,
                               ///< Ipopt, or the closed form) [s]
  std::string solver_status;
  double kinetic = 0.0;               ///< 1/2 v' M v, v = (u^{k+1} - u^k) / dt [J]
  double strain = 0.0;                ///< 1/2 (u^{k+1})' K u^{k+1} [J]
  double external_work = 0.0;         ///< cumulative [J]
  double normal_contact_work = 0.0;   ///< cumulative [J] (<= 0: impacts dissipate)
  double friction_dissipation = 0.0;  ///< cumulative [J] (>= 0)
  double damping_dissipation = 0.0;   ///< cumulative work of C v^k [J] (RayleighDamping)
  double energy_balance_error = 0.0;  ///< E - E0 - W_ext - W_contact + D_damping [J]
  double normal_force_sum = 0.0;      ///< sum_c lambda_c [N]
  double tangent_force_sum = 0.0;     ///< sum_c |tau_c| [N]
  double max_penetration =
      0.0;               ///< max_c max(0, -gap_c), gap_c = s_c - n_c . u^{k+1}_c [m]
  int active_nodes = 0;  ///< nodes with lambda_c > force_accuracy [N]
  /// Accuracy of the step, recomputed from u^{k+1}, u^k, u^{k-1} and the contact result
  /// (see StepAccuracy): largest nodal equilibrium residual [N], contact-force residual
  /// [N] and friction-law violation [N], and what the step was asked for (force_accuracy
  /// [N], displacement_accuracy [m]).
  double equilibrium_residual = 0.0, complementarity_residual = 0.0,
         friction_residual = 0.0;
  double force_accuracy = 0.0, displacement_accuracy = 0.0;
  bool accurate = true;  ///< every measure within kAccuracySlack times its accuracy
  /// With DynamicOptions::compare_with_ipopt: ||du - du_ipopt||_inf / max(||du||_inf,
  /// 1e-300) for the same step data (-1 when not compared).
  double ipopt_relative_difference = -1.0;
};

/// The scales each step is solved against (the stopping rule of every step method):
///   force scale F [N] = max(|f(t_k)|_inf, |K u^k|_inf, |r^k|_inf): the largest applied,
///       elastic or contact nodal force of the step (r^k: the previous step's contact
///       forces);
///   displacement scale D [m] = max(|u^k - u^{k-1}|_inf, F dt^2 / m_max, max_c -gap_c):
///       the motion of a step, and at least the displacement the force scale produces in
///       one step of the heaviest node (the same number in the step's own units, M /
///       m_max);
///   if F = 0 it is taken as D m_max / dt^2 (a body in free flight: the force that would
///   stop the heaviest node in one step), and if both are 0 (nothing moves, loads or
///   touches) as 1.
/// Every force row is then solved to tolerance F (+ its round-off) and every gap or slip
/// row to tolerance D (+ its round-off): contact forces in flight below tolerance F,
/// penetration below tolerance D, with tolerance = ncp.tolerance (relative, default
/// 1e-10). After the step the accuracy is measured independently (StepRecord) and a step
/// whose equilibrium residual, contact or friction residual exceeds kAccuracySlack times
/// force_accuracy = tolerance F + round-off, or whose penetration exceeds kAccuracySlack
/// times displacement_accuracy = tolerance D + round-off, makes the run end as
/// kAccuracyNotReached. (The slack covers the change from the contact frames to the
/// global components and the NCP function: |phi_FB(a, b)| <= 1 bounds min(a, b) by 1 / (2
/// - sqrt 2) = 1.71.)
inline constexpr double kAccuracySlack = 10.0;

struct DynamicOptions {
  double dt = 0.0;                    ///< time step [s]
  double start_time = 0.0;            ///< t_0 [s]
  double end_time = 0.0;              ///< run until t >= end_time (within dt/1000) [s]
  double friction_coefficient = 0.0;  ///< f_c (0 = frictionless)
  /// How each step is posed and solved; kFull for the thesis formulation.
  StepMethod step_method = StepMethod::kAuto;
  /// With friction and the condensed step (the full and explicit steps always use the
  /// lagged bound; the sparse step only kCoulombFc). kCoulombFc uses of `ncp` only
  /// ncp.tolerance, ncp.max_iterations and ncp.log_to_stderr. Default kCoulombFc:
  /// implicit Coulomb is the law itself, not a fixed point on it (README, "Coulomb
  /// friction in Delassus form").
  FrictionFormulation friction_formulation = FrictionFormulation::kCoulombFc;
  /// Semismooth Newton settings of the Newton-based step methods, ncp.ncp_function among
  /// them (Fischer-Burmeister by default, or min, or penalized FB). `tolerance` is
  /// relative to the step's force and displacement scales (see kAccuracySlack above), and
  /// also Ipopt's (kIpopt, compare_with_ipopt). Default min tie: a touching node counts
  /// as closed.
  ncp::Options ncp = ContactNcpOptions();
  InitialState initial_state = InitialState::kStaticEquilibrium;
  Eigen::VectorXd u0, v0;  ///< for kPrescribed (free dofs) [m], [m/s]
  /// Frictionless runs: also solve every step's QP with Ipopt and record the relative
  /// difference of the increments (a reference check; slow). Ipopt stops at its scaled
  /// test tol = ncp.tolerance and its unscaled tests set from the step's scales:
  /// stationarity to tolerance F, constraint violation to tolerance D, lambda_c gap_c to
  /// tolerance F D.
  bool compare_with_ipopt = false;
  /// Refuse dt > dt_crit unless this is set.
  bool allow_unstable_time_step = false;
  /// Stop with kEnergyBlowUp when kinetic + strain energy exceeds this factor times
  /// (their initial value + sum of |external work increments|), once that is > 0. (The
  /// shadow energy of the balance stays bounded even in an unstable run, so it is not
  /// used.)
  double energy_blowup_factor = 100.0;
  /// Called after every step with the record and the state (u^{k+1}, contact result).
  std::function<void(const StepRecord&, const Eigen::VectorXd& u,
                     const ContactSystem::Result& contact, double force_scale)>
      on_step;
  /// Print a progress line on stderr about once per second.
  bool progress = false;
  /// Read between steps (after on_step): once it is true the run ends there with
  /// DynamicStatus::kInterrupted - every finished step recorded and passed to on_step,
  /// none started. Lock-free, so a signal handler may set it (contact-sim does on
  /// SIGINT/SIGTERM); nullptr: never.
  const std::atomic<bool>* stop_requested = nullptr;
};

}  // namespace contact
