// The central-difference time integrator (contact/dynamics.hpp, contact/simulation.hpp).
// The step methods live behind internal::StepAlgorithm (step/step_method.hpp, one file
// each), the critical step in critical_time_step.cpp, the accuracy measures in
// step_accuracy.cpp and the energy bookkeeping in energy_balance.cpp; this file holds the
// step of the time loop (CentralDifferences), Simulation around it and RunDynamics as a
// loop over Simulation::Step. The scene constructor of Simulation is in
// scene/scene_simulation.cpp.
#include "contact/dynamics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include "checkpoint.hpp"
#include "contact/convex_qp.hpp"
#include "contact/simulation.hpp"
#include "contact/static_contact.hpp"
#include "critical_time_step.hpp"
#include "damping.hpp"
#include "energy_balance.hpp"
#include "internal_force.hpp"
#include "mass_inverse.hpp"
#include "parallel.hpp"
#include "step/step_method.hpp"
#include "step_accuracy.hpp"
#include "text_format.hpp"

namespace contact {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

const char* const kWho = "contact::RunDynamics: ";

// The number of steps to reach end_time (within dt / 1000), in double.
double NumSteps(const DynamicOptions& options) {
  return std::ceil((options.end_time - options.start_time) / options.dt - 1e-3);
}

// Misuse at the API boundary: throws std::invalid_argument.
void Validate(const DynamicModel& model, const DynamicOptions& options) {
  const Eigen::Index n = model.K.rows();
  const std::string who = kWho;
  if (model.dim != 2 && model.dim != 3)
    throw std::invalid_argument(who + "dim must be 2 or 3, got " +
                                std::to_string(model.dim));
  if (model.M.rows() != n || model.M.cols() != n || model.K.cols() != n)
    throw std::invalid_argument(who + "K and M must both be " + std::to_string(n) +
                                " x " + std::to_string(n));
  if (!model.load) throw std::invalid_argument(who + "the load function is not set");
  if (!(options.dt > 0.0) || !std::isfinite(options.dt))
    throw std::invalid_argument(who + "dt must be > 0, got " +
                                std::to_string(options.dt));
  if (!(options.end_time >= options.start_time) || !std::isfinite(options.end_time) ||
      !std::isfinite(options.start_time))
    throw std::invalid_argument(who + "end_time must be finite and >= start_time");
  // Counted in double: (end_time - start_time) / dt may exceed every integer type.
  const double step_count = NumSteps(options);
  if (!(step_count <= kMaxTimeSteps))
    throw std::invalid_argument(
        who + "(end_time - start_time) / dt = " + internal::FormatShort(step_count) +
        " time steps; at most " + internal::FormatShort(kMaxTimeSteps) + " are accepted");
  if (!(options.friction_coefficient >= 0.0))
    throw std::invalid_argument(who + "friction_coefficient must be >= 0, got " +
                                std::to_string(options.friction_coefficient));
  if ((options.step_method == StepMethod::kIpopt || options.compare_with_ipopt) &&
      !BuiltWithIpopt())
    throw std::invalid_argument(who +
                                "the Ipopt step (solver.step = \"ipopt\", "
                                "compare_with_ipopt) cannot run: " +
                                kWithoutIpopt);
  if ((options.step_method == StepMethod::kIpopt || options.compare_with_ipopt) &&
      options.friction_coefficient > 0.0)
    throw std::invalid_argument(who +
                                "the Ipopt step handles frictionless contact only "
                                "(friction_coefficient = " +
                                std::to_string(options.friction_coefficient) + ")");
  if (!internal::IsSymmetric(model.K, 1e-12) || !internal::IsSymmetric(model.M, 1e-12))
    throw std::invalid_argument(
        who + "K and M must be symmetric (to 1e-12 of their largest entry)");
  if (options.initial_state == InitialState::kPrescribed &&
      (options.u0.size() != n || options.v0.size() != n))
    throw std::invalid_argument(who + "prescribed u0 and v0 must have size " +
                                std::to_string(n));
}

// Stability: central differences need dt <= 2 / omega_max. False (and the summary says
// why) if dt exceeds it without allow_unstable_time_step.
bool CheckCriticalStep(const DynamicModel& model, const DynamicOptions& options,
                       internal::MassInverse* mass, DynamicSummary* summary) {
  const CriticalTimeStep crit = internal::WithDamping(
      internal::Lanczos(model.K, model.M, mass, kCriticalStepTolerance,
                        kCriticalStepMaxIterations),
      model.damping);
  if (internal::AcceptCriticalStep(crit, options, summary)) return true;
  summary->message += internal::DampedCriticalStepNote(crit, model.damping);
  return false;
}

}  // namespace

bool internal::AcceptCriticalStep(const CriticalTimeStep& crit,
                                  const DynamicOptions& options,
                                  DynamicSummary* summary) {
  summary->critical_time_step = crit.dt_crit;
  // omega_max = 0 (no stiffness, e.g. a rigid mass) gives dt_crit = inf: any dt is
  // stable.
  if (!(crit.dt_crit > 0) || !(crit.omega_max >= 0) || !std::isfinite(crit.omega_max))
    throw std::invalid_argument(
        std::string(kWho) +
        "the critical time step 2/omega_max = " + internal::FormatShort(crit.dt_crit) +
        " s is not a positive finite number (omega_max = " +
        internal::FormatShort(crit.omega_max) +
        " rad/s): K or M is out of the range of double precision (check the "
        "Young's modulus [Pa], density [kg/m^3] and mesh size [m])");
  if (!(options.dt > crit.dt_crit) || options.allow_unstable_time_step) return true;
  summary->status = DynamicStatus::kRefusedUnstable;
  char buffer[512];
  std::snprintf(
      buffer, sizeof buffer,
      "time step dt = %.6g s exceeds the critical step dt_crit = 2/omega_max = %.6g s "
      "of central differences (omega_max = %.6g rad/s): choose dt <= %.6g s (scene key "
      "time.dt), or set time.allow_unstable = true in the scene "
      "(DynamicOptions::allow_unstable_time_step in C++) to run anyway",
      options.dt, crit.dt_crit, crit.omega_max, crit.dt_crit);
  summary->message = buffer;
  return false;
}

namespace {

// The state of the integrator between steps k-1 -> k and k -> k+1: the carried part
// (checkpoint.hpp: displacements, the products with K and M carried between steps so that
// none is formed twice, and what the next step starts from) and the step's buffers, so
// that nothing is allocated in the loop.  Mdu = M (u^{k+1} - u^k).
struct State : internal::CarriedState {
  Eigen::VectorXd f;  // f(t_k) [N]
  // Step k -> k+1 (buffers).
  Eigen::VectorXd Q, q, bound, u_next, Ku_next, Mdu, r, residual, lambda_next;
  Eigen::VectorXd damping_force;  // C v^k [N] (damping.hpp)
  double W = 0.0, W_next = 0.0;  // stored energy at u^k, u^{k+1} [J] (internal_force.hpp)
};

// Initial state (thesis section 4.3): static frictionless equilibrium for f(t0) at rest,
// or u^{-1} = u^0 - dt v^0 + dt^2/2 M^-1 (f(t0) - K u^0) from a prescribed u^0, v^0.
// False (and the summary says why) if the static solve failed.
bool SetInitialState(const DynamicModel& model, const DynamicOptions& options,
                     internal::MassInverse* mass, State* state, DynamicSummary* summary) {
  const Eigen::Index n = model.K.rows();
  const double dt = options.dt;
  state->f.resize(n);
  model.load(options.start_time, &state->f);
  state->lambda =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.contact_nodes.size()));
  if (options.initial_state == InitialState::kStaticEquilibrium) {
    StaticContactOptions static_options;
    static_options.ncp = options.ncp;
    const StaticContactResult s = SolveStaticContact(model.dim, model.K, state->f,
                                                     model.contact_nodes, static_options);
    if (!s.converged) {
      summary->status = DynamicStatus::kSolverFailure;
      summary->message = "static initial state: " + s.message;
      return false;
    }
    state->u = s.u;
    state->u_previous = state->u;
    state->lambda = s.normal_force;
  } else {
    state->u = options.u0;
    Eigen::VectorXd a0(n);  // M a0 = f - K u0
    mass->Solve(state->f - model.K * state->u, &a0);
    state->u_previous = state->u - dt * options.v0 + 0.5 * dt * dt * a0;
  }
  // (Products by internal::SymmetricMultiply: parallel, same result for any thread
  // count.)
  state->Ku.resize(n);
  state->Mdu_previous.resize(n);
  state->Mdu = state->u - state->u_previous;  // (as a temporary for the product)
  internal::SymmetricMultiply(model.K, state->u, &state->Ku);
  internal::SymmetricMultiply(model.M, state->Mdu, &state->Mdu_previous);
  state->du = state->u - state->u_previous;
  for (Eigen::VectorXd* v : {&state->Q, &state->q, &state->r, &state->residual,
                             &state->u_next, &state->Ku_next, &state->Mdu})
    v->resize(n);
  return true;
}

// One step of the time loop, k -> k+1: load and q, scales, solve, accuracy, energy,
// record, advance, guards. Between steps the load and the gaps s_c may change.
class CentralDifferences {
 public:
  CentralDifferences(const DynamicModel& model, const DynamicOptions& options,
                     internal::MassInverse* mass, State* state, DynamicSummary* summary)
      : model_(model),
        options_(options),
        mass_(mass),
        state_(*state),
        summary_(*summary),
        dt_(options.dt),
        m_max_(internal::MaxAbsEntry(model.M)),
        force_scale_(m_max_ / (dt_ * dt_)),
        method_(internal::MakeStepAlgorithm(model, options, mass, m_max_)),
        energy_(state->u, state->u_previous, state->Ku, state->Mdu_previous, dt_),
        forces_(model),
        load_(model.load),
        nodes_(model.contact_nodes),
        damping_(model, options.dt) {
    StartInternalForce();
    // The frictionless reference of compare_with_ipopt, next to any other step method.
    if (options.compare_with_ipopt && options.step_method != StepMethod::kIpopt)
      reference_ =
          std::make_unique<internal::IpoptQp>(model, m_max_, options.ncp.tolerance);
    summary->step_method = internal::ResolveStepMethod(model, options, *mass);
    summary->predicted_cost = internal::PredictStepCost(model, options, *mass);
    gap0_.resize(static_cast<Eigen::Index>(nodes_.size()));
    for (size_t c = 0; c < nodes_.size(); ++c)
      gap0_(static_cast<Eigen::Index>(c)) = nodes_[c].gap;
  }

  /// Step k -> k+1. False (and summary_ says why) if the run must stop here.
  bool Step(long k) {
    const auto step_start = Clock::now();
    StepRecord rec;
    rec.step = static_cast<int>(k + 1);
    rec.time = options_.start_time + static_cast<double>(k) * dt_ + dt_;
    const internal::StepScales scales = LoadStep(k);
    const auto solve_start = Clock::now();
    summary_.assembly_seconds +=
        std::chrono::duration<double>(solve_start - step_start).count();
    const double mass_seconds = mass_->solve_seconds();
    const long mass_solves = mass_->solves();
    const bool solved = SolveStep(k, scales, &rec);
    summary_.mass_solve_seconds += mass_->solve_seconds() - mass_seconds;
    summary_.mass_solves += mass_->solves() - mass_solves;
    summary_.contact_solve_seconds +=
        Seconds(solve_start) - (mass_->solve_seconds() - mass_seconds);
    if (!solved || !MeasureStep(scales, &rec)) return false;
    rec.seconds = Seconds(step_start);
    Accumulate(rec);
    Advance();
    return GuardEnergy(rec) && !StopRequested(rec);
  }

  /// The load from the next step on.
  void SetLoad(std::function<void(double, Eigen::VectorXd*)> load) {
    load_ = std::move(load);
  }
  /// s_c [m] from the next step on (checked by the caller).
  void SetGaps(const Eigen::VectorXd& gaps) {
    gap0_ = gaps;
    for (size_t c = 0; c < nodes_.size(); ++c)
      nodes_[c].gap = gaps(static_cast<Eigen::Index>(c));
  }
  const Eigen::VectorXd& gaps() const { return gap0_; }
  /// The obstacle's translation over the next step [m]: the friction slip is relative to
  /// it, which only some step methods take (step_method.hpp, TakesObstacleSlip).
  void AddObstacleStep(const Eigen::VectorXd& increment) {
    if (options_.friction_coefficient > 0.0 && !method_->TakesObstacleSlip() &&
        increment.norm() > 0.0)
      throw std::invalid_argument(
          std::string(kWho) + "the obstacle moves with friction (coefficient " +
          internal::FormatShort(options_.friction_coefficient) +
          "): the slip relative to a moving obstacle is taken by the explicit step only "
          "(solver.step = \"explicit\"), not the " +
          ToString(summary_.step_method) + " step");
    if (obstacle_step_.size() == 0)
      obstacle_step_ = Eigen::VectorXd::Zero(increment.size());
    obstacle_step_ += increment;
  }
  double force_scale() const { return force_scale_; }
  const StepRecord& first_inaccurate() const { return first_inaccurate_; }

  /// What a checkpoint needs besides State and the summary.
  void Save(internal::CheckpointData* data) const {
    data->gaps = gap0_;
    data->energy = energy_;
    data->warm_start = method_->WarmStart();
    data->first_inaccurate = first_inaccurate_;
  }
  /// Restores Save's part (sizes checked by the caller; the warm start's by the method,
  /// which throws std::invalid_argument before it changes anything).
  void Restore(const internal::CheckpointData& data) {
    method_->SetWarmStart(data.warm_start);
    SetGaps(data.gaps);
    energy_ = data.energy;
    first_inaccurate_ = data.first_inaccurate;
    forces_.Restore(data.summary);
  }
  /// After the carried state is restored: the stored energy W(u^k) (not carried).
  void RestoreStoredEnergy() {
    State& s = state_;
    Eigen::VectorXd f(s.u.size());
    s.W = forces_.finite() ? model_.kinematics->FiniteForce(s.u, &f).energy
                           : 0.5 * s.u.dot(s.Ku);
  }
  /// False if the internal force of u^0 could not be evaluated (the summary says why).
  bool started() const { return summary_.status == DynamicStatus::kNotRun; }

 private:
  // Q^k = M (u^{k-1} - u^k) / dt^2 + K u^k - f^k (eq. 73), q = Q^k dt^2 / m_max (eq. 81),
  // the Tresca bounds f_c lambda^k (eq. 70), and the step's scales (dynamics_types.hpp,
  // kAccuracySlack).
  internal::StepScales LoadStep(long k) {
    State& s = state_;
    load_(options_.start_time + static_cast<double>(k) * dt_, &s.f);
    s.Q = s.Ku - s.f - s.Mdu_previous / (dt_ * dt_);
    if (damping_.active()) {  // + C v^k, v^k = (u^k - u^{k-1}) / dt (damping.hpp)
      damping_.Compute(s.Mdu_previous, s.du, &s.damping_force);
      s.Q += s.damping_force;
    }
    s.q = s.Q / force_scale_;
    if (options_.friction_coefficient > 0.0)
      s.bound = (options_.friction_coefficient / force_scale_) * s.lambda.cwiseMax(0.0);
    else
      s.bound.resize(0);
    s.Mdu = s.u - s.u_previous;  // (du of the previous step, as a temporary)
    return internal::ComputeStepScales(s.f, s.Ku, s.contact_force_max, s.Mdu, nodes_, s.u,
                                       m_max_, dt_);
  }

  // The step method, and the Ipopt reference. False (and the summary says why) on
  // failure.
  bool SolveStep(long k, const internal::StepScales& scales, StepRecord* rec) {
    State& s = state_;
    const internal::StepData data{
        s.q,    s.u,          s.bound, s.du,
        scales, force_scale_, gap0_,   obstacle_step_.size() ? &obstacle_step_ : nullptr};
    const internal::StepOutcome outcome = method_->Solve(data, &s.contact);
    obstacle_step_.resize(0);  // (the next step's is set anew)
    rec->solve_seconds = outcome.solve_seconds;
    rec->solver_status = outcome.status;
    rec->newton_iterations = outcome.newton_iterations;
    rec->jacobian_evaluations = outcome.jacobian_evaluations;
    rec->residual_evaluations = outcome.residual_evaluations;
    rec->krylov_iterations = outcome.krylov_iterations;
    summary_.friction_restarts += outcome.friction_restarts;
    // Implicit Coulomb: the bound the step was solved (and is measured) against is
    // f_c lambda^{k+1}, not the lagged f_c lambda^k.
    if (outcome.implicit_friction_bound)
      s.bound = options_.friction_coefficient * s.contact.normal_force.cwiseMax(0.0);
    if (outcome.ok && reference_) CompareWithIpopt(data, rec);
    summary_.newton_iterations += rec->newton_iterations;
    summary_.jacobian_evaluations += rec->jacobian_evaluations;
    summary_.residual_evaluations += rec->residual_evaluations;
    summary_.krylov_iterations += rec->krylov_iterations;
    if (outcome.ok) return true;
    summary_.status = DynamicStatus::kSolverFailure;
    summary_.message = "step " + std::to_string(k + 1) +
                       " (t = " + std::to_string(rec->time) +
                       " s): " + rec->solver_status;
    return false;
  }

  // ||du - du_ipopt||_inf / max(||du||_inf, 1e-300) for the same step data.
  void CompareWithIpopt(const internal::StepData& data, StepRecord* rec) {
    const ConvexQpResult qp = reference_->Solve(data);
    rec->ipopt_relative_difference =
        qp.status == ConvexQpStatus::kSolved
            ? (state_.contact.x - qp.x).lpNorm<Eigen::Infinity>() /
                  std::max(state_.contact.x.lpNorm<Eigen::Infinity>(), 1e-300)
            : std::numeric_limits<double>::infinity();
    summary_.max_ipopt_relative_difference =
        std::max(summary_.max_ipopt_relative_difference, rec->ipopt_relative_difference);
  }

  // The internal force and stored energy of u^0 under finite strain from the start, and
  // the shadow energy E^{-1/2} = kinetic + W(u^0) - f(u^0) . (u^0 - u^{-1}) / 2 (equal
  // to kinetic + (u^{-1})' K u^0 / 2 for a quadratic W).
  void StartInternalForce() {
    State& s = state_;
    s.W = 0.5 * s.u.dot(s.Ku);
    if (!forces_.finite()) return;
    if (!forces_.Evaluate(0, options_.start_time, s.u, &s.Ku, &s.W, &summary_)) return;
    energy_.strain0 = s.W;
    energy_.energy0 = energy_.kinetic0 + s.W - 0.5 * s.Ku.dot(s.u - s.u_previous);
  }

  // u^{k+1}, the contact forces r^{k+1} = M (u^{k+1} - 2u^k + u^{k-1}) / dt^2 + K u^k -
  // f^k [N] (f_int(u^k) for K u^k under finite strain), the accuracy asked for and
  // reached (step_accuracy.hpp), the energies, the forces. False (and the summary says
  // why) if the internal force of u^{k+1} cannot be evaluated.
  bool MeasureStep(const internal::StepScales& scales, StepRecord* rec) {
    const auto products_start = Clock::now();
    State& s = state_;
    s.du = s.contact.x;
    s.u_next = s.u + s.du;
    internal::SymmetricMultiply(model_.M, s.du, &s.Mdu);
    if (!forces_.Evaluate(rec->step, rec->time, s.u_next, &s.Ku_next, &s.W_next,
                          &summary_) ||
        !forces_.RecheckCriticalStep(rec->step, s.u_next, options_, mass_, &summary_))
      return false;
    const auto check_start = Clock::now();
    s.r = s.Mdu / (dt_ * dt_) + s.Q;
    internal::SetAskedAccuracy(options_.ncp.tolerance, scales, s.Q, s.Mdu, dt_, s.u_next,
                               gap0_, rec);
    internal::MeasureStepAccuracy(model_.dim, nodes_, s.r, s.contact, force_scale_,
                                  s.u_next, s.bound, &s.residual, rec);
    s.contact_force_max = (s.r - s.residual).lpNorm<Eigen::Infinity>();
    energy_.AddStepWork(model_.dim, nodes_, s.f, s.r, s.u_next, s.u_previous);
    if (damping_.active())
      energy_.AddDampingWork(s.damping_force, s.u_next, s.u_previous);
    // Finite strain: E^{k+1/2} = kinetic + W(u^k) + f(u^k) . du / 2, the form of the
    // linear shadow energy (u^k)' K u^{k+1} / 2 that holds for any W (its balance error
    // is third order in du).
    if (forces_.finite())
      energy_.Record(s.du.dot(s.Mdu), 2.0 * s.W + s.Ku.dot(s.du), 2.0 * s.W_next, dt_,
                     rec);
    else
      energy_.Record(s.du, s.Mdu, s.u, s.u_next, s.Ku_next, dt_, rec);
    s.lambda_next = force_scale_ * s.contact.normal_force;
    rec->normal_force_sum = s.lambda_next.sum();
    for (Eigen::Index c = 0; c < s.contact.tangent_force.cols(); ++c)
      rec->tangent_force_sum += force_scale_ * s.contact.tangent_force.col(c).norm();
    // In contact: a normal force above the step's force accuracy [N]; below it the force
    // is round-off of a node in flight (e.g. 3.9e-19 N after a bounce), not contact.
    rec->active_nodes =
        static_cast<int>((s.lambda_next.array() > rec->force_accuracy).count());
    const double check_seconds = Seconds(check_start);
    summary_.accuracy_check_seconds += check_seconds;
    summary_.assembly_seconds += Seconds(products_start) - check_seconds;
    return true;
  }

  // The summary's maxima and counts, the record, and the caller's on_step.
  void Accumulate(const StepRecord& rec) {
    summary_.max_penetration = std::max(summary_.max_penetration, rec.max_penetration);
    summary_.max_equilibrium_residual =
        std::max(summary_.max_equilibrium_residual, rec.equilibrium_residual);
    summary_.max_complementarity_residual =
        std::max(summary_.max_complementarity_residual, rec.complementarity_residual);
    summary_.max_friction_residual =
        std::max(summary_.max_friction_residual, rec.friction_residual);
    if (!rec.accurate && summary_.inaccurate_steps++ == 0) first_inaccurate_ = rec;
    summary_.energy_balance_error =
        std::max(summary_.energy_balance_error, std::abs(rec.energy_balance_error));
    summary_.steps = rec.step;
    summary_.records.push_back(rec);
    if (options_.on_step)
      options_.on_step(rec, state_.u_next, state_.contact, force_scale_);
  }

  // u^{k-1} <- u^k <- u^{k+1}, with the products and forces that go along.
  void Advance() {
    State& s = state_;
    s.lambda.swap(s.lambda_next);
    s.u_previous.swap(s.u);
    s.u.swap(s.u_next);
    s.Ku.swap(s.Ku_next);
    s.W = s.W_next;
    s.Mdu_previous.swap(s.Mdu);
  }

  // DynamicOptions::stop_requested, read once a step is finished and recorded.
  bool StopRequested(const StepRecord& rec) {
    const long num_steps = static_cast<long>(NumSteps(options_));
    if (!options_.stop_requested || !options_.stop_requested->load() ||
        rec.step >= num_steps)
      return false;
    internal::SetInterrupted(rec, num_steps, &summary_);
    return true;
  }

  // Kinetic + strain energy within energy_blowup_factor of the initial energy and
  // external work. (The reference is zero until energy enters - a body at rest under a
  // step load -: no ratio test before that, so round-off energy cannot trip it.) The
  // shadow energy of the balance cannot reveal an instability (its cross term turns
  // negative).
  bool GuardEnergy(const StepRecord& rec) {
    return internal::EnergyWithinGuard(rec, energy_.BlowUpReference(),
                                       options_.energy_blowup_factor, &summary_);
  }

  const DynamicModel& model_;
  const DynamicOptions& options_;
  internal::MassInverse*
      mass_;  // M^-1 of the run (its solve timers: the mass-solve phase)
  State& state_;
  DynamicSummary& summary_;
  const double dt_;
  const double m_max_;        // largest entry of M [kg]: S = M / m_max
  const double force_scale_;  // m_max / dt^2: system units -> newtons
  std::unique_ptr<internal::StepAlgorithm> method_;
  std::unique_ptr<internal::IpoptQp> reference_;
  internal::EnergyBalance energy_;
  internal::InternalForce forces_;  // K u or f_int(u), and the kinematics' switch
  std::function<void(double, Eigen::VectorXd*)>
      load_;                        // f(t) [N] (DynamicModel::load at first)
  std::vector<ContactNode> nodes_;  // the model's, with the current gaps s_c
  Eigen::VectorXd gap0_;            // s_c [m]
  StepRecord first_inaccurate_;
  internal::DampingForce damping_;  // C v^k (none unless model.damping is set)
  Eigen::VectorXd obstacle_step_;   // the obstacle's translation over the step [m]
};

}  // namespace

void SymmetricMultiply(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                       Eigen::VectorXd* y) {
  if (A.rows() != A.cols() || x.size() != A.cols())
    throw std::invalid_argument(
        "SymmetricMultiply: A must be square with as many columns as x has entries");
  internal::SymmetricMultiply(A, x, y);
}

const char* ToString(DynamicStatus s) {
  switch (s) {
    case DynamicStatus::kNotRun:
      return "not-run";
    case DynamicStatus::kCompleted:
      return "completed";
    case DynamicStatus::kSolverFailure:
      return "solver-failure";
    case DynamicStatus::kEnergyBlowUp:
      return "energy-blow-up";
    case DynamicStatus::kRefusedUnstable:
      return "refused-unstable-time-step";
    case DynamicStatus::kAccuracyNotReached:
      return "accuracy-not-reached";
    case DynamicStatus::kInterrupted:
      return "interrupted";
    case DynamicStatus::kInvertedElement:
      return "inverted-element";
    case DynamicStatus::kOutsideSmallStrain:
      return "outside-small-strain";
  }
  return "unknown";
}

const char* ToString(SimulationState s) {
  switch (s) {
    case SimulationState::kRunning:
      return "running";
    case SimulationState::kFinished:
      return "finished";
    case SimulationState::kFailed:
      return "failed";
  }
  return "unknown";
}

// The integrator and everything it reads between steps (simulation.hpp lists the state).
struct Simulation::Impl {
  Impl(const DynamicModel& model_in, DynamicOptions options_in)
      : start(Clock::now()),
        model((Validate(model_in, options_in), model_in)),
        options(std::move(options_in)),
        mass(model.M, kWho),
        num_steps(static_cast<long>(NumSteps(options))) {
    if (CheckCriticalStep(model, options, &mass, &summary) &&
        SetInitialState(model, options, &mass, &state, &summary)) {
      summary.records.reserve(static_cast<size_t>(std::max(0L, num_steps)));
      integrator =
          std::make_unique<CentralDifferences>(model, options, &mass, &state, &summary);
      summary.u = state.u;
      if (!integrator->started()) {
        run_state = SimulationState::kFailed;
      } else {
        summary.message = "running: 0 of " + std::to_string(num_steps) + " steps";
        if (num_steps <= 0) Finish();
      }
    } else {
      run_state = SimulationState::kFailed;
    }
    summary.seconds = Seconds(start);
  }

  // The status of a run that reached end_time.
  void Finish() {
    internal::SetFinalStatus(integrator->first_inaccurate(), &summary);
    internal::InternalForce::SetFinalStatus(&summary);
    run_state = SimulationState::kFinished;
  }

  // One step and the progress line; the state after it.
  void Step() {
    const bool ok = integrator->Step(k);
    k = static_cast<long>(
        summary.records.size());  // (the energy guard stops after its step)
    if (!ok) {
      run_state = SimulationState::kFailed;
      return;
    }
    if (k >= num_steps) Finish();
    if (options.progress && Seconds(start) - last_progress > 1.0) {
      last_progress = Seconds(start);
      const StepRecord& rec = summary.records.back();
      const double fraction = static_cast<double>(k) / static_cast<double>(num_steps);
      std::fprintf(stderr, "  step %d / %ld, t = %.6g s, %d Newton iterations, %s\n",
                   rec.step, num_steps, rec.time, rec.newton_iterations,
                   internal::ProgressText(fraction, last_progress).c_str());
    }
  }

  /// The state after step k for a checkpoint (the caller checks that there is one).
  void Save(internal::CheckpointData* data) const;
  /// Checks that `data` is a state of this run (CheckpointError naming what differs).
  void Check(const internal::CheckpointData& data) const;
  /// Replaces the state with data (checked).
  void Restore(const internal::CheckpointData& data);

  const Clock::time_point start;
  const DynamicModel& model;
  const DynamicOptions options;
  internal::MassInverse mass;  // M^-1, once per run
  State state;
  const long num_steps;  // from start_time to end_time
  DynamicSummary summary;
  std::unique_ptr<CentralDifferences> integrator;  // null if the run was refused
  long k = 0;                                      // steps taken
  SimulationState run_state = SimulationState::kRunning;
  double last_progress = 0.0;  // [s] since start
};

void Simulation::Impl::Save(internal::CheckpointData* data) const {
  internal::CheckpointIdentity& id = data->identity;
  id.model_hash = internal::ModelFingerprint(model, options);
  id.dim = model.dim;
  id.free_dofs = model.K.rows();
  id.contact_nodes = static_cast<std::int64_t>(model.contact_nodes.size());
  id.num_steps = num_steps;
  id.step_method = static_cast<std::int64_t>(summary.step_method);
  data->k = k;
  data->carried = state;  // the carried part of the state (slicing intended)
  integrator->Save(data);
  data->summary = summary;
}

namespace {

std::string Hex(std::uint64_t v) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(v));
  return buffer;
}

// CheckpointError unless `size` == `expected` (or 0 when `empty_ok`).
void CheckSize(const char* what, Eigen::Index size, Eigen::Index expected,
               bool empty_ok = false) {
  if (size == expected || (empty_ok && size == 0)) return;
  throw CheckpointError(std::string(what) + " has " + std::to_string(size) +
                        " entries, this run has " + std::to_string(expected));
}

}  // namespace

void Simulation::Impl::Check(const internal::CheckpointData& d) const {
  const internal::CheckpointIdentity& id = d.identity;
  const auto differs = [](const std::string& what, const std::string& saved,
                          const std::string& now) {
    throw CheckpointError("it is of another run: " + what + " " + saved +
                          " in the checkpoint, " + now + " now");
  };
  const Eigen::Index n = model.K.rows();
  const auto N = static_cast<Eigen::Index>(model.contact_nodes.size());
  if (id.dim != model.dim)
    differs("dim", std::to_string(id.dim), std::to_string(model.dim));
  if (id.free_dofs != n)
    differs("free dofs", std::to_string(id.free_dofs), std::to_string(n));
  if (id.contact_nodes != N)
    differs("contact nodes", std::to_string(id.contact_nodes), std::to_string(N));
  if (id.num_steps != num_steps)
    differs("time steps", std::to_string(id.num_steps), std::to_string(num_steps));
  if (id.step_method != static_cast<std::int64_t>(summary.step_method))
    differs("step method", ToString(static_cast<StepMethod>(id.step_method)),
            ToString(summary.step_method));
  const std::uint64_t fingerprint = internal::ModelFingerprint(model, options);
  if (id.model_hash != fingerprint)
    differs(
        "the model (K, M, contact nodes, dt, times, friction, step method, tolerance) "
        "has fingerprint",
        Hex(id.model_hash), Hex(fingerprint));
  if (d.k < 0 || d.k > num_steps || d.summary.records.size() != static_cast<size_t>(d.k))
    throw CheckpointError("its step index " + std::to_string(d.k) + " does not fit its " +
                          std::to_string(d.summary.records.size()) +
                          " step records and " + std::to_string(num_steps) + " steps");
  const internal::CarriedState& c = d.carried;
  for (const auto& [what, v] : {std::pair<const char*, const Eigen::VectorXd*>{"u", &c.u},
                                {"u_previous", &c.u_previous},
                                {"K u", &c.Ku},
                                {"M du", &c.Mdu_previous},
                                {"du", &c.du}})
    CheckSize(what, v->size(), n);
  CheckSize("lambda", c.lambda.size(), N);
  CheckSize("the gaps", d.gaps.size(), N);
  CheckSize("the final displacement", d.summary.u.size(), n, true);
  const bool stepped = d.k > 0;  // (before the first step the contact result is empty)
  CheckSize("the contact result's du", c.contact.x.size(), n, !stepped);
  CheckSize("the contact result's normal forces", c.contact.normal_force.size(), N,
            !stepped);
  CheckSize("the contact result's gaps", c.contact.gap.size(), N, !stepped);
  CheckSize("the contact result's friction forces", c.contact.tangent_force.size(),
            (model.dim - 1) * N, !stepped);
  CheckSize("the contact result's slips", c.contact.slip.size(), (model.dim - 1) * N,
            !stepped);
  if (c.contact.tangent_force.size() && c.contact.tangent_force.rows() != model.dim - 1)
    throw CheckpointError("its friction forces have " +
                          std::to_string(c.contact.tangent_force.rows()) +
                          " rows, this run " + std::to_string(model.dim - 1));
}

void Simulation::Impl::Restore(const internal::CheckpointData& d) {
  try {
    // The warm start first: it may refuse before anything changes.
    integrator->Restore(d);
  } catch (const std::invalid_argument& e) {
    throw CheckpointError(std::string("it does not fit this run: ") + e.what());
  }
  static_cast<internal::CarriedState&>(state) = d.carried;
  integrator->RestoreStoredEnergy();
  const double seconds = summary.seconds;
  summary = d.summary;
  summary.seconds += seconds;
  summary.status = DynamicStatus::kNotRun;  // (an interrupted run's checkpoint goes on)
  summary.u = state.u;
  summary.records.reserve(static_cast<size_t>(std::max(0L, num_steps)));
  k = d.k;
  run_state = SimulationState::kRunning;
  summary.message =
      "running: " + std::to_string(k) + " of " + std::to_string(num_steps) + " steps";
  if (k >= num_steps) Finish();
}

Simulation::Simulation(const DynamicModel& model, DynamicOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(options))) {}

Simulation::Simulation(std::shared_ptr<SceneData> scene, const DynamicModel& model,
                       DynamicOptions options)
    : scene_(std::move(scene)),
      impl_(std::make_unique<Impl>(model, std::move(options))) {}

Simulation::~Simulation() = default;

SimulationState Simulation::Step(long n) {
  if (n < 0)
    throw std::invalid_argument("contact::Simulation::Step: n must be >= 0, got " +
                                std::to_string(n));
  Impl& s = *impl_;
  const auto start = Clock::now();
  for (long i = 0; i < n && s.run_state == SimulationState::kRunning; ++i) {
    if (scene_) ApplySceneHistories();
    s.Step();
  }
  if (s.integrator) s.summary.u = s.state.u;
  if (s.run_state == SimulationState::kRunning)
    s.summary.message = "running: " + std::to_string(s.k) + " of " +
                        std::to_string(s.num_steps) + " steps";
  s.summary.seconds += Seconds(start);
  return s.run_state;
}

SimulationState Simulation::state() const { return impl_->run_state; }
double Simulation::time() const {  // (the last record's, to the bit)
  return impl_->k > 0 ? impl_->summary.records.back().time : impl_->options.start_time;
}
int Simulation::step_index() const { return static_cast<int>(impl_->k); }
int Simulation::num_steps() const { return static_cast<int>(impl_->num_steps); }
const DynamicSummary& Simulation::summary() const { return impl_->summary; }
const std::vector<StepRecord>& Simulation::records() const {
  return impl_->summary.records;
}
const DynamicModel& Simulation::model() const { return impl_->model; }
const DynamicOptions& Simulation::options() const { return impl_->options; }

void Simulation::SaveCheckpoint(const std::string& path,
                                const std::string& application_data) const {
  const Impl& s = *impl_;
  if (!s.integrator || (s.run_state == SimulationState::kFailed &&
                        s.summary.status != DynamicStatus::kInterrupted))
    throw std::logic_error(
        "contact::Simulation::SaveCheckpoint: no state to continue from (" +
        s.summary.message + ")");
  internal::CheckpointData data;
  s.Save(&data);
  if (scene_) SaveScene(&data);
  data.application_data = application_data;
  internal::WriteCheckpoint(path, data);
}

std::string Simulation::LoadCheckpoint(const std::string& path) {
  Impl& s = *impl_;
  if (!s.integrator)
    throw std::logic_error("contact::Simulation::LoadCheckpoint: the run was refused (" +
                           s.summary.message + ")");
  const internal::CheckpointData data = internal::ReadCheckpoint(path);
  try {
    if (scene_) CheckScene(data);  // the scene text and mesh first: the clearest message
    s.Check(data);
  } catch (const CheckpointError& e) {
    throw CheckpointError("checkpoint '" + path + "': " + e.what());
  }
  s.Restore(data);
  if (scene_) RestoreScene(data);
  return data.application_data;
}

std::unique_ptr<Simulation> Simulation::Load(const std::string& path,
                                             const Scene& scene) {
  auto simulation = std::make_unique<Simulation>(scene);
  simulation->LoadCheckpoint(path);
  return simulation;
}

const Eigen::VectorXd& Simulation::displacement() const {
  if (!impl_->integrator)
    throw std::logic_error("contact::Simulation: no state (the run was refused: " +
                           impl_->summary.message + ")");
  return impl_->state.u;
}

Eigen::VectorXd Simulation::velocity() const {
  return (displacement() - impl_->state.u_previous) / impl_->options.dt;
}

ContactNodeStates Simulation::contact() const {
  const Impl& s = *impl_;
  const Eigen::VectorXd& u = displacement();
  const auto N = static_cast<Eigen::Index>(s.model.contact_nodes.size());
  const int dim = s.model.dim;
  ContactNodeStates out;
  out.state.resize(static_cast<size_t>(N));
  const ContactSystem::Result& c = s.state.contact;
  if (s.k > 0) {  // the last step's result
    const double F = s.integrator->force_scale();
    const StepRecord& rec = s.summary.records.back();
    out.normal_force = F * c.normal_force;
    out.friction_force = F * c.tangent_force;
    out.gap = c.gap;
    for (Eigen::Index i = 0; i < N; ++i)
      out.state[static_cast<size_t>(i)] =
          ClassifyContact(out.normal_force(i), c.slip.col(i).norm(), rec.force_accuracy,
                          rec.displacement_accuracy);
    return out;
  }
  // The initial state: gaps of u^0, the static equilibrium's normal forces
  // (frictionless), unknown (NaN) forces of a prescribed start.
  const bool known = s.options.initial_state == InitialState::kStaticEquilibrium;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.normal_force = known ? s.state.lambda : Eigen::VectorXd::Constant(N, nan);
  out.friction_force = Eigen::MatrixXd::Constant(dim - 1, N, known ? 0.0 : nan);
  out.gap.resize(N);
  const Eigen::VectorXd& gaps = s.integrator->gaps();
  for (Eigen::Index i = 0; i < N; ++i) {
    const ContactNode& node = s.model.contact_nodes[static_cast<size_t>(i)];
    double un = 0.0;
    for (int a = 0; a < dim; ++a)
      if (node.dofs[a] >= 0) un += node.normal(a) * u(node.dofs[a]);
    out.gap(i) = gaps(i) - un;
    out.state[static_cast<size_t>(i)] =
        ClassifyContact(out.normal_force(i), 0.0, 0.0, 0.0);
  }
  return out;
}

void Simulation::SetLoad(std::function<void(double, Eigen::VectorXd*)> load) {
  if (!load)
    throw std::invalid_argument(
        "contact::Simulation::SetLoad: the load function is not set");
  if (!impl_->integrator) return;
  impl_->integrator->SetLoad(std::move(load));
}

void Simulation::SetContactGaps(const Eigen::VectorXd& gaps) {
  const auto N = static_cast<Eigen::Index>(impl_->model.contact_nodes.size());
  if (gaps.size() != N)
    throw std::invalid_argument(
        "contact::Simulation::SetContactGaps: one gap per contact node (" +
        std::to_string(N) + ") is needed, got " + std::to_string(gaps.size()));
  for (Eigen::Index c = 0; c < N; ++c)
    if (!std::isfinite(gaps(c)))
      throw std::invalid_argument(
          "contact::Simulation::SetContactGaps: the gap of contact node " +
          std::to_string(c) + " is not finite [m]");
  if (impl_->integrator) impl_->integrator->SetGaps(gaps);
}

void Simulation::AddObstacleStep(const Eigen::VectorXd& increment) {
  if (impl_->integrator) impl_->integrator->AddObstacleStep(increment);
}

const Eigen::VectorXd& Simulation::contact_gaps() const {
  if (!impl_->integrator)
    throw std::logic_error("contact::Simulation: no state (the run was refused: " +
                           impl_->summary.message + ")");
  return impl_->integrator->gaps();
}

DynamicSummary RunDynamics(const DynamicModel& model, const DynamicOptions& options) {
  Simulation simulation(model, options);
  simulation.Step(std::numeric_limits<long>::max());
  return std::move(simulation.impl_->summary);
}

}  // namespace contact
