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

bool Options::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    return fail("Options::tolerance must be finite and >= 0, got " +
                FormatNumber("%g", tolerance));
  if (!(roundoff_ulps >= 0.0) || !std::isfinite(roundoff_ulps))
    return fail("Options::roundoff_ulps must be finite and >= 0, got " +
                FormatNumber("%g", roundoff_ulps));
  if (blas_threads < 0)
    return fail("Options::blas_threads must be >= 0 (0: leave the BLAS alone), got " +
                std::to_string(blas_threads));
  if (max_iterations < 0)
    return fail("Options::max_iterations must be >= 0, got " +
                std::to_string(max_iterations));
  if (!(descent_rho > 0.0))
    return fail("Options::descent_rho must be > 0 (eq. 22), got " +
                FormatNumber("%g", descent_rho));
  if (!(descent_p > 2.0))
    return fail("Options::descent_p must be > 2 (eq. 22), got " +
                FormatNumber("%g", descent_p));
  if (!(armijo_beta > 0.0 && armijo_beta < 0.5))
    return fail("Options::armijo_beta must lie in (0, 1/2) (eq. 23), got " +
                FormatNumber("%g", armijo_beta));
  if (nonmonotone_memory < 1 || nonmonotone_memory > 1000)
    return fail("Options::nonmonotone_memory must lie in [1, 1000], got " +
                std::to_string(nonmonotone_memory));
  if (merit_restarts < 0 || merit_restarts > 1000)
    return fail("Options::merit_restarts must lie in [0, 1000], got " +
                std::to_string(merit_restarts));
  if (max_backtracks < 0 || max_backtracks > 1000)
    return fail("Options::max_backtracks must lie in [0, 1000], got " +
                std::to_string(max_backtracks));
  if (!(degenerate_tolerance >= 0.0))
    return fail("Options::degenerate_tolerance must be >= 0, got " +
                FormatNumber("%g", degenerate_tolerance));
  if (!(stationarity_tolerance >= 0.0))
    return fail("Options::stationarity_tolerance must be >= 0, got " +
                FormatNumber("%g", stationarity_tolerance));
  if (!(penalized_fb_lambda > 0.0 && penalized_fb_lambda <= 1.0))
    return fail("Options::penalized_fb_lambda must lie in (0, 1], got " +
                FormatNumber("%g", penalized_fb_lambda));
  if (stagnation_window < 0 || stagnation_window > kMaxStagnationWindow)
    return fail("Options::stagnation_window must lie in [0, " +
                std::to_string(kMaxStagnationWindow) + "] iterations, got " +
                std::to_string(stagnation_window));
  if (!(stagnation_tolerance >= 0.0 && stagnation_tolerance < 1.0))
    return fail("Options::stagnation_tolerance must lie in [0, 1), got " +
                FormatNumber("%g", stagnation_tolerance));
  if (hybrid_window < 0 || hybrid_window > kMaxStagnationWindow)
    return fail("Options::hybrid_window must lie in [0, " +
                std::to_string(kMaxStagnationWindow) + "] iterations, got " +
                std::to_string(hybrid_window));
  if (!(hybrid_decrease > 0.0 && hybrid_decrease < 1.0))
    return fail("Options::hybrid_decrease must lie in (0, 1), got " +
                FormatNumber("%g", hybrid_decrease));
  if (!(hybrid_budget_per_unknown > 0.0))
    return fail(
        "Options::hybrid_budget_per_unknown must be > 0 (or +inf) iterations, got " +
        FormatNumber("%g", hybrid_budget_per_unknown));
  if (!(max_seconds > 0.0))
    return fail("Options::max_seconds must be > 0 (or +inf), got " +
                FormatNumber("%g", max_seconds));
  if (!(factorization_flop_rate >= 0.0) || !std::isfinite(factorization_flop_rate))
    return fail("Options::factorization_flop_rate must be finite and >= 0, got " +
                FormatNumber("%g", factorization_flop_rate));
  if (dense_threshold < 0)
    return fail("Options::dense_threshold must be >= 0, got " +
                std::to_string(dense_threshold));
  if (!(infinite_bound > 0.0))
    return fail("Options::infinite_bound must be > 0 (or +inf), got " +
                FormatNumber("%g", infinite_bound));
  // Enums set from integers (a cast, a file) may hold any value: checked before a switch.
  const int function = static_cast<int>(ncp_function);
  if (function < 0 || function > static_cast<int>(kLastNcpFunction))
    return fail("Options::ncp_function must be an NcpFunction (0.." +
                std::to_string(static_cast<int>(kLastNcpFunction)) + "), got " +
                std::to_string(function));
  const int solver = static_cast<int>(linear_solver);
  if (solver < 0 || solver > static_cast<int>(kLastLinearSolverType))
    return fail("Options::linear_solver must be a LinearSolverType (0.." +
                std::to_string(static_cast<int>(kLastLinearSolverType)) + "), got " +
                std::to_string(solver));
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
