// ncp-hybrid-overhead: what the hybrid default (Options::hybrid) costs on the runs the
// plain strategy solves (the target "problems the plain FB solves cost at most
// ~10% more"). For every collection problem, standard start and NCP function whose plain
// run (hybrid = false) converges: the work of both runs, which does not depend on the
// machine's load (iterations, Jacobian and residual evaluations), and their time,
// measured as the CPU time of the thread (not wall time: the 2 shared cores of the
// development machine run ~7 jobs, and a batch's wall time is mostly waiting) in
// alternating batches of calls (each batch ~kBatchSeconds, kRounds rounds, the order
// swapped every round); the time ratio is the median over the
// rounds of hybrid / plain. Both settings run on one kept Solver. One markdown line per
// run, then the totals.
//
// Usage: ncp-hybrid-overhead [--max-n N]   (default N = 1000)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

#include "ncp/solver.hpp"
#include "ncp_collection/collection.hpp"

namespace {

// CPU seconds of the calling thread.
double ThreadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
constexpr double kBatchSeconds = 1e-2;
constexpr int kRounds = 9;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int max_n = 1000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--max-n") == 0 && i + 1 < argc) {
      max_n = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: ncp-hybrid-overhead [--max-n N]\n");
      return 2;
    }
  }
  std::printf(
      "| problem | n | start | function | iterations | Jacobians | residuals | time "
      "ratio |\n|---|---|---|---|---|---|---|---|\n");
  long work[2][3] = {{0, 0, 0}, {0, 0, 0}};
  std::vector<double> ratios;
  int differ = 0, runs = 0;
  for (ncp::collection::TestProblem& p : ncp::collection::StandardCollection()) {
    if (p.NumVariables() > max_n) continue;
    for (const ncp::collection::StartPoint& start : p.starts) {
      for (const ncp::NcpFunction function :
           {ncp::NcpFunction::kFischerBurmeister, ncp::NcpFunction::kMin,
            ncp::NcpFunction::kPenalizedFischerBurmeister}) {
        ncp::Options options[2];
        for (ncp::Options& o : options) o.ncp_function = function;
        options[0].hybrid = false;
        // One Solver for both settings (set_options before every call): two Solvers
        // doing the same work differed by up to 4x in UMFPACK's factorization time
        // (jbearing-25x25, both plain), an effect of the instance, not of the settings.
        ncp::Solver solver(options[0]);
        ncp::Summary summary[2];
        ncp::Vector x;
        auto run = [&](int which) {
          x = start.x;
          solver.set_options(options[which]);
          solver.Solve(*p.F, p.lower, p.upper, &x, &summary[which]);
        };
        run(0);
        run(1);
        if (!summary[0].IsSolutionUsable()) continue;
        const int calls = std::max(
            1, static_cast<int>(kBatchSeconds / std::max(summary[0].total_time_s, 1e-7)));
        std::vector<double> round_ratio;
        for (int round = 0; round < kRounds; ++round) {
          double seconds[2];
          for (int i = 0; i < 2; ++i) {
            const int which = (round + i) % 2;
            const double t0 = ThreadSeconds();
            for (int c = 0; c < calls; ++c) run(which);
            seconds[which] = ThreadSeconds() - t0;
          }
          round_ratio.push_back(seconds[1] / seconds[0]);
        }
        const double ratio = Median(round_ratio);
        ratios.push_back(ratio);
        ++runs;
        const int counts[2][3] = {{summary[0].iterations, summary[0].jacobian_evaluations,
                                   summary[0].residual_evaluations},
                                  {summary[1].iterations, summary[1].jacobian_evaluations,
                                   summary[1].residual_evaluations}};
        for (int w = 0; w < 2; ++w)
          for (int c = 0; c < 3; ++c) work[w][c] += counts[w][c];
        const bool same = std::equal(counts[0], counts[0] + 3, counts[1]);
        differ += same ? 0 : 1;
        std::printf("| %s | %d | %s | %s | %d -> %d | %d -> %d | %d -> %d | %.3f |\n",
                    p.name.c_str(), p.NumVariables(), start.label.c_str(),
                    ncp::ToString(function), counts[0][0], counts[1][0], counts[0][1],
                    counts[1][1], counts[0][2], counts[1][2], ratio);
        std::fflush(stdout);
      }
    }
  }
  double log_sum = 0.0;
  for (double r : ratios) log_sum += std::log(r);
  std::printf(
      "\n%d runs converged without the hybrid; %d of them do different work with it. "
      "Totals without -> with: %ld -> %ld iterations, %ld -> %ld Jacobians, %ld -> %ld "
      "residual evaluations. Time with / without (median over %d interleaved rounds "
      "per run): geometric mean %.3f, median %.3f, largest %.3f.\n",
      runs, differ, work[0][0], work[1][0], work[0][1], work[1][1], work[0][2],
      work[1][2], kRounds, ratios.empty() ? 0.0 : std::exp(log_sum / ratios.size()),
      ratios.empty() ? 0.0 : Median(ratios),
      ratios.empty() ? 0.0 : *std::max_element(ratios.begin(), ratios.end()));
  return 0;
}
