// ncp-collection: runs every problem of the standard collection from every standard
// start point with the Fischer-Burmeister, min and penalized FB functions, and prints one
// line each. The last column is the natural residual ||x - mid(l, u, x - F(x))||_inf
// recomputed here from the problem data, independently of the solver's own Summary.
//
// Usage: ncp-collection [--markdown]
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/collection.hpp"

int main(int argc, char** argv) {
  const bool markdown = argc > 1 && std::strcmp(argv[1], "--markdown") == 0;
  using ncp::NcpFunction;
  std::vector<ncp::collection::TestProblem> problems =
      ncp::collection::StandardCollection();

  if (markdown) {
    std::printf(
        "| problem | n | start | function | status | iterations | Jacobian evals | "
        "residual evals | merit restarts | strategy switches | ||Phi||_inf | natural "
        "residual | "
        "documented failure |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  } else {
    std::printf("%-26s %6s %-9s %-19s %-20s %5s %5s %6s %4s %10s %10s\n", "problem", "n",
                "start", "function", "status", "iter", "jac", "res", "rst", "|Phi|inf",
                "nat.res");
  }
  int runs = 0, converged = 0, false_claims = 0, expected = 0;
  for (ncp::collection::TestProblem& p : problems) {
    for (NcpFunction function : {NcpFunction::kFischerBurmeister, NcpFunction::kMin,
                                 NcpFunction::kPenalizedFischerBurmeister}) {
      for (const ncp::collection::StartPoint& start : p.starts) {
        ncp::Options options;
        options.ncp_function = function;
        ncp::Vector x = start.x;
        ncp::Summary summary;
        ncp::Solve(options, *p.F, p.lower, p.upper, &x, &summary);
        const double residual =
            ncp::collection::NaturalResidual(*p.F, p.lower, p.upper, x);
        const bool documented = p.FindExpectedFailure(start.label, function) != nullptr;
        ++runs;
        if (summary.IsSolutionUsable()) ++converged;
        // A claimed success whose recomputed residual is large counts as a failure.
        if (summary.IsSolutionUsable() && !(residual <= 1e-8)) ++false_claims;
        if (documented) ++expected;
        // The hybrid default's switches (Options::hybrid): "penalized-fb@51 min@101 ...".
        std::string switches;
        for (const ncp::StrategySwitch& w : summary.strategy_switches)
          switches += std::string(switches.empty() ? "" : " ") +
                      ncp::ToString(w.to_strategy.ncp_function) +
                      (w.to_strategy.regularized_direction ? "+lm" : "") + "@" +
                      std::to_string(w.iteration);
        if (markdown) {
          std::printf(
              "| %s | %d | %s | %s | %s | %d | %d | %d | %d | %s | %.2e | %.2e | %s |\n",
              p.name.c_str(), p.NumVariables(), start.label.c_str(),
              ncp::ToString(function), ncp::ToString(summary.termination),
              summary.iterations, summary.jacobian_evaluations,
              summary.residual_evaluations, summary.merit_restarts, switches.c_str(),
              summary.final_phi_inf, residual, documented ? "yes" : "");
        } else {
          std::printf("%-26s %6d %-9s %-19s %-20s %5d %5d %6d %4d %10.3e %10.3e%s\n",
                      p.name.c_str(), p.NumVariables(), start.label.c_str(),
                      ncp::ToString(function), ncp::ToString(summary.termination),
                      summary.iterations, summary.jacobian_evaluations,
                      summary.residual_evaluations, summary.merit_restarts,
                      summary.final_phi_inf, residual,
                      documented ? "  (documented failure)" : "");
          if (!switches.empty())
            std::printf("%28s strategies: %s\n", "", switches.c_str());
        }
      }
    }
  }
  std::printf(
      "\n%d runs: %d converged, %d not converged (%d of them documented failures), "
      "%d claimed convergence with natural residual > 1e-8\n",
      runs, converged, runs - converged, expected, false_claims);
  return false_claims == 0 ? 0 : 1;
}
