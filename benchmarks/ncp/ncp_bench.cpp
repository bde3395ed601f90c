// ncp-bench: the comparison benchmark of the complementarity solvers.
//
// Runs every problem of the standard collection from every standard start, and the
// scalable families (obstacle problems in 1D and 2D, one- and two-sided, random sparse
// P-LCPs) at several sizes, with every solver configuration:
//   ncp-{fb,min,pfb}-{dense,umfpack}, ncp-fb-{klu,sparselu}   semismooth Newton (ours)
//   siconos-mcp-{fb,min}, siconos-lcp-{lemke,fb,min}          the Siconos Numerics peer
// and writes one row per (problem, start, solver, tolerance).
//
// Shared status vocabulary (each solver's native status is mapped onto it):
//   converged            the solver claims a solution
//   max_iterations       its iteration limit was reached
//   time_limit           stopped by (ncp) or exceeded (Siconos) the per-run time limit
//   stationary_point     stopped at / stagnated near a stationary point of the merit
//   function line_search_failure  no acceptable step numerical_error      singular Newton
//   system, NaN/Inf, failed evaluation failure              a peer failure without finer
//   information (Siconos info != 0) not_applicable       the solver cannot take this
//   problem (size, bounds, nonlinearity)
// `solved` is 1 only if status = converged AND the natural residual recomputed here,
// ||x - mid(l, u, x - F(x))||_inf, is <= 1e-6 (kAcceptedResidual below): a claimed
// success with a larger residual counts as a failure. A run that is not solved is charged
// the time limit in `charged_time_s` (the quantity the performance profiles use).
//
// Usage: ncp-bench [--quick] [--csv FILE] [--json] [--time-limit S]
//                  [--tolerances 1e-8,1e-10] [--dense-max-n N] [--peer-max-n N] [--max-n
//                  N]
//                  [--small-timing FILE] [--skip-table]
// --small-timing adds the side-by-side time per iteration against Siconos on the problems
// with n <= 10 (small_timing.hpp) and writes it to FILE; --skip-table runs only that.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "ncp/output_file.hpp"
#include "ncp/residuals.hpp"
#include "ncp/solver.hpp"
#include "ncp_bench_config.hpp"
#include "ncp_collection/collection.hpp"
#include "siconos_peer.hpp"
#include "small_timing.hpp"

namespace {

using ncp::collection::ObstacleKind;
using ncp::collection::TestProblem;

/// A claimed solution counts as solved when the natural residual is at most this.
constexpr double kAcceptedResidual = 1e-6;
/// Iteration limit of every Newton solver (ours and Siconos'); Lemke gets max(500, 10 n)
/// pivots.
constexpr int kMaxIterations = 500;

struct Settings {
  bool quick = false;
  bool json = false;
  std::string csv_path;
  double time_limit_s = 10.0;
  std::vector<double> tolerances = {1e-8, 1e-10};  ///< --quick: {1e-8}
  bool tolerances_given = false;
  /// Our dense (full-pivoting) LU only up to this n: above it one factorization takes
  /// seconds and the dense runs only measure the time limit.
  int dense_max_n = 200;
  /// Siconos is given dense matrices and cannot be interrupted (only its iteration limit
  /// stops it), so it runs only up to this n.
  int peer_max_n = 1000;
  /// Scalable-family members with more unknowns are skipped (a single sparse
  /// factorization cannot be interrupted by the time limit).
  long max_n = 100000;
  /// Side-by-side timing of the problems with n <= kSmallTimingMaxN into this CSV.
  std::string small_timing_path;
  bool skip_table = false;
};

/// The "small problems" of the per-iteration comparison.
constexpr int kSmallTimingMaxN = 10;
/// Tolerance of the per-iteration comparison (ncp's and Siconos' own stopping tests).
constexpr double kSmallTimingTolerance = 1e-10;

/// One problem of the benchmark: a collection problem or a member of a scalable family.
struct BenchProblem {
  std::string family;  ///< "collection" or the scalable family name
  int size = 0;        ///< the family's size parameter (n in 1D, m for m x m grids)
  TestProblem problem;
  ncp_bench::PeerProblem peer;
};

/// One solver configuration.
struct SolverConfig {
  std::string name;
  bool ours = true;
  ncp::NcpFunction function = ncp::NcpFunction::kFischerBurmeister;
  ncp::LinearSolverType linear_solver = ncp::LinearSolverType::kUmfpack;
  ncp_bench::PeerMethod peer = ncp_bench::PeerMethod::kMcpNewtonFb;
};

struct Row {
  std::string family, problem;
  int size = 0, n = 0;
  std::string start, solver, ncp_function, linear_solver;
  double tolerance = 0.0;
  std::string status, native_status;
  bool solved = false;
  int iterations = -1, jacobian_evaluations = -1, residual_evaluations = -1;
  double time_s = 0.0, charged_time_s = 0.0, natural_residual = 0.0;
};

std::string MapStatus(ncp::TerminationType t) {
  using T = ncp::TerminationType;
  switch (t) {
    case T::kConverged:
      return "converged";
    case T::kAtRoundoffFloor:
      return "at_roundoff_floor";
    case T::kMaxIterations:
      return "max_iterations";
    case T::kUserAbort:
      return "failure";  // no callback stops ncp here
    case T::kTimeLimit:
      return "time_limit";
    case T::kInfeasible:
      return "infeasible";
    case T::kStationaryPoint:
      return "stationary_point";
    case T::kLineSearchFailure:
      return "line_search_failure";
    case T::kLinearSolverFailure:
    case T::kNonFiniteValues:
    case T::kEvaluationFailure:
      return "numerical_error";
    case T::kNotSolved:
      return "failure";
  }
  return "failure";
}

const char* ShortName(ncp::LinearSolverType t) {
  switch (t) {
    case ncp::LinearSolverType::kDenseLU:
      return "dense";
    case ncp::LinearSolverType::kSparseLU:
      return "sparselu";
    case ncp::LinearSolverType::kUmfpack:
      return "umfpack";
    case ncp::LinearSolverType::kKlu:
      return "klu";
    case ncp::LinearSolverType::kCholmod:
      return "cholmod";
    case ncp::LinearSolverType::kAuto:
      return "auto";
  }
  return "?";
}

const char* ShortName(ncp::NcpFunction f) {
  switch (f) {
    case ncp::NcpFunction::kFischerBurmeister:
      return "fb";
    case ncp::NcpFunction::kMin:
      return "min";
    case ncp::NcpFunction::kPenalizedFischerBurmeister:
      return "pfb";
  }
  return "?";
}

std::vector<SolverConfig> SolverConfigs() {
  using F = ncp::NcpFunction;
  using L = ncp::LinearSolverType;
  std::vector<SolverConfig> configs;
  auto ours = [&](F f, L l) {
    SolverConfig c;
    c.name = std::string("ncp-") + ShortName(f) + "-" + ShortName(l);
    c.function = f;
    c.linear_solver = l;
    configs.push_back(c);
  };
  for (F f : {F::kFischerBurmeister, F::kMin, F::kPenalizedFischerBurmeister}) {
    ours(f, L::kDenseLU);
    ours(f, L::kUmfpack);
  }
  ours(F::kFischerBurmeister, L::kKlu);
  ours(F::kFischerBurmeister, L::kSparseLU);
  ours(F::kFischerBurmeister, L::kCholmod);
  if (ncp_bench::PeerAvailable()) {
    using P = ncp_bench::PeerMethod;
    for (P p : {P::kMcpNewtonFb, P::kMcpNewtonMin, P::kLcpLemke, P::kLcpNewtonFb,
                P::kLcpNewtonMin}) {
      SolverConfig c;
      c.name = ncp_bench::PeerName(p);
      c.ours = false;
      c.peer = p;
      configs.push_back(c);
    }
  }
  return configs;
}

/// F(x) = M x + q, checked at two random points around the start: F(y) - F(x) = M (y - x)
/// and F'(y) = F'(x) to relative accuracy 1e-10. Returns M through *M.
bool IsAffine(ncp::SquareFunction& F, const ncp::Vector& x0, ncp::SparseMatrix* M) {
  const int n = F.NumVariables();
  std::mt19937_64 engine(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  ncp::Vector y(n), Fx(n), Fy(n);
  for (int i = 0; i < n; ++i) y[i] = x0[i] + uniform(engine);
  ncp::SparseMatrix My;
  if (!F.Jacobian(x0, M) || !F.Jacobian(y, &My) || !F.Evaluate(x0, &Fx) ||
      !F.Evaluate(y, &Fy))
    return false;
  const double scale = 1.0 + Fx.lpNorm<Eigen::Infinity>() + Fy.lpNorm<Eigen::Infinity>();
  const ncp::Vector linear = Fx + (*M) * (y - x0);
  if ((Fy - linear).lpNorm<Eigen::Infinity>() > 1e-10 * scale) return false;
  const ncp::SparseMatrix difference = *M - My;
  double max_entry = 0.0, max_difference = 0.0;
  for (int k = 0; k < M->nonZeros(); ++k)
    max_entry = std::max(max_entry, std::abs(M->valuePtr()[k]));
  for (int k = 0; k < difference.nonZeros(); ++k)
    max_difference = std::max(max_difference, std::abs(difference.valuePtr()[k]));
  return max_difference <= 1e-12 * (1.0 + max_entry);
}

BenchProblem MakeBenchProblem(std::string family, int size, TestProblem problem) {
  BenchProblem b;
  b.family = std::move(family);
  b.size = size;
  b.problem = std::move(problem);
  b.peer.F = b.problem.F.get();
  b.peer.lower = b.problem.lower;
  b.peer.upper = b.problem.upper;
  b.peer.affine = IsAffine(*b.problem.F, b.problem.starts.front().x, &b.peer.M);
  return b;
}

std::vector<BenchProblem> MakeProblems(const Settings& settings) {
  std::vector<BenchProblem> problems;
  for (TestProblem& p : ncp::collection::StandardCollection()) {
    // --quick keeps the small problems of the collection only (n <= 100).
    if (settings.quick && p.NumVariables() > 100) continue;
    problems.push_back(MakeBenchProblem("collection", p.NumVariables(), std::move(p)));
  }
  const std::vector<int> sizes_1d =
      settings.quick ? std::vector<int>{50} : std::vector<int>{100, 1000, 10000, 100000};
  const std::vector<int> sizes_2d =
      settings.quick ? std::vector<int>{8} : std::vector<int>{10, 30, 100, 300};
  const std::vector<int> sizes_lcp =
      settings.quick ? std::vector<int>{50} : std::vector<int>{100, 1000, 10000, 100000};
  for (ObstacleKind kind : {ObstacleKind::kLowerBump, ObstacleKind::kTwoSidedBand}) {
    const std::string suffix = kind == ObstacleKind::kLowerBump ? "bump" : "band";
    for (int n : sizes_1d)
      if (n <= settings.max_n)
        problems.push_back(MakeBenchProblem("obstacle1d-" + suffix, n,
                                            ncp::collection::Obstacle1D(n, kind)));
    for (int m : sizes_2d)
      if (static_cast<long>(m) * m <= settings.max_n)
        problems.push_back(MakeBenchProblem("obstacle2d-" + suffix, m,
                                            ncp::collection::Obstacle2D(m, kind)));
  }
  for (int n : sizes_lcp)
    if (n <= settings.max_n)
      problems.push_back(
          MakeBenchProblem("random-plcp", n, ncp::collection::RandomPLcp(n)));
  return problems;
}

Row RunOne(const Settings& settings, BenchProblem& b,
           const ncp::collection::StartPoint& start, const SolverConfig& config,
           double tolerance) {
  TestProblem& p = b.problem;
  Row row;
  row.family = b.family;
  row.problem = p.name;
  row.size = b.size;
  row.n = p.NumVariables();
  row.start = start.label;
  row.solver = config.name;
  row.tolerance = tolerance;
  ncp::Vector x = start.x;
  bool claimed = false;
  if (config.ours) {
    row.ncp_function = ShortName(config.function);
    row.linear_solver = ShortName(config.linear_solver);
    if (config.linear_solver == ncp::LinearSolverType::kDenseLU &&
        row.n > settings.dense_max_n) {
      row.status = "not_applicable";
      row.native_status = "n above the dense limit";
    } else {
      ncp::Options options;
      options.ncp_function = config.function;
      options.linear_solver = config.linear_solver;
      options.tolerance = tolerance;
      options.max_iterations = kMaxIterations;
      options.max_seconds = settings.time_limit_s;
      ncp::Summary summary;
      ncp::Solve(options, *p.F, p.lower, p.upper, &x, &summary);
      row.status = MapStatus(summary.termination);
      row.native_status = ncp::ToString(summary.termination);
      row.iterations = summary.iterations;
      row.jacobian_evaluations = summary.jacobian_evaluations;
      row.residual_evaluations = summary.residual_evaluations;
      row.time_s = summary.total_time_s;
      claimed = summary.IsSolutionUsable();
    }
  } else {
    row.ncp_function = config.peer == ncp_bench::PeerMethod::kLcpLemke ? "pivoting"
                       : (config.peer == ncp_bench::PeerMethod::kMcpNewtonMin ||
                          config.peer == ncp_bench::PeerMethod::kLcpNewtonMin)
                           ? "min"
                           : "fb";
    row.linear_solver =
        config.peer == ncp_bench::PeerMethod::kLcpLemke ? "pivoting" : "dense";
    const ncp_bench::PeerResult r =
        ncp_bench::RunPeer(config.peer, b.peer, start.x, tolerance, kMaxIterations,
                           settings.peer_max_n, settings.time_limit_s);
    if (!r.applicable) {
      row.status = "not_applicable";
      row.native_status = r.reason;
    } else {
      x = r.x;
      claimed = r.claimed_success;
      row.native_status = r.native_status;
      row.iterations = r.iterations;
      row.jacobian_evaluations = r.jacobian_evaluations;
      row.residual_evaluations = r.residual_evaluations;
      row.time_s = r.time_s;
      // Siconos reports info != 0 without finer cause; its iteration count tells whether
      // the limit was reached. The time limit is enforced through NaN from the callbacks
      // (MCP) or checked afterwards (LCP).
      if (r.time_s > settings.time_limit_s) {
        row.status = "time_limit";
      } else if (claimed) {
        row.status = "converged";
      } else if (r.iterations >= r.iteration_limit) {
        row.status = "max_iterations";
      } else {
        row.status = "failure";
      }
    }
  }
  if (row.status == "not_applicable") {
    row.natural_residual = std::numeric_limits<double>::quiet_NaN();
  } else {
    row.natural_residual = ncp::BoxMcpResidual(*p.F, p.lower, p.upper, x);
  }
  row.solved = row.status == "converged" && row.natural_residual <= kAcceptedResidual;
  row.charged_time_s = row.solved ? row.time_s : settings.time_limit_s;
  return row;
}

std::string Sanitize(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '"', '\'');
  return s;
}

std::string Number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

const char* kCsvHeader =
    "family,problem,size,n,start,solver,ncp_function,linear_solver,tolerance,status,"
    "native_status,solved,iterations,jacobian_evaluations,residual_evaluations,time_s,"
    "charged_time_s,natural_residual";

std::string CsvLine(const Row& r) {
  std::ostringstream s;
  s << Sanitize(r.family) << ',' << Sanitize(r.problem) << ',' << r.size << ',' << r.n
    << ',' << Sanitize(r.start) << ',' << r.solver << ',' << r.ncp_function << ','
    << r.linear_solver << ',' << Number(r.tolerance) << ',' << r.status << ','
    << Sanitize(r.native_status) << ',' << (r.solved ? 1 : 0) << ',' << r.iterations
    << ',' << r.jacobian_evaluations << ',' << r.residual_evaluations << ','
    << Number(r.time_s) << ',' << Number(r.charged_time_s) << ','
    << Number(r.natural_residual);
  return s.str();
}

std::string JsonString(const std::string& v) {
  std::string out = "\"";
  for (char c : v) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string JsonNumber(double v) { return std::isfinite(v) ? Number(v) : "null"; }

std::string JsonObject(const Row& r) {
  std::ostringstream s;
  s << "{\"family\":" << JsonString(r.family) << ",\"problem\":" << JsonString(r.problem)
    << ",\"size\":" << r.size << ",\"n\":" << r.n << ",\"start\":" << JsonString(r.start)
    << ",\"solver\":" << JsonString(r.solver)
    << ",\"ncp_function\":" << JsonString(r.ncp_function)
    << ",\"linear_solver\":" << JsonString(r.linear_solver)
    << ",\"tolerance\":" << JsonNumber(r.tolerance)
    << ",\"status\":" << JsonString(r.status)
    << ",\"native_status\":" << JsonString(r.native_status)
    << ",\"solved\":" << (r.solved ? "true" : "false")
    << ",\"iterations\":" << r.iterations
    << ",\"jacobian_evaluations\":" << r.jacobian_evaluations
    << ",\"residual_evaluations\":" << r.residual_evaluations
    << ",\"time_s\":" << JsonNumber(r.time_s)
    << ",\"charged_time_s\":" << JsonNumber(r.charged_time_s)
    << ",\"natural_residual\":" << JsonNumber(r.natural_residual) << "}";
  return s.str();
}

/// The side-by-side small-problem timing (small_timing.hpp) over the collection problems
/// with n <= kSmallTimingMaxN, written to settings.small_timing_path.
bool RunSmallTiming(const Settings& settings, const std::vector<BenchProblem>& problems,
                    std::ostream& log) {
  std::vector<ncp_bench::SmallTimingCase> cases;
  for (const BenchProblem& b : problems) {
    if (b.family != "collection" || b.problem.NumVariables() > kSmallTimingMaxN) continue;
    for (const ncp::collection::StartPoint& start : b.problem.starts)
      cases.push_back({b.problem.name, start.label, &b.peer, start.x});
  }
  // Mixed problems with free variables, n = 2 and 10.
  std::vector<ncp_bench::MixedFreeProblem> mixed;
  mixed.push_back(ncp_bench::MakeMixedFreeProblem(2, 1, 2));
  mixed.push_back(ncp_bench::MakeMixedFreeProblem(10, 4, 10));
  for (const ncp_bench::MixedFreeProblem& p : mixed)
    for (const auto& [label, x0] : p.starts)
      cases.push_back({p.name, label, &p.peer, x0});
  const auto rows = ncp_bench::TimeSmallProblems(cases, kSmallTimingTolerance, log);
  ncp::OutputFile out = ncp::OutputFile::OpenAtomic(settings.small_timing_path);
  ncp_bench::WriteSmallTimingCsv(rows, out.stream());
  out.Close();
  return true;
}

[[noreturn]] void Usage(const char* message) {
  std::fprintf(stderr,
               "ncp-bench: %s\nusage: ncp-bench [--quick] [--csv FILE] [--json] "
               "[--time-limit S] [--tolerances T1,T2,...] [--dense-max-n N] "
               "[--peer-max-n N] [--max-n N] [--small-timing FILE] [--skip-table]\n",
               message);
  std::exit(2);
}

Settings ParseArguments(int argc, char** argv) {
  Settings s;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) Usage(("missing value after " + arg).c_str());
      return argv[++i];
    };
    if (arg == "--quick") {
      s.quick = true;
    } else if (arg == "--json") {
      s.json = true;
    } else if (arg == "--csv") {
      s.csv_path = value();
    } else if (arg == "--time-limit") {
      s.time_limit_s = std::atof(value().c_str());
      if (!(s.time_limit_s > 0.0)) Usage("--time-limit must be positive");
    } else if (arg == "--tolerances") {
      s.tolerances.clear();
      s.tolerances_given = true;
      std::stringstream list(value());
      std::string item;
      while (std::getline(list, item, ','))
        s.tolerances.push_back(std::atof(item.c_str()));
      for (double t : s.tolerances)
        if (!(t > 0.0)) Usage("tolerances must be positive");
      if (s.tolerances.empty()) Usage("--tolerances needs at least one value");
    } else if (arg == "--dense-max-n") {
      s.dense_max_n = std::atoi(value().c_str());
    } else if (arg == "--peer-max-n") {
      s.peer_max_n = std::atoi(value().c_str());
    } else if (arg == "--max-n") {
      s.max_n = std::atol(value().c_str());
      if (s.max_n < 1) Usage("--max-n must be >= 1");
    } else if (arg == "--small-timing") {
      s.small_timing_path = value();
    } else if (arg == "--skip-table") {
      s.skip_table = true;
    } else if (arg == "--help" || arg == "-h") {
      Usage("help");
    } else {
      Usage(("unknown argument " + arg).c_str());
    }
  }
  if (s.quick && !s.tolerances_given) s.tolerances = {1e-8};
  if (s.skip_table && s.small_timing_path.empty())
    Usage("--skip-table needs --small-timing FILE");
  return s;
}

}  // namespace

int RunBenchmark(int argc, char** argv) {
  const Settings settings = ParseArguments(argc, argv);
  // Progress goes to stderr when stdout carries the JSON.
  std::ostream& log = settings.json ? std::cerr : std::cout;
  log << "ncp-bench: peer = " << ncp_bench::PeerDescription()
      << (ncp_bench::PeerAvailable() ? ""
                                     : " (Siconos not found at configure time: "
                                       "running our solvers only)")
      << ", time limit " << settings.time_limit_s << " s, accepted natural residual "
      << kAcceptedResidual << (settings.quick ? ", quick mode" : "") << "\n";

  ncp::OutputFile csv;  // one committed row per run: a stopped benchmark keeps whole rows
  if (!settings.csv_path.empty()) {
    csv = ncp::OutputFile::Open(settings.csv_path);
    csv.stream() << kCsvHeader << "\n";
    csv.Commit();
  }
  std::vector<BenchProblem> problems = MakeProblems(settings);
  const std::vector<SolverConfig> configs = SolverConfigs();
  std::vector<Row> rows;
  char line[256];
  if (!settings.small_timing_path.empty() && !RunSmallTiming(settings, problems, log))
    return 1;
  for (BenchProblem& b : problems) {
    if (settings.skip_table) break;
    for (const ncp::collection::StartPoint& start : b.problem.starts) {
      for (const SolverConfig& config : configs) {
        for (double tolerance : settings.tolerances) {
          Row row = RunOne(settings, b, start, config, tolerance);
          if (csv.is_open()) {
            csv.stream() << CsvLine(row) << "\n";
            csv.Commit();
          }
          if (row.status != "not_applicable") {
            std::snprintf(line, sizeof line,
                          "%-26s %7d %-9s %-18s %6.0e %-20s %4d %9.3e %10.3e %s\n",
                          row.problem.c_str(), row.n, row.start.c_str(),
                          row.solver.c_str(), row.tolerance, row.status.c_str(),
                          row.iterations, row.time_s, row.natural_residual,
                          row.solved ? "" : "  NOT SOLVED");
            log << line << std::flush;
          }
          rows.push_back(std::move(row));
        }
      }
    }
  }
  if (csv.is_open()) csv.Close();
  if (settings.json) {
    std::cout << "[\n";
    for (size_t k = 0; k < rows.size(); ++k)
      std::cout << "  " << JsonObject(rows[k]) << (k + 1 < rows.size() ? ",\n" : "\n");
    std::cout << "]\n";
  }
  int attempted = 0, solved = 0;
  for (const Row& r : rows) {
    if (r.status == "not_applicable") continue;
    ++attempted;
    if (r.solved) ++solved;
  }
  log << rows.size() << " rows, " << attempted << " attempted, " << solved << " solved\n";
  return 0;
}

// Exit codes: 0 done, 1 a benchmark failure, 2 usage, 3 an output (--csv, --small-timing,
// the JSON on stdout) could not be written (the file and the reason on stderr).
int main(int argc, char** argv) {
  std::signal(SIGXFSZ, SIG_IGN);  // a file-size limit: EFBIG, reported, not a kill
  try {
    const int code = RunBenchmark(argc, argv);
    std::cout.flush();
    if (!std::cout) {
      std::fprintf(stderr, "ncp-bench: writing to stdout failed\n");
      return 3;
    }
    return code;
  } catch (const ncp::OutputError& e) {
    std::fprintf(stderr, "ncp-bench: output failed: %s\n", e.what());
    return 3;
  }
}
