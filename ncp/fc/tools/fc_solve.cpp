// fc-solve FILE [--global] [--solver hybrid|ac|nm|fb] [--tolerance T]
//          [--max-iterations N] [--time-limit S] [--gauss-seidel N] [--rho-scale S]
//          [--stall-window N]
//          [--gauss-seidel-fallback N] [--regularization R] [--shift-cap S] [--json]
//          [--reactions OUT.txt] [--velocities OUT.txt] [--verbose]
// Reads a frictional contact problem (Siconos .dat or FCLIB .hdf5), solves it, prints the
// status and Siconos' natural-map error recomputed at the returned r (or one JSON
// object), and writes r one value per line in the file's contact order. A global problem
// (M v = q + H r, u = H' v + b; --global for a text file, stated by an FCLIB file itself)
// is solved through its Delassus form W = H' M^-1 H (ncp/fc/global.hpp); the global
// velocity v = M^-1 (q + H r) is reported with the residuals of the global problem,
// recomputed from M, H, q, b without W. Exit code: 0 converged or at the round-off
// floor (--json: "converged" only for the first, "usable" for both), 1 not (the error
// reached is reported), 2 bad input or usage, 3 an output file could not be written
// (its name and the reason on stderr; each file is written as NAME.partial and renamed
// when complete, so NAME is never a truncated result).

#include <csignal>
#include <cxxopts.hpp>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "ncp/fc/error.hpp"
#include "ncp/fc/global.hpp"
#include "ncp/fc/io.hpp"
#include "ncp/fc/solver.hpp"
#include "ncp/output_file.hpp"

namespace {

/// r (or v) one value per line, written atomically (ncp::OutputFile).
void WriteVector(const std::string& path, const ncp::Vector& r) {
  ncp::OutputFile file = ncp::OutputFile::OpenAtomic(path);
  std::ostream& out = file.stream();
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (int i = 0; i < r.size(); ++i) out << r[i] << '\n';
  file.Close();
}

nlohmann::json ToJson(const ncp::fc::FrictionProblem& p, const ncp::fc::Options& o,
                      const ncp::fc::Summary& s, double error) {
  return {{"problem", p.name},
          {"dimension", p.dimension},
          {"contacts", p.num_contacts},
          {"solver", ncp::fc::ToString(o.formulation)},
          {"final_formulation", ncp::fc::ToString(s.formulation_final)},
          {"tolerance", o.tolerance},
          {"status", ncp::fc::ToString(s.termination)},
          {"converged", s.termination == ncp::fc::Termination::kConverged},
          {"usable", s.IsSolutionUsable()},
          {"message", s.message},
          {"iterations", s.iterations},
          {"gauss_seidel_sweeps", s.gauss_seidel_sweeps},
          {"fallback_sweeps", s.fallback_sweeps},
          {"attempts", s.attempts},
          {"backtracks", s.backtracks},
          {"linear_solver_failures", s.linear_solver_failures},
          {"levenberg_marquardt_steps", s.levenberg_marquardt_steps},
          {"linear_solver", ncp::ToString(s.linear_solver_used)},
          {"initial_error", s.initial_error},
          {"error", error},
          {"time_s", s.total_time_s}};
}

cxxopts::Options MakeCli() {
  cxxopts::Options cli(
      "fc-solve", "Solve a frictional contact problem (Siconos .dat or FCLIB .hdf5)");
  cli.add_options()("file", "problem file", cxxopts::value<std::string>())(
      "solver",
      "hybrid (default), ac (Alart-Curnier), nm (natural map) or fb (Fischer-Burmeister)",
      cxxopts::value<std::string>()->default_value("hybrid"))(
      "tolerance", "converged when Siconos' natural-map error <= this",
      cxxopts::value<double>()->default_value("1e-8"))(
      "max-iterations", "Newton steps in total",
      cxxopts::value<int>()->default_value("500"))(
      "time-limit", "wall-clock limit in seconds (0: none)",
      cxxopts::value<double>()->default_value("0"))(
      "gauss-seidel", "projected Gauss-Seidel sweeps before Newton",
      cxxopts::value<int>()->default_value("0"))(
      "gauss-seidel-fallback",
      "at most this many Gauss-Seidel sweeps when the hybrid's first attempt stalls",
      cxxopts::value<int>()->default_value(
          std::to_string(ncp::fc::Options().gauss_seidel_fallback_sweeps)))(
      "stall-window",
      "an attempt stalls when its error has not halved in this many steps",
      cxxopts::value<int>()->default_value("15"))(
      "rho-scale", "multiplies the per-contact rho of the formulations",
      cxxopts::value<double>()->default_value("1"))(
      "regularization",
      "Newton shift delta = this x max |J_ii| in (J + delta I) d = -Phi",
      cxxopts::value<double>()->default_value("1e-10"))(
      "shift-cap",
      "relative Newton shift min(this, natural-map error) when above --regularization",
      cxxopts::value<double>()->default_value("1e-6"))(
      "json", "print one JSON object instead of the text report")(
      "reactions", "write r, one value per line, to this file",
      cxxopts::value<std::string>())(
      "global",
      "the text file holds a global problem (M, H, q, b, mu); FCLIB files say so")(
      "velocities", "global problem: write v, one value per line, to this file",
      cxxopts::value<std::string>())("verbose", "one line per Newton step on stderr")(
      "h,help", "this help")("version", "print the version and exit");
  cli.parse_positional({"file"});
  cli.positional_help("FILE");
  return cli;
}

ncp::fc::Options OptionsFromArgs(const cxxopts::ParseResult& args) {
  ncp::fc::Options options;
  options.formulation = ncp::fc::ParseFormulation(args["solver"].as<std::string>());
  options.tolerance = args["tolerance"].as<double>();
  options.max_iterations = args["max-iterations"].as<int>();
  options.max_time_s = args["time-limit"].as<double>();
  options.gauss_seidel_sweeps = args["gauss-seidel"].as<int>();
  options.gauss_seidel_fallback_sweeps = args["gauss-seidel-fallback"].as<int>();
  options.stall_window = args["stall-window"].as<int>();
  options.rho_scale = args["rho-scale"].as<double>();
  options.regularization = args["regularization"].as<double>();
  options.shift_error_cap = args["shift-cap"].as<double>();
  options.log_to_stderr = args.count("verbose") > 0;
  return options;
}

/// The global problem's velocity v = M^-1 (q + H r) and its residuals recomputed from M,
/// H, q, b, into the JSON report; returns the text report's line.
std::string ReportGlobal(const ncp::fc::GlobalFrictionProblem& global_problem,
                         const ncp::Vector& r, const cxxopts::ParseResult& args,
                         nlohmann::json* report) {
  const ncp::Vector v = ncp::fc::GlobalVelocity(global_problem, r);
  const ncp::fc::GlobalResidual residual =
      ncp::fc::ComputeGlobalResidual(global_problem, v, r);
  (*report)["dofs"] = global_problem.num_dofs();
  (*report)["global_motion_residual"] = residual.motion;
  (*report)["global_contact_error"] = residual.contact;
  (*report)["velocity"] = std::vector<double>(v.data(), v.data() + v.size());
  if (args.count("velocities")) WriteVector(args["velocities"].as<std::string>(), v);
  std::ostringstream line;
  line << std::setprecision(3) << "global form, " << global_problem.num_dofs()
       << " dofs: |M v - q - H r| / (1 + |q|) = " << residual.motion
       << ", contact law at u = H'v + b: error " << residual.contact << '\n';
  return line.str();
}

/// Reads, solves, reports; the exit code (0 usable, 1 not).
int SolveFile(const cxxopts::ParseResult& args) {
  if (!args.count("file")) throw std::invalid_argument("no problem file given");
  const std::string file = args["file"].as<std::string>();
  const bool global = args.count("global") > 0 || ncp::fc::IsFclibGlobal(file);
  ncp::fc::GlobalFrictionProblem global_problem;
  if (global) global_problem = ncp::fc::ReadGlobalProblem(file);
  const ncp::fc::FrictionProblem problem =
      global ? ncp::fc::ReduceToLocal(global_problem) : ncp::fc::ReadProblem(file);
  if (args.count("velocities") && !global)
    throw std::invalid_argument("--velocities needs a global problem (--global)");
  const ncp::fc::Options options = OptionsFromArgs(args);
  ncp::Vector r;
  ncp::fc::Summary summary;
  ncp::fc::Solve(options, problem, &r, &summary);
  const double error = ncp::fc::NaturalMapError(problem, r);
  if (args.count("reactions")) WriteVector(args["reactions"].as<std::string>(), r);
  nlohmann::json report = ToJson(problem, options, summary, error);
  report["form"] = global ? "global" : "local";
  const std::string global_line =
      global ? ReportGlobal(global_problem, r, args, &report) : std::string();
  if (args.count("json")) {
    std::cout << report.dump(2) << '\n';
  } else {
    std::cout << problem.name << ": " << problem.num_contacts << " contacts, dimension "
              << problem.dimension << '\n'
              << global_line << summary.BriefReport() << '\n';
    if (!summary.IsSolutionUsable())
      std::cout << "NOT SOLVED: the returned reactions reach error " << error
                << " > tolerance " << options.tolerance << '\n';
  }
  return summary.IsSolutionUsable() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  cxxopts::Options cli = MakeCli();
  // A file-size limit (ulimit -f) makes the write fail with EFBIG, reported, instead of
  // killing the process with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    const auto args = cli.parse(argc, argv);
    if (args.count("help")) {
      std::cout << cli.help() << '\n';
      return 0;
    }
    if (args.count("version")) {
      std::cout << "fc-solve " << NCP_VERSION << '\n';
      return 0;
    }
    const int code = SolveFile(args);
    std::cout.flush();
    if (!std::cout) {
      std::cerr << "fc-solve: writing the report to stdout failed\n";
      return 3;
    }
    return code;
  } catch (const ncp::OutputError& e) {
    std::cerr << "fc-solve: output failed: " << e.what() << '\n';
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "fc-solve: " << e.what() << '\n';
    return 2;
  }
}
