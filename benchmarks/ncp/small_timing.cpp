// Side-by-side timing of ncp and Siconos on small problems; see small_timing.hpp.
#include "small_timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "ncp/solver.hpp"

namespace ncp_bench {
namespace {

using Clock = std::chrono::steady_clock;

/// Batches of about this many seconds, alternated between the solvers, kRounds times.
constexpr double kBatchSeconds = 2e-3;
constexpr int kRounds = 9;
constexpr int kMaxIterations = 500;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Seconds per call of `call`, run `calls` times.
template <class Call>
double SecondsPerCall(int calls, Call&& call) {
  const auto start = Clock::now();
  for (int c = 0; c < calls; ++c) call();
  return std::chrono::duration<double>(Clock::now() - start).count() / calls;
}

ncp::Options TimingOptions(double tolerance) {
  ncp::Options options;  // defaults: FB, kAuto (dense LU for n <= 100)
  options.tolerance = tolerance;
  options.max_iterations = kMaxIterations;
  return options;
}

// F(x) = M x + q + x.^3 / 10 (MixedFreeProblem); the Jacobian stores all n^2 entries.
class CubicAffine final : public ncp::SquareFunction {
 public:
  CubicAffine(ncp::DenseMatrix M, ncp::Vector q) : M_(std::move(M)), q_(std::move(q)) {}
  int NumVariables() const override { return static_cast<int>(q_.size()); }
  bool Evaluate(const ncp::Vector& x, ncp::Vector* F) override {
    F->noalias() = M_ * x;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      (*F)(i) += q_(i) + 0.1 * x(i) * x(i) * x(i);
    return true;
  }
  bool Jacobian(const ncp::Vector& x, ncp::SparseMatrix* J) override {
    if (J->nonZeros() != M_.size()) *J = M_.sparseView(0.0, 0.0);
    // Column-major, every entry stored: the values are M's, plus the diagonal term.
    double* values = J->valuePtr();
    const Eigen::Index n = x.size();
    for (Eigen::Index c = 0; c < n; ++c)
      for (Eigen::Index r = 0; r < n; ++r)
        values[c * n + r] = M_(r, c) + (r == c ? 0.3 * x(c) * x(c) : 0.0);
    return true;
  }

 private:
  ncp::DenseMatrix M_;
  ncp::Vector q_;
};

}  // namespace

MixedFreeProblem MakeMixedFreeProblem(int n, int free_variables, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  ncp::DenseMatrix B(n, n), K(n, n);
  ncp::Vector q(n);
  for (int i = 0; i < n; ++i) {
    q(i) = normal(rng);
    for (int j = 0; j < n; ++j) B(i, j) = normal(rng), K(i, j) = normal(rng);
  }
  const ncp::DenseMatrix M = 2.0 * ncp::DenseMatrix::Identity(n, n) +
                             (K - K.transpose()) + B * B.transpose() / n;
  MixedFreeProblem p;
  p.name = "mixed-free-" + std::to_string(n);
  p.F = std::make_unique<CubicAffine>(M, q);
  p.peer.F = p.F.get();
  p.peer.lower = ncp::Vector::Zero(n);
  p.peer.lower.head(free_variables).setConstant(-std::numeric_limits<double>::infinity());
  p.peer.upper = ncp::Vector::Constant(n, std::numeric_limits<double>::infinity());
  p.starts = {{"zero", ncp::Vector::Zero(n)}, {"ones", ncp::Vector::Ones(n)}};
  return p;
}

std::vector<SmallTimingRow> TimeSmallProblems(const std::vector<SmallTimingCase>& cases,
                                              double tolerance, std::ostream& log) {
  std::vector<SmallTimingRow> rows;
  if (!PeerAvailable()) {
    log << "small-problem timing skipped: built without Siconos\n";
    return rows;
  }
  const ncp::Options options = TimingOptions(tolerance);
  const double no_limit = std::numeric_limits<double>::infinity();
  char line[256];
  std::snprintf(line, sizeof line, "\n%-16s %-6s %3s %9s %9s %12s %12s %12s %7s\n",
                "problem", "start", "n", "ncp its", "sic. its", "ncp us/it",
                "reused us/it", "sic. us/it", "ratio");
  log << line;
  for (const SmallTimingCase& c : cases) {
    ncp::SquareFunction& F = *c.peer->F;
    const ncp::Vector& lower = c.peer->lower;
    const ncp::Vector& upper = c.peer->upper;
    ncp::Vector x;
    ncp::Summary summary;
    ncp::Solver reused(options);
    auto run_ncp = [&]() {
      x = c.x0;
      ncp::Solve(options, F, lower, upper, &x, &summary);
    };
    auto run_reused = [&]() {
      x = c.x0;
      reused.Solve(F, lower, upper, &x, &summary);
    };
    PeerResult peer;
    auto run_peer = [&]() {
      peer = RunPeer(PeerMethod::kMcpNewtonFb, *c.peer, c.x0, tolerance, kMaxIterations,
                     1000, no_limit);
    };
    // One untimed call each: iteration counts, status, warm caches.
    run_ncp();
    run_reused();
    run_peer();
    if (!peer.applicable || summary.iterations <= 0 || peer.iterations <= 0) continue;
    SmallTimingRow row;
    row.problem = c.problem;
    row.start = c.start;
    row.n = F.NumVariables();
    row.ncp_converged = summary.IsSolutionUsable();
    row.ncp_iterations = summary.iterations;
    row.peer_converged = peer.claimed_success;
    row.peer_iterations = peer.iterations;
    const int calls = std::max(
        1, static_cast<int>(kBatchSeconds / std::max(summary.total_time_s, 1e-7)));
    std::vector<double> ncp_s, reused_s, peer_s;
    for (int round = 0; round < kRounds; ++round) {
      ncp_s.push_back(SecondsPerCall(calls, run_ncp));
      peer_s.push_back(SecondsPerCall(calls, run_peer));
      reused_s.push_back(SecondsPerCall(calls, run_reused));
    }
    row.ncp_us = 1e6 * Median(ncp_s);
    row.ncp_reused_us = 1e6 * Median(reused_s);
    row.peer_us = 1e6 * Median(peer_s);
    std::snprintf(
        line, sizeof line, "%-16s %-6s %3d %9d %9d %12.3f %12.3f %12.3f %7.2f%s\n",
        row.problem.c_str(), row.start.c_str(), row.n, row.ncp_iterations,
        row.peer_iterations, row.ncp_us_per_iteration(),
        row.ncp_reused_us_per_iteration(), row.peer_us_per_iteration(),
        row.ncp_us_per_iteration() / row.peer_us_per_iteration(),
        row.ncp_converged && row.peer_converged ? "" : "  (not both converged)");
    log << line << std::flush;
    rows.push_back(row);
  }
  // Summary over the cases both solved: geometric mean, median and worst ratio per
  // iteration, for ncp::Solve (set-up in every call) and for a Solver kept between calls.
  auto summarize = [&](const char* what, double (SmallTimingRow::*ncp_time)() const) {
    std::vector<double> ratios;
    for (const SmallTimingRow& r : rows)
      if (r.ncp_converged && r.peer_converged)
        ratios.push_back((r.*ncp_time)() / r.peer_us_per_iteration());
    if (ratios.empty()) return;
    double log_sum = 0.0;
    int at_most_one = 0;
    for (double q : ratios) {
      log_sum += std::log(q);
      if (q <= 1.0) ++at_most_one;
    }
    std::snprintf(
        line, sizeof line,
        "time per iteration %s / Siconos MCP FB over %zu cases both solved: geometric "
        "mean %.2f, median %.2f, largest %.2f; ncp faster or equal in %d\n",
        what, ratios.size(), std::exp(log_sum / static_cast<double>(ratios.size())),
        Median(ratios), *std::max_element(ratios.begin(), ratios.end()), at_most_one);
    log << line;
  };
  summarize("ncp::Solve (one call)", &SmallTimingRow::ncp_us_per_iteration);
  summarize("ncp::Solver kept", &SmallTimingRow::ncp_reused_us_per_iteration);
  return rows;
}

void WriteSmallTimingCsv(const std::vector<SmallTimingRow>& rows, std::ostream& out) {
  out << "problem,start,n,ncp_converged,siconos_converged,ncp_iterations,siconos_"
         "iterations,"
         "ncp_us_per_call,ncp_reused_us_per_call,siconos_us_per_call,ncp_us_per_"
         "iteration,"
         "ncp_reused_us_per_iteration,siconos_us_per_iteration,ratio_per_iteration\n";
  for (const SmallTimingRow& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%s,%d,%d,%d,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                  r.problem.c_str(), r.start.c_str(), r.n, r.ncp_converged ? 1 : 0,
                  r.peer_converged ? 1 : 0, r.ncp_iterations, r.peer_iterations, r.ncp_us,
                  r.ncp_reused_us, r.peer_us, r.ncp_us_per_iteration(),
                  r.ncp_reused_us_per_iteration(), r.peer_us_per_iteration(),
                  r.ncp_us_per_iteration() / r.peer_us_per_iteration());
    out << line;
  }
}

}  // namespace ncp_bench
