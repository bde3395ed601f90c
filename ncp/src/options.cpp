// Options (defaults of Algorithm 1, validation) and the Summary's reports (solver.hpp).

#include <cmath>
#include <sstream>
#include <string>

#include "format_number.hpp"
#include "ncp/solver.hpp"
#include "strategy.hpp"

namespace ncp {

using internal::FormatNumber;

Options Options::Algorithm1() {
  Options options;
  options.descent_rho = 1e-8;
  options.descent_p = 2.1;
  options.armijo_beta = 1e-4;
  options.nonmonotone_memory = 1;
  options.regularized_direction = false;
  options.gradient_fallback = true;
  options.minimum_norm_step = false;
  options.merit_restarts = 0;
  options.hybrid = false;
  return options;
}

namespace {

// Tolerances, iteration counts, the descent and Armijo constants (eq. 22, 23); "" when
// valid.
std::string AccuracyError(const Options& o) {
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance))
    return "Options::tolerance must be finite and >= 0, got " +
           FormatNumber("%g", o.tolerance);
  if (!(o.roundoff_ulps >= 0.0) || !std::isfinite(o.roundoff_ulps))
    return "Options::roundoff_ulps must be finite and >= 0, got " +
           FormatNumber("%g", o.roundoff_ulps);
  if (o.max_iterations < 0)
    return "Options::max_iterations must be >= 0, got " +
           std::to_string(o.max_iterations);
  if (!(o.descent_rho > 0.0))
    return "Options::descent_rho must be > 0 (eq. 22), got " +
           FormatNumber("%g", o.descent_rho);
  if (!(o.descent_p > 2.0))
    return "Options::descent_p must be > 2 (eq. 22), got " +
           FormatNumber("%g", o.descent_p);
  if (!(o.armijo_beta > 0.0 && o.armijo_beta < 0.5))
    return "Options::armijo_beta must lie in (0, 1/2) (eq. 23), got " +
           FormatNumber("%g", o.armijo_beta);
  if (o.nonmonotone_memory < 1 || o.nonmonotone_memory > 1000)
    return "Options::nonmonotone_memory must lie in [1, 1000], got " +
           std::to_string(o.nonmonotone_memory);
  if (o.merit_restarts < 0 || o.merit_restarts > 1000)
    return "Options::merit_restarts must lie in [0, 1000], got " +
           std::to_string(o.merit_restarts);
  if (o.max_backtracks < 0 || o.max_backtracks > 1000)
    return "Options::max_backtracks must lie in [0, 1000], got " +
           std::to_string(o.max_backtracks);
  return {};
}

// The degenerate set, restarts, stagnation and the hybrid's constants; "" when valid.
std::string SafeguardError(const Options& o) {
  if (!(o.degenerate_tolerance >= 0.0))
    return "Options::degenerate_tolerance must be >= 0, got " +
           FormatNumber("%g", o.degenerate_tolerance);
  if (!(o.stationarity_tolerance >= 0.0))
    return "Options::stationarity_tolerance must be >= 0, got " +
           FormatNumber("%g", o.stationarity_tolerance);
  if (!(o.penalized_fb_lambda > 0.0 && o.penalized_fb_lambda <= 1.0))
    return "Options::penalized_fb_lambda must lie in (0, 1], got " +
           FormatNumber("%g", o.penalized_fb_lambda);
  if (o.stagnation_window < 0 || o.stagnation_window > kMaxStagnationWindow)
    return "Options::stagnation_window must lie in [0, " +
           std::to_string(kMaxStagnationWindow) + "] iterations, got " +
           std::to_string(o.stagnation_window);
  if (!(o.stagnation_tolerance >= 0.0 && o.stagnation_tolerance < 1.0))
    return "Options::stagnation_tolerance must lie in [0, 1), got " +
           FormatNumber("%g", o.stagnation_tolerance);
  if (o.hybrid_window < 0 || o.hybrid_window > kMaxStagnationWindow)
    return "Options::hybrid_window must lie in [0, " +
           std::to_string(kMaxStagnationWindow) + "] iterations, got " +
           std::to_string(o.hybrid_window);
  if (!(o.hybrid_decrease > 0.0 && o.hybrid_decrease < 1.0))
    return "Options::hybrid_decrease must lie in (0, 1), got " +
           FormatNumber("%g", o.hybrid_decrease);
  if (!(o.hybrid_budget_per_unknown > 0.0))
    return "Options::hybrid_budget_per_unknown must be > 0 (or +inf) iterations, got " +
           FormatNumber("%g", o.hybrid_budget_per_unknown);
  return {};
}

// Time, backend and bound limits, and the enums; "" when valid.
std::string LimitsError(const Options& o) {
  if (!(o.max_seconds > 0.0))
    return "Options::max_seconds must be > 0 (or +inf), got " +
           FormatNumber("%g", o.max_seconds);
  if (!(o.factorization_flop_rate >= 0.0) || !std::isfinite(o.factorization_flop_rate))
    return "Options::factorization_flop_rate must be finite and >= 0, got " +
           FormatNumber("%g", o.factorization_flop_rate);
  if (o.blas_threads < 0)
    return "Options::blas_threads must be >= 0 (0: leave the BLAS alone), got " +
           std::to_string(o.blas_threads);
  if (o.dense_threshold < 0)
    return "Options::dense_threshold must be >= 0, got " +
           std::to_string(o.dense_threshold);
  if (!(o.infinite_bound > 0.0))
    return "Options::infinite_bound must be > 0 (or +inf), got " +
           FormatNumber("%g", o.infinite_bound);
  // Enums set from integers (a cast, a file) may hold any value: checked before a switch.
  const int function = static_cast<int>(o.ncp_function);
  if (function < 0 || function > static_cast<int>(kLastNcpFunction))
    return "Options::ncp_function must be an NcpFunction (0.." +
           std::to_string(static_cast<int>(kLastNcpFunction)) + "), got " +
           std::to_string(function);
  const int solver = static_cast<int>(o.linear_solver);
  if (solver < 0 || solver > static_cast<int>(kLastLinearSolverType))
    return "Options::linear_solver must be a LinearSolverType (0.." +
           std::to_string(static_cast<int>(kLastLinearSolverType)) + "), got " +
           std::to_string(solver);
  return {};
}

}  // namespace

bool Options::IsValid(std::string* error) const {
  for (const std::string& what :
       {AccuracyError(*this), SafeguardError(*this), LimitsError(*this)}) {
    if (what.empty()) continue;
    if (error) *error = what;
    return false;
  }
  return true;
}

std::string Summary::BriefReport() const {
  std::ostringstream out;
  out << ToString(termination) << ": " << iterations << " iterations, "
      << jacobian_evaluations << " Jacobian / " << residual_evaluations
      << " residual evaluations, ||Phi||_inf = " << FormatNumber("%.3e", final_phi_inf)
      << ", " << FormatNumber("%.3g", total_time_s) << " s";
  if (merit_restarts > 0) out << ", " << merit_restarts << " merit restarts";
  if (!strategy_switches.empty())
    out << ", " << strategy_switches.size() << " strategy switches";
  return out.str();
}

std::string Summary::FullReport() const {
  std::ostringstream out;
  out << "ncp solver summary\n"
      << "  termination              " << ToString(termination) << "\n"
      << "  message                  " << message << "\n"
      << "  unknowns / eqs / pairs   " << num_variables << " / " << num_equations << " / "
      << num_pairs << "\n"
      << "  NCP function             " << ToString(ncp_function) << "\n"
      << "  linear solver            " << ToString(linear_solver_requested) << " -> "
      << ToString(linear_solver_used) << "\n"
      << "  iterations               " << iterations << "\n"
      << "  Jacobian evaluations     " << jacobian_evaluations << "\n"
      << "  residual evaluations     " << residual_evaluations << "\n"
      << "  gradient steps           " << gradient_steps << "\n"
      << "  regularized (LM) steps   " << regularized_steps << "\n"
      << "  minimum-norm steps       " << minimum_norm_steps << "\n"
      << "  equilibrated LU          " << equilibrated_factorizations << "\n"
      << "  merit restarts           " << merit_restarts << "\n"
      << "  strategy switches        " << strategy_switches.size()
      << internal::StrategySwitchSuffix(strategy_switches) << "\n"
      << "  linear solver failures   " << linear_solver_failures << "\n"
      << "  descent test failures    " << descent_test_failures << "\n"
      << "  backtracks               " << backtracks << "\n"
      << "  symbolic factorizations  " << symbolic_factorizations << "\n"
      << "  Cholesky -> LU fallbacks " << cholesky_fallbacks << "\n"
      << "  start components moved   " << projected_start_components << "\n"
      << "  final components moved   " << projected_final_components << "\n"
      << "  ||Phi||_inf initial      " << FormatNumber("%.6e", initial_phi_inf) << "\n"
      << "  ||Phi||_inf final        " << FormatNumber("%.6e", final_phi_inf)
      << (roundoff_limited ? " (at the round-off floor)" : "") << "\n"
      << "  psi final                " << FormatNumber("%.6e", final_psi) << "\n"
      << "  time total / eval / lin  " << FormatNumber("%.6f", total_time_s) << " / "
      << FormatNumber("%.6f", evaluation_time_s) << " / "
      << FormatNumber("%.6f", linear_solver_time_s) << " s\n";
  return out.str();
}

}  // namespace ncp
