// fc-bench [DIR|FILE ...] --csv OUT.csv [--tolerance 1e-8] [--time-limit 10] [--quick]
// Every frictional contact problem (.dat, .hdf5) of the directories, with each ncp::fc
// formulation and each Siconos solver (fc3d_driver, fc2d_driver in 2D), from r = 0. One
// CSV row per (problem, solver): the solver's own claim, iterations, best-of-repetitions
// time per solve, and the natural-map error recomputed by ncp::fc::NaturalMapError at the
// returned r. A row counts as solved only if the solver claims convergence AND the
// recomputed error <= tolerance.
#include <chrono>
#include <csignal>
#include <cxxopts.hpp>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "fc_bench_config.hpp"
#include "fc_siconos_peer.hpp"
#include "ncp/fc/error.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/solver.hpp"
#include "ncp/output_file.hpp"

namespace {

struct Row {
  std::string problem, solver, status;
  int contacts = 0, dimension = 0, iterations = -1;
  bool claimed = false;
  double time_s = -1.0, error = -1.0, reported_error = -1.0;
};

std::vector<std::string> ProblemFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& in : inputs) {
    if (std::filesystem::is_directory(in)) {
      for (const auto& e : std::filesystem::directory_iterator(in)) {
        const std::string ext = e.path().extension().string();
        if (ext == ".dat" || ext == ".hdf5") files.push_back(e.path().string());
      }
    } else {
      files.push_back(in);
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// ncp::fc from r = 0, repeated until min_timing_s has passed (at most 20 times), best
/// time.
Row RunOurs(ncp::fc::Formulation f, const ncp::fc::FrictionProblem& p, double tolerance,
            double time_limit, double min_timing_s) {
  ncp::fc::Options options;
  options.formulation = f;
  options.tolerance = tolerance;
  options.max_time_s = time_limit;
  options.max_iterations = 1000;
  Row row;
  const char* short_name[] = {"ac", "nm", "fb", "hybrid"};  // in Formulation's order
  row.solver = std::string("ncp-") + short_name[static_cast<int>(f)];
  ncp::Vector r;
  ncp::fc::Summary summary;
  double best = 1e300, total = 0.0;
  for (int rep = 0; rep < 20 && (rep == 0 || total < min_timing_s); ++rep) {
    r.resize(0);
    const auto start = std::chrono::steady_clock::now();
    ncp::fc::Solve(options, p, &r, &summary);
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, t);
    total += t;
    if (summary.termination == ncp::fc::Termination::kTimeLimit) break;
  }
  row.status = ncp::fc::ToString(summary.termination);
  row.claimed = summary.IsSolutionUsable();
  row.iterations = summary.iterations;
  row.time_s = best;
  row.reported_error = summary.final_error;
  row.error = ncp::fc::NaturalMapError(p, r);
  return row;
}

Row RunSiconos(const std::string& solver, const std::string& path,
               const ncp::fc::FrictionProblem& p, double tolerance, double time_limit,
               double min_timing_s) {
  const int max_iterations =
      solver == "siconos-nsgs" || solver == "siconos-admm" ? 10000 : 1000;
  const fc_bench::PeerRun run = fc_bench::RunPeer(
      solver, path, p, tolerance, max_iterations, time_limit, min_timing_s);
  Row row;
  row.solver = solver;
  row.status = run.status;
  row.claimed = run.status == "converged";
  row.iterations = run.iterations;
  row.time_s = run.time_s;
  row.reported_error = run.siconos_error;
  row.error = run.r.size() == p.size() ? ncp::fc::NaturalMapError(p, run.r) : -1.0;
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  cxxopts::Options cli("fc-bench",
                       "ncp::fc vs Siconos fc3d solvers on frictional contact problems");
  cli.add_options()("inputs", "directories or files",
                    cxxopts::value<std::vector<std::string>>())(
      "csv", "output CSV", cxxopts::value<std::string>())(
      "tolerance", "natural-map error tolerance",
      cxxopts::value<double>()->default_value("1e-8"))(
      "time-limit", "seconds per solve; slower or failed rows are charged this",
      cxxopts::value<double>()->default_value("10"))(
      "min-timing",
      "repeat each solve until this many seconds have passed (best time kept)",
      cxxopts::value<double>()->default_value("0.05"))(
      "quick", "only problems with at most 10 contacts (smoke test)")("h,help",
                                                                      "this help");
  cli.parse_positional({"inputs"});
  std::signal(SIGXFSZ, SIG_IGN);  // a file-size limit: EFBIG, reported, not a kill
  try {
    const auto args = cli.parse(argc, argv);
    if (args.count("help") || !args.count("csv")) {
      std::cout << cli.help() << '\n';
      return args.count("help") ? 0 : 2;
    }
    std::vector<std::string> inputs{FC_BENCH_DATA_DIR};
    if (args.count("inputs")) inputs = args["inputs"].as<std::vector<std::string>>();
    const double tol = args["tolerance"].as<double>(),
                 limit = args["time-limit"].as<double>();
    const double min_timing = args["min-timing"].as<double>();
    // One committed block of rows per problem: a stopped benchmark keeps whole rows.
    ncp::OutputFile csv_file = ncp::OutputFile::Open(args["csv"].as<std::string>());
    std::ostream& csv = csv_file.stream();
    csv << "problem,contacts,dimension,solver,status,claimed,iterations,time_s,error,"
           "reported_error,solved\n";
    csv << std::setprecision(6);
    std::cerr << "fc-bench: tolerance " << tol << ", time limit " << limit << " s, peer "
              << fc_bench::PeerDescription() << '\n';
    for (const std::string& path : ProblemFiles(inputs)) {
      ncp::fc::FrictionProblem p;
      try {
        p = ncp::fc::ReadProblem(path);
      } catch (const std::exception& e) {
        std::cerr << "fc-bench: skipping " << path << ": " << e.what() << '\n';
        continue;
      }
      if (args.count("quick") && p.num_contacts > 10) continue;
      std::vector<Row> rows;
      for (auto f :
           {ncp::fc::Formulation::kHybrid, ncp::fc::Formulation::kAlartCurnier,
            ncp::fc::Formulation::kNaturalMap, ncp::fc::Formulation::kFischerBurmeister})
        rows.push_back(RunOurs(f, p, tol, limit, min_timing));
      for (const std::string& s : fc_bench::PeerSolvers(p.dimension))
        rows.push_back(RunSiconos(s, path, p, tol, limit, min_timing));
      for (Row& row : rows) {
        row.problem = p.name;
        row.contacts = p.num_contacts;
        row.dimension = p.dimension;
        const bool solved = row.claimed && row.error >= 0.0 && row.error <= tol;
        csv << row.problem << ',' << row.contacts << ',' << row.dimension << ','
            << row.solver << ',' << row.status << ',' << row.claimed << ','
            << row.iterations << ',' << row.time_s << ',' << row.error << ','
            << row.reported_error << ',' << solved << '\n';
        std::cerr << std::left << std::setw(36) << p.name << std::setw(16) << row.solver
                  << std::setw(22) << row.status << " it " << std::setw(6)
                  << row.iterations << " t " << std::setw(11) << row.time_s << " error "
                  << row.error << (solved ? "" : "  (not solved)") << '\n';
      }
      csv_file.Commit();
    }
    csv_file.Close();
    return 0;
  } catch (const ncp::OutputError& e) {
    std::cerr << "fc-bench: output failed: " << e.what() << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "fc-bench: " << e.what() << '\n';
    return 2;
  }
}
