/// \file dynamics.hpp
/// Elastodynamic contact by central differences (thesis section 4.3): for k = 0, 1, ...
///     M (u^{k+1} - 2 u^k + u^{k-1}) / dt^2 + K u^k = f(t_k) + r^{k+1}            (eq.
///     68)
/// where r^{k+1} are the contact forces, which satisfy Signorini's conditions at u^{k+1}
/// and Tresca friction with bound f_c lambda^k (Coulomb by fixed point on the previous
/// step's normal force, thesis eq. 70). Each step is one ContactSystem with
///     S = M / Mmax,  q = dt^2 Q^k / Mmax,  Q^k = M (u^{k-1} - u^k) / dt^2 + K u^k -
///     f(t_k)
/// (eq. 73, 80, 81), unknown du = u^{k+1} - u^k, solved by ncp (or Ipopt, frictionless).
///
/// Energies are the exact discrete balance of central differences: with
///     E^{k+1/2} = 1/2 v' M v + 1/2 (u^k)' K u^{k+1},   v = (u^{k+1} - u^k) / dt
/// multiplying the step equation by (u^{k+1} - u^{k-1}) / 2 gives
///     E^{k+1/2} - E^{-1/2} = W_ext + W_contact,
///     W_ext += f(t_k) . (u^{k+1} - u^{k-1}) / 2,  W_contact += r^{k+1} . (u^{k+1} -
///     u^{k-1}) / 2,
/// so the reported balance error measures only the solver's residual and round-off.
/// W_contact is split into its normal part and the friction dissipation (>= 0).
/// With Rayleigh damping (DynamicModel::damping) Q^k gains C v^k, v^k = (u^k - u^{k-1})
/// / dt, and the balance its dissipation D (contact/src/damping.hpp).
#pragma once

#include <Eigen/SparseCore>

#include "contact/dynamics_types.hpp"

namespace contact {

/// At most this many time steps (end_time - start_time) / dt per run: RunDynamics keeps
/// one StepRecord (~200 bytes) per step, reserved up front.
inline constexpr double kMaxTimeSteps = 1e6;
/// The defaults of EstimateCriticalTimeStep, which RunDynamics uses too.
inline constexpr double kCriticalStepTolerance = 1e-9;
inline constexpr int kCriticalStepMaxIterations = 20000;
/// Critical step of central differences, dt_crit = 2 / omega_max, omega_max^2 the largest
/// eigenvalue of M^-1 K, estimated by the Lanczos method on the pencil (K, M) (the
/// largest Ritz value rises to omega_max^2 from below; it is checked every third step and
/// the iteration stops when it moved by at most `relative_tolerance` over two checks in a
/// row). One step costs a product with K and a solve with M (elementwise for a diagonal
/// M, else a CHOLMOD factor computed once). Lanczos converges to the extreme eigenvalue
/// much faster than power iteration (Golub and Van Loan, Matrix Computations,
/// section 10.1; counts on the thesis mesh: benchmarks/results/defaults/README.md).
CriticalTimeStep EstimateCriticalTimeStep(
    const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
    double relative_tolerance = kCriticalStepTolerance,
    int max_iterations = kCriticalStepMaxIterations);

/// y = A x for a symmetric sparse A (column storage): y_i is the dot product of column i
/// with x, and the rows are split over the OpenMP threads, so the result is bit-for-bit
/// the serial one for any number of threads. RunDynamics makes one such product with K
/// and one with M per step (contact-scaling-bench measures step times in units of it).
void SymmetricMultiply(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& x,
                       Eigen::VectorXd* y);

enum class DynamicStatus {
  kNotRun,
  kCompleted,           ///< every step solved and within its accuracy
  kSolverFailure,       ///< a step's solver failed (the run stopped there)
  kEnergyBlowUp,        ///< the energy guard tripped (the run stopped there)
  kRefusedUnstable,     ///< dt > dt_crit without allow_unstable_time_step (nothing run)
  kAccuracyNotReached,  ///< the run went to the end, but some step missed its accuracy
  kInterrupted,      ///< DynamicOptions::stop_requested was set (the run stopped after a
                     ///< step)
  kInvertedElement,  ///< finite strain: an element turned inside out (det F <= 0; the
                     ///< run stopped at that step, the message names element and step)
  kOutsideSmallStrain,  ///< material.kinematics = "small", and the run left the validity
                        ///< of the linear strain (the message: largest rotation and the
                        ///< spurious strain it implies)
};
const char* ToString(DynamicStatus s);

struct DynamicSummary {
  DynamicStatus status = DynamicStatus::kNotRun;
  std::string message = "not run yet";
  StepMethod step_method = StepMethod::kAuto;  ///< the method that ran (kAuto resolved)
  int steps = 0;
  long newton_iterations = 0, jacobian_evaluations = 0, residual_evaluations = 0;
  /// Steps whose Newton solve from the previous friction forces failed and that were
  /// solved again from the neutral friction start (see ContactSystem::StartPoint).
  int friction_restarts = 0;
  /// GMRES iterations over the run (StepMethod::kSparse; 0 otherwise): the sparse step's
  /// Newton systems, one solve with M's factor each (docs/contact-steps.md).
  long krylov_iterations = 0;
  double seconds = 0.0;
  /// Where the steps' time went, summed over the run [s] (docs/contact-steps.md):
  /// assembly (the load f^k, Q^k, the step's scales and the products M du, K u^{k+1}),
  /// the solves with M's factor inside the step method (mass_solves of them: two per step
  /// plus, for the sparse step, one per product with W), the contact solve proper (the
  /// step method's time without its mass solves) and the accuracy check (residuals
  /// recomputed, energies).
  double assembly_seconds = 0.0, mass_solve_seconds = 0.0, contact_solve_seconds = 0.0,
         accuracy_check_seconds = 0.0;
  long mass_solves = 0;
  /// The cost per step that StepMethod::kAuto predicts for each method it chooses among
  /// (contact/src/step/step_method.cpp, docs/contact-steps.md) and its choice.
  StepCostPrediction predicted_cost;
  double max_penetration = 0.0;  ///< over all steps [m]
  /// Largest per-step measures over the run (see StepRecord) [N].
  double max_equilibrium_residual = 0.0, max_complementarity_residual = 0.0,
         max_friction_residual = 0.0;
  int inaccurate_steps = 0;                     ///< steps with StepRecord::accurate false
  double energy_balance_error = 0.0;            ///< max over steps of |balance error| [J]
  double critical_time_step = -1.0;             ///< [s]
  double max_ipopt_relative_difference = -1.0;  ///< with compare_with_ipopt
  /// The kinematics that ran (DynamicModel::kinematics): "small" or "finite", and the
  /// step from which finite strain ran (0: from the start; -1: never).
  std::string kinematics = "small";
  int finite_strain_from_step = -1;
  /// Material model of the finite-strain steps (ToString(MaterialModel)).
  std::string material_model = "linear";
  /// The largest element rotation [rad] and spurious strain of the linear model [-]
  /// measured while small strain ran (StrainMeasure), and the first step at which the
  /// linear model was not valid (-1: never).
  double max_rotation = 0.0, max_spurious_strain = 0.0;
  int small_strain_invalid_step = -1;
  std::vector<StepRecord> records;
  Eigen::VectorXd u;  ///< final displacement (free dofs)
};

/// Runs the time loop. Throws std::invalid_argument on inconsistent input (sizes, K or M
/// not symmetric, dt <= 0, Ipopt with friction); numerical trouble ends with a status.
DynamicSummary RunDynamics(const DynamicModel& model, const DynamicOptions& options);

}  // namespace contact
