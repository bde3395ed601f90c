// ncp-petsc-bench: Bueler's radially symmetric obstacle problem (bueler_obstacle.hpp) on
// DMDA grids from 10^4 to 10^6+ unknowns, solved by ncp::petsc::Solver (FB or min
// semismooth Newton, nested iteration) and by PETSc's SNESVI (SSLS and RSLS, with and
// without -snes_grid_sequence), each with the same KSP/PC families (MUMPS LU, Krylov +
// PCMG, + hypre,
// + GAMG: CG GMRES where the Newton matrix is not symmetric). One CSV row per (solver
// configuration, grid) on the ranks of the run:
//
//   mpiexec -n 2 ncp-petsc-bench --grids 129,257 --solvers ncp-fb-seq-mg,rsls-seq-mg
//   --csv out.csv
//
// Configuration names: <kind>[-seq]-<linear>, kind in {ncp-fb, ncp-min, ssls, rsls},
// linear in {lu, mg, hypre, gamg}; --list prints them, --print-header the CSV header.
// Exit status 0 when every row ran (whatever the solvers' statuses), 1 on bad arguments
// or a PETSc error. benchmarks/petsc/run.sh runs the whole table;
// benchmarks/results/petsc/README.md has the results.
#include <petscsys.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "obstacle_runs.hpp"

namespace ncp_petsc_bench {
namespace {

const char* const kCsvHeader =
    "solver,ranks,n,grid,coarse_grid,linear,ksp,grid_sequencing,newton_iterations,total_"
    "newton_iterations,"
    "ksp_iterations,seconds,cpu_seconds,error_vs_exact,error_l2,natural_residual,status,"
    "native_status,"
    "peak_rss_mib";

const char* LinearName(LinearFamily linear) {
  switch (linear) {
    case LinearFamily::kMumpsLu:
      return "lu";
    case LinearFamily::kMultigrid:
      return "mg";
    case LinearFamily::kHypre:
      return "hypre";
    case LinearFamily::kGamg:
      return "gamg";
  }
  return "?";
}

std::vector<RunConfig> AllConfigs() {
  std::vector<RunConfig> configs;
  const std::pair<const char*, SolverKind> kinds[] = {
      {"ncp-fb", SolverKind::kNcpFischerBurmeister},
      {"ncp-min", SolverKind::kNcpMin},
      {"ssls", SolverKind::kSnesViSsls},
      {"rsls", SolverKind::kSnesViRsls}};
  const LinearFamily families[] = {LinearFamily::kMumpsLu, LinearFamily::kMultigrid,
                                   LinearFamily::kHypre, LinearFamily::kGamg};
  for (const auto& [kind_name, kind] : kinds) {
    for (bool sequencing : {false, true}) {
      for (LinearFamily linear : families) {
        configs.push_back(
            {std::string(kind_name) + (sequencing ? "-seq-" : "-") + LinearName(linear),
             kind, sequencing, linear});
      }
    }
  }
  return configs;
}

std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

struct Arguments {
  std::vector<PetscInt> grids{129};
  std::vector<std::string> solvers{"ncp-fb-seq-mg", "ssls-seq-mg", "rsls-seq-mg"};
  RunSettings settings;
  std::string csv;
  bool append = false;
  bool list = false;
  bool print_header = false;
  std::vector<char*> petsc_argv;  ///< what is left for PetscInitialize
};

double ParseNumber(const std::string& key, const std::string& value, double min,
                   double max) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(x >= min && x <= max)) {
    std::ostringstream message;
    message << key << " = '" << value << "': accepted a number in [" << min << ", " << max
            << "]";
    throw std::invalid_argument(message.str());
  }
  return x;
}

Arguments ParseArguments(int argc, char** argv) {
  Arguments args;
  args.settings.coarse_grid = 5;
  args.petsc_argv.push_back(argv[0]);
  for (int k = 1; k < argc; ++k) {
    const std::string key = argv[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= argc) throw std::invalid_argument(key + " needs a value");
      return argv[++k];
    };
    if (key == "--grids") {
      args.grids.clear();
      for (const std::string& g : SplitCommas(value())) {
        args.grids.push_back(PetscInt(ParseNumber("--grids", g, 3, 1e5)));
      }
    } else if (key == "--coarse") {
      args.settings.coarse_grid = PetscInt(ParseNumber(key, value(), 3, 1e5));
    } else if (key == "--solvers") {
      args.solvers = SplitCommas(value());
    } else if (key == "--tolerance") {
      args.settings.tolerance = ParseNumber(key, value(), 1e-16, 1.0);
    } else if (key == "--check-tolerance") {
      args.settings.check_tolerance = ParseNumber(key, value(), 1e-16, 1e3);
    } else if (key == "--ksp-rtol") {
      args.settings.ksp_rtol = ParseNumber(key, value(), 1e-14, 0.5);
    } else if (key == "--max-newton") {
      args.settings.max_newton_iterations = int(ParseNumber(key, value(), 1, 1e4));
    } else if (key == "--min-scale") {
      args.settings.min_scale = ParseNumber(key, value(), 1e-6, 1.0);
    } else if (key == "--csv") {
      args.csv = value();
    } else if (key == "--append") {
      args.append = true;
    } else if (key == "--print-header") {
      args.print_header = true;
    } else if (key == "--list") {
      args.list = true;
    } else if (key.rfind("--", 0) == 0) {
      throw std::invalid_argument(
          "unknown option " + key +
          " (accepted: --grids --coarse --solvers --tolerance --check-tolerance "
          "--ksp-rtol --max-newton --min-scale --csv --append --list --print-header; "
          "PETSc options "
          "-xxx)");
    } else {
      args.petsc_argv.push_back(argv[k]);
    }
  }
  args.petsc_argv.push_back(nullptr);
  return args;
}

const RunConfig& FindConfig(const std::vector<RunConfig>& configs,
                            const std::string& name) {
  for (const RunConfig& c : configs) {
    if (c.name == name) return c;
  }
  throw std::invalid_argument("--solvers: unknown configuration '" + name +
                              "' (--list prints them)");
}

std::string CsvRow(const RunConfig& config, const RunSettings& settings,
                   const RunResult& r) {
  std::ostringstream o;
  o.precision(6);
  o << config.name << ',' << r.ranks << ',' << r.n << ',' << settings.grid << ','
    << (config.grid_sequencing ? settings.coarse_grid : settings.grid) << ','
    << LinearName(config.linear) << ',' << KspDescription(config.linear, config.kind)
    << ',' << (config.grid_sequencing ? 1 : 0) << ',' << r.newton_iterations << ','
    << r.total_newton_iterations << ',' << r.ksp_iterations << ',' << r.seconds << ','
    << r.cpu_seconds << ',' << r.error_max << ',' << r.error_l2 << ','
    << r.natural_residual << ',' << r.status << ',' << r.native_status << ','
    << r.peak_rss_mib;
  return o.str();
}

PetscErrorCode RunAll(const Arguments& args) {
  PetscFunctionBeginUser;
  const std::vector<RunConfig> configs = AllConfigs();
  if (args.list) {
    for (const RunConfig& c : configs)
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", c.name.c_str()));
    PetscFunctionReturn(0);
  }
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  FILE* csv = nullptr;
  if (rank == 0 && !args.csv.empty()) {
    csv = std::fopen(args.csv.c_str(), args.append ? "a" : "w");
    PetscCheck(csv, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN,
               "--csv %s: cannot open for writing", args.csv.c_str());
    if (!args.append || std::ftell(csv) == 0) std::fprintf(csv, "%s\n", kCsvHeader);
    std::fflush(csv);
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", kCsvHeader));
  for (PetscInt grid : args.grids) {
    for (const std::string& name : args.solvers) {
      const RunConfig& config = FindConfig(configs, name);
      RunSettings settings = args.settings;
      settings.grid = grid;
      RunResult result;
      if (config.kind == SolverKind::kNcpFischerBurmeister ||
          config.kind == SolverKind::kNcpMin) {
        PetscCall(RunNcp(config, settings, &result));
      } else {
        PetscCall(RunSnesVi(config, settings, &result));
      }
      // Never trust a claimed success: the recomputed natural residual must agree.
      if (result.status == "converged" &&
          !(result.natural_residual <= settings.check_tolerance)) {
        result.status = "false_convergence";
      }
      const std::string row = CsvRow(config, settings, result);
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", row.c_str()));
      if (csv) {
        std::fprintf(csv, "%s\n", row.c_str());
        std::fflush(csv);
      }
    }
  }
  if (csv) std::fclose(csv);
  PetscFunctionReturn(0);
}

}  // namespace
}  // namespace ncp_petsc_bench

int main(int argc, char** argv) {
  using namespace ncp_petsc_bench;
  Arguments args;
  try {
    args = ParseArguments(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ncp-petsc-bench: %s\n", e.what());
    return 1;
  }
  if (args.print_header) {  // the CSV header alone (run.sh), without starting PETSc
    std::printf("%s\n", kCsvHeader);
    return 0;
  }
  int petsc_argc = int(args.petsc_argv.size()) - 1;
  char** petsc_argv = args.petsc_argv.data();
  if (PetscInitialize(&petsc_argc, &petsc_argv, nullptr, nullptr) != 0) return 1;
  int status = 0;
  try {
    status = RunAll(args) != 0 ? 1 : 0;
  } catch (const std::exception& e) {
    PetscPrintf(PETSC_COMM_WORLD, "ncp-petsc-bench: %s\n", e.what());
    status = 1;
  }
  if (PetscFinalize() != 0) return 1;
  return status;
}
