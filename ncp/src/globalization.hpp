// The scalar decisions of Algorithm 1 (thesis section 3.1), shared by every
// implementation of the iteration: ncp::Solver (solver.cpp, Eigen) and ncp::petsc::Solver
// (ncp/petsc, distributed PETSc Vec/Mat). Each function takes the reduced quantities of
// an iterate (norms, dot products, counts: on several ranks already reduced over the
// communicator) and returns the decision, so that both solvers take the same steps from
// the same numbers. Nothing here touches a vector.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "format_number.hpp"
#include "ncp/solver.hpp"

namespace ncp::internal {

// ---- the z-vector rule ---------------------------------------------------------------
/// Pair (a, b) in the degenerate set gamma = {j : a_j = b_j = 0} (DFK 1996, eq. 13), or
/// within Options::degenerate_tolerance of it. The min function has no gamma: its
/// B-subdifferential element is chosen by Options::min_tie_takes_b instead.
inline bool InDegenerateSet(NcpFunction function, double degenerate_tolerance, double a,
                            double b) {
  if (function == NcpFunction::kMin) return false;
  return degenerate_tolerance == 0.0 ? a == 0.0 && b == 0.0
                                     : std::hypot(a, b) <= degenerate_tolerance;
}

// ---- step 1: the stopping tests -------------------------------------------------------
/// The stopping test's bound on |Phi_i| with the round-off floor of row i
/// (Options::roundoff_ulps): threshold + ulps eps r_i, r_i the row's sensitivity |J||x|
/// (solver.hpp, Options::roundoff_ulps).
inline double RoundoffFloorBound(double threshold, double roundoff_ulps, double r_i) {
  return threshold + roundoff_ulps * std::numeric_limits<double>::epsilon() * r_i;
}
/// Row i within its round-off floor: |Phi_i| <= RoundoffFloorBound.
inline bool RowWithinRoundoffFloor(double phi_i, double threshold, double roundoff_ulps,
                                   double r_i) {
  return std::abs(phi_i) <= RoundoffFloorBound(threshold, roundoff_ulps, r_i);
}

/// The stagnation test (Options::stagnation_window, stagnation_tolerance): the smallest
/// psi so far decreased by less than stagnation_tolerance of itself over the last window
/// iterations (a ring buffer). With a monotone line search the smallest psi is psi(x^k);
/// a nonmonotone one may raise psi in between. kk counts the iterates since the last
/// (re)start.
class StagnationTest {
 public:
  void Reset(int window) { ring_.assign(static_cast<size_t>(window) + 1, 0.0); }
  /// Records psi(x^k); true when the iterates stagnate.
  bool Stagnated(size_t kk, double psi, const Options& o) {
    const size_t window = static_cast<size_t>(o.stagnation_window);
    best_psi_ = kk == 0 ? psi : std::min(best_psi_, psi);
    ring_[kk % (window + 1)] = best_psi_;
    const double best_window_ago = ring_[(kk + 1) % (window + 1)];  // at k - window
    return !(window == 0 || kk < window ||
             best_window_ago - best_psi_ > o.stagnation_tolerance * best_window_ago);
  }

 private:
  std::vector<double> ring_;
  double best_psi_ = 0.0;
};

inline std::string ConvergedMessage(const Options& o, bool weighted,
                                    bool roundoff_limited, double phi_inf, int k) {
  std::string what = weighted ? "every row within floor + " +
                                    FormatNumber("%.1e", o.tolerance) +
                                    " x scale in its own units (relative ||Phi||_inf = " +
                                    FormatNumber("%.3e", phi_inf) + ")"
                              : "||Phi||_inf = " + FormatNumber("%.3e", phi_inf) +
                                    " <= " + FormatNumber("%.3e", o.tolerance);
  if (roundoff_limited)
    what =
        (weighted ? "relative ||Phi||_inf = " : "||Phi||_inf = ") +
        FormatNumber("%.3e", phi_inf) + " > tolerance " +
        FormatNumber("%.1e", o.tolerance) +
        ", at the round-off floor: every row within " + "the tolerance + " +
        FormatNumber("%g", o.roundoff_ulps) +
        " ulps of its sensitivity |J||x| (double precision resolves no more at this x)";
  return what + " after " + std::to_string(k) + " iterations";
}

inline std::string MaxIterationsMessage(const Options& o, double phi_inf) {
  return "reached max_iterations = " + std::to_string(o.max_iterations) +
         " with ||Phi||_inf = " + FormatNumber("%.3e", phi_inf);
}

inline std::string StagnationMessage(const Options& o, double phi_inf, double grad_inf) {
  return "the smallest psi decreased by less than " +
         FormatNumber("%.1e", o.stagnation_tolerance) + " relative over the last " +
         std::to_string(o.stagnation_window) +
         " iterations (||Phi||_inf = " + FormatNumber("%.3e", phi_inf) +
         ", ||grad psi||_inf = " + FormatNumber("%.3e", grad_inf) +
         "): the iterates approach a stationary point of psi that is not a solution";
}

inline std::string ZeroGradientMessage(double phi_inf) {
  return "grad psi = J' Phi = 0 with ||Phi||_inf = " + FormatNumber("%.3e", phi_inf) +
         ": a stationary point of psi that is not a solution";
}

inline std::string TimeLimitMessage(const Options& o, const char* where, int k,
                                    double phi_inf) {
  return "max_seconds = " + FormatNumber("%.3g", o.max_seconds) + " s reached " + where +
         std::to_string(k) + " with ||Phi||_inf = " + FormatNumber("%.3e", phi_inf);
}

// ---- step 2: the direction ------------------------------------------------------------
/// The computed Newton direction d must solve J d = -Phi to a small normwise backward
/// error,
/// ||J d + Phi||_inf <= 1e-6 (||Phi||_inf + || |J||d| ||_inf) (Rigal and Gaches 1967;
/// Higham 2002, Thm. 7.1): a guard against an unstable factorization that "succeeded".
/// The terms |J||d|, not |J d|, set the scale: rows of size h^-2 (fine grids) leave a
/// residual of eps |J||d| in any backward-stable solve, far above 1e-6 ||Phi|| once h^-2
/// eps ~ 1e-6.
inline bool NewtonSolutionAccurate(double residual_inf, double phi_inf,
                                   double terms_inf) {
  return residual_inf <= 1e-6 * (phi_inf + terms_inf);
}

/// The descent test grad psi' d <= -rho ||d||_2^p (thesis eq. 22); slope = grad psi' d.
inline bool PassesDescentTest(double slope, double direction_norm, const Options& o) {
  return slope <= -o.descent_rho * std::pow(direction_norm, o.descent_p);
}

// ---- step 3: Armijo line search on psi with steps 2^-i --------------------------------
/// The Armijo reference: psi(x^k) (monotone, nonmonotone_memory = 1, eq. 23) or the
/// largest psi of the last nonmonotone_memory iterates (Grippo, Lampariello and Lucidi
/// 1986; Munson et al. 2001, sec. 3). kk counts the iterates since the last (re)start.
class NonmonotoneReference {
 public:
  void Reset(int memory) { psi_.assign(static_cast<size_t>(memory), 0.0); }
  double Update(size_t kk, double psi) {
    const size_t memory = psi_.size();
    psi_[kk % memory] = psi;
    double reference = psi;
    for (size_t j = 0; j < std::min(memory, kk + 1); ++j)
      reference = std::max(reference, psi_[j]);
    return reference;
  }

 private:
  std::vector<double> psi_;
};

/// What one trial point x + t d gave.
struct LineSearchTrial {
  enum Kind { kUnchanged, kNotEvaluable, kNonFinite, kEvaluated };
  Kind kind;
  double psi;  ///< psi(x + t d) when kEvaluated
};

struct LineSearchResult {
  bool accepted = false;
  bool out_of_time = false;
  int backtracks = 0;  ///< i of the last trial step 2^-i
  double step = 1.0;   ///< 2^-i
  int trials = 0, non_finite_trials = 0, failed_trials = 0;
};

/// Steps t = 1, 1/2, ..., 2^-max_backtracks; try_step(t) evaluates x + t d. Accepted when
///   psi(x + t d) <= reference + beta t slope  and  psi(x + t d) < reference
/// (eq. 23; the strict decrease keeps round-off from stalling the iteration). A trial
/// point where the problem cannot be evaluated, or evaluates to non-finite values, is
/// rejected; one equal to x (no component moves any more) ends the search, since shorter
/// steps cannot move either.
template <class OutOfTime, class TryStep>
LineSearchResult ArmijoLineSearch(const Options& o, double reference, double slope,
                                  OutOfTime&& out_of_time, TryStep&& try_step) {
  LineSearchResult r;
  double t = 1.0;
  int i = 0;
  for (; i <= o.max_backtracks; ++i, t *= 0.5) {
    if (out_of_time()) {
      r.out_of_time = true;
      r.backtracks = i;
      return r;
    }
    const LineSearchTrial trial = try_step(t);
    if (trial.kind == LineSearchTrial::kUnchanged) break;
    ++r.trials;
    if (trial.kind == LineSearchTrial::kNotEvaluable) {
      ++r.failed_trials;
      continue;
    }
    if (trial.kind == LineSearchTrial::kNonFinite) {
      ++r.non_finite_trials;
      continue;
    }
    if (trial.psi <= reference + o.armijo_beta * t * slope && trial.psi < reference) {
      r.accepted = true;
      break;
    }
  }
  r.backtracks = i;
  r.step = t;
  return r;
}

/// Why a line search found no step, and the message (direction: "Newton", "gradient",
/// ...).
struct Ending {
  TerminationType termination;
  std::string message;
};
inline Ending LineSearchFailure(const Options& o, const LineSearchResult& r,
                                const char* direction, int k, double phi_inf,
                                double grad_inf) {
  const std::string where = std::string(" along the ") + direction +
                            " direction at iteration " + std::to_string(k) +
                            ", ||Phi||_inf = " + FormatNumber("%.3e", phi_inf) +
                            ", ||grad psi||_inf = " + FormatNumber("%.3e", grad_inf);
  // Every trial NaN/Inf, or none evaluable: say so rather than "no decrease".
  if (r.trials > 0 && r.non_finite_trials == r.trials)
    return {TerminationType::kNonFiniteValues,
            "Phi has NaN or Inf entries at all " + std::to_string(r.trials) +
                " trial points of the line search" + where};
  if (r.trials > 0 && r.failed_trials == r.trials)
    return {TerminationType::kEvaluationFailure,
            "the problem could not be evaluated at any of the " +
                std::to_string(r.trials) + " trial points of the line search" + where};
  if (grad_inf <= o.stationarity_tolerance * phi_inf)
    return {TerminationType::kStationaryPoint,
            "no decrease of psi possible" + where +
                ": a stationary point of psi that is not a solution"};
  return {TerminationType::kLineSearchFailure,
          "no Armijo step of length >= 2^-" + std::to_string(o.max_backtracks) + where +
              (r.non_finite_trials + r.failed_trials > 0
                   ? " (" + std::to_string(r.non_finite_trials) + " of " +
                         std::to_string(r.trials) + " trial points gave NaN/Inf, " +
                         std::to_string(r.failed_trials) + " could not be evaluated)"
                   : std::string())};
}

// ---- the restart strategy (Options::merit_restarts) -----------------------------------
/// An FB-family solve that ended at a non-solution stationary point of psi or in a failed
/// line search continues with the other member of the family.
inline bool MeritRestartApplies(TerminationType ended, int restarts_left,
                                NcpFunction function) {
  const bool stuck = ended == TerminationType::kStationaryPoint ||
                     ended == TerminationType::kLineSearchFailure;
  return stuck && restarts_left > 0 && function != NcpFunction::kMin;
}
/// FB <-> penalized FB.
inline NcpFunction OtherMeritFunction(NcpFunction function) {
  return function == NcpFunction::kFischerBurmeister
             ? NcpFunction::kPenalizedFischerBurmeister
             : NcpFunction::kFischerBurmeister;
}
inline std::string RestartSuffix(int restarts) {
  return " (after " + std::to_string(restarts) +
         " restarts switching FB <-> penalized FB)";
}

}  // namespace ncp::internal
