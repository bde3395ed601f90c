// contact-sim: runs a dynamic contact scene file and reports what it did.
//
//   contact-sim SCENE.toml [--json] [--step auto|condensed|sparse|full|explicit|ipopt]
//                          [--ncp-function fb|min|penalized-fb] [--dt S] [--friction F]
//                          [--friction-formulation lagged-bound|coulomb-fc] [--end-time
//                          S]
//                          [--output DIR] [--resume] [--quiet]
//   mpiexec -n R contact-sim SCENE.toml ...   (built with PETSc: the explicit or the
//   condensed step on R ranks,
//                                             docs/petsc-contact.md)
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cxxopts.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "contact/bodies_scene.hpp"
#include "contact/scene.hpp"
#include "contact/simulation.hpp"
#include "ncp/output_file.hpp"
#ifdef CONTACT_SIM_WITH_PETSC
#include <petscsys.h>

#include "contact/petsc/distributed_scene.hpp"
#endif

namespace {

// Set by the first SIGINT or SIGTERM: the run stops after the step in progress
// (DynamicOptions::stop_requested). The handler is reset on delivery (SA_RESETHAND), so a
// second signal ends the process at once.
std::atomic<bool> g_stop_requested{false};
volatile std::sig_atomic_t g_stop_signal = 0;
static_assert(std::atomic<bool>::is_always_lock_free,
              "the stop flag is set in a signal handler");

extern "C" void RequestStop(int signal_number) {
  g_stop_signal = signal_number;
  g_stop_requested.store(true);
}

/// SIGINT and SIGTERM stop the run between steps; SIGXFSZ is ignored so that a file-size
/// limit (ulimit -f) makes the write fail with EFBIG - reported, with the file's name -
/// instead of killing the process.
void InstallSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = RequestStop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGXFSZ, SIG_IGN);
}

/// A TOML basic string literal of `s` (quotes and backslashes escaped).
std::string TomlString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

/// MPI and PETSc when the process was started by mpiexec (OpenMPI, MPICH/PMI or PMIx
/// set these): a plain `contact-sim SCENE.toml` initializes neither and runs as it always
/// did. PETSc's options come from the environment variable PETSC_OPTIONS (the command
/// line is contact-sim's). On ranks other than 0 stdout and stderr go to /dev/null; a
/// rank's own failure is still printed, on the stderr kept in error_fd.
class MpiSession {
 public:
  MpiSession() {
#ifdef CONTACT_SIM_WITH_PETSC
    const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") ||
                          std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
    if (!launched) return;
    if (PetscInitialize(nullptr, nullptr, nullptr, nullptr) != 0) {
      std::fprintf(stderr, "contact-sim: PetscInitialize failed\n");
      std::exit(1);
    }
    active_ = true;
    // PETSc's errors reach the user as one line (contact::petsc's exception carries
    // PETSc's message, e.g. "Unable to find requested KSP type nonsense"), not PETSc's
    // traceback.
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
    MPI_Comm_size(PETSC_COMM_WORLD, &size_);
    // A one-process MPI stub (e.g. of a sequential MUMPS) found before libmpi makes every
    // rank rank 0 of 1: refuse rather than run R copies of the serial run.
    const char* launched_size = std::getenv("OMPI_COMM_WORLD_SIZE");
    if (launched_size && std::atoi(launched_size) != size_) {
      std::fprintf(stderr,
                   "contact-sim: mpiexec started %s processes but MPI reports %d: "
                   "MPI_Init is bound to "
                   "a one-process stub (link libmpi before Ipopt's sequential MUMPS)\n",
                   launched_size, size_);
      std::exit(1);
    }
    if (rank_ != 0) {
      error_fd_ = dup(2);
      if (!std::freopen("/dev/null", "w", stdout) ||
          !std::freopen("/dev/null", "w", stderr))
        error_fd_ = -1;
    }
#endif
  }
  ~MpiSession() {
#ifdef CONTACT_SIM_WITH_PETSC
    if (active_) PetscFinalize();
#endif
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool active() const { return active_; }
  /// `code`, once rank 0 has got here: mpiexec stops every rank as soon as one exits with
  /// a nonzero code, which must not cut rank 0's report short.
  int AfterRankZero(int code) const {
#ifdef CONTACT_SIM_WITH_PETSC
    if (active_) MPI_Barrier(PETSC_COMM_WORLD);
#endif
    return code;
  }
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// A warning (rank 0) for each PETSc option (PETSC_OPTIONS) that the run did not use:
  /// misspelt, or for a solver the scene's step does not have (-mass_ksp_type with the
  /// explicit step).
  void WarnAboutUnusedPetscOptions() const {
#ifdef CONTACT_SIM_WITH_PETSC
    if (!active_ || rank_ != 0) return;
    PetscInt count = 0;
    char **names = nullptr, **values = nullptr;
    if (PetscOptionsLeftGet(nullptr, &count, &names, &values) != 0) return;
    for (PetscInt i = 0; i < count; ++i)
      std::fprintf(stderr,
                   "contact-sim: warning: PETSc option -%s%s%s was not used by this run "
                   "(misspelt, or for a solver this step does not have)\n",
                   names[i], values[i] ? " " : "", values[i] ? values[i] : "");
    PetscOptionsLeftRestore(nullptr, &count, &names, &values);
#endif
  }
  /// A failure of this rank alone: printed (on rank > 0 with its rank), then every rank
  /// is stopped (MPI_Abort) - the others may be waiting for this one.
  [[noreturn]] void AbortRun(const std::string& what) const {
    const std::string line =
        "contact-sim: " + (rank_ > 0 ? "[rank " + std::to_string(rank_) + "] " : "") +
        what + "\n";
    if (rank_ == 0)
      std::fputs(line.c_str(), stderr);
    else if (error_fd_ >= 0 && write(error_fd_, line.data(), line.size()) < 0) {
    }
#ifdef CONTACT_SIM_WITH_PETSC
    MPI_Abort(PETSC_COMM_WORLD, 1);
#endif
    std::exit(1);
  }

 private:
  bool active_ = false;
  int rank_ = 0, size_ = 1;
  int error_fd_ = -1;
};

/// The command line; "scene" is the positional argument.
cxxopts::Options MakeCli() {
  cxxopts::Options cli("contact-sim",
                       "Elastodynamic contact of a body with a rigid obstacle");
  cli.add_options()("scene", "scene file (TOML)", cxxopts::value<std::string>())(
      "json", "print one JSON summary object on stdout")(
      "step", "override solver.step: auto, condensed, sparse, full, explicit, ipopt",
      cxxopts::value<std::string>())(
      "ncp-function", "override solver.ncp_function: fb, min, penalized-fb",
      cxxopts::value<std::string>())("solver",
                                     "replaced by --ncp-function and --step ipopt",
                                     cxxopts::value<std::string>())(
      "dt", "override time.dt [s]", cxxopts::value<std::string>())(
      "end-time", "override time.end_time [s]", cxxopts::value<std::string>())(
      "friction", "override friction.coefficient", cxxopts::value<std::string>())(
      "friction-formulation", "override solver.friction: lagged-bound, coulomb-fc",
      cxxopts::value<std::string>())("tolerance", "override solver.tolerance",
                                     cxxopts::value<std::string>())(
      "output", "override output.directory", cxxopts::value<std::string>())(
      "no-output", "write no files")(
      "distributed",
      "run through PETSc DMPlex even on one MPI rank (under mpiexec: the explicit, the "
      "condensed or the sparse step)")(
      "resume",
      "continue the run from the checkpoint in the output directory (checkpoint.bin, "
      "written every output.checkpoint_every steps and when interrupted); the scene "
      "and its overrides must be the same")(
      "quiet",
      "no progress lines, notes or warnings; a run that does not complete prints its "
      "reason once and no table")("h,help", "show this help")(
      "version", "print the version and exit");
  cli.parse_positional({"scene"});
  cli.positional_help("SCENE.toml");
  return cli;
}

/// The options that replace values of the scene file, as TOML literals validated with the
/// file's values (same ranges).
contact::SceneOverrides OverridesOf(const cxxopts::ParseResult& args) {
  contact::SceneOverrides overrides;
  const std::pair<const char*, const char*> string_options[] = {
      {"ncp-function", "solver.ncp_function"},
      {"step", "solver.step"},
      {"friction-formulation", "solver.friction"}};
  for (const auto& [option, key] : string_options)
    if (args.count(option))
      overrides.emplace_back(key, TomlString(args[option].as<std::string>()));
  const std::pair<const char*, const char*> number_options[] = {
      {"dt", "time.dt"},
      {"end-time", "time.end_time"},
      {"friction", "friction.coefficient"},
      {"tolerance", "solver.tolerance"}};
  for (const auto& [option, key] : number_options)
    if (args.count(option)) overrides.emplace_back(key, args[option].as<std::string>());
  return overrides;
}

/// The human-readable summary: the status line, the model's size, one row of the run's
/// counts (headed in words; the thesis's table names them dt, f_c, k_sim, N_Jac, N_func,
/// t_comp), then the accuracy and energy balance of the run, on MPI ranks too - but for
/// the condensed step there, which does not compute them yet.
void PrintReport(std::FILE* table, const contact::Scene& scene,
                 const contact::SceneResult& r) {
  const contact::DynamicSummary& s = r.summary;
  // A run that did not complete has its reason on stderr already (main): not twice.
  if (s.status == contact::DynamicStatus::kCompleted)
    std::fprintf(table, "%s: %s (%s)\n", scene.name.c_str(), contact::ToString(s.status),
                 s.message.c_str());
  else
    std::fprintf(table, "%s: %s (the reason is above)\n", scene.name.c_str(),
                 contact::ToString(s.status));
  std::fprintf(table,
               "  %d dofs (%d free), %d elements, %d contact nodes, dt_crit = %.4g s\n",
               r.num_dofs, r.num_free_dofs, r.num_elements, r.num_contact_nodes,
               s.critical_time_step);
  std::fprintf(table, "  %-10s %-8s %-10s %-10s %-10s %-10s\n", "dt [s]", "friction",
               "time steps", "Jacobians", "residuals", "time [s]");
  std::fprintf(table, "  %-10g %-8g %-10d %-10ld %-10ld %-10.4f\n", scene.dynamics.dt,
               scene.friction_coefficient, s.steps, s.jacobian_evaluations,
               s.residual_evaluations, s.seconds);
  std::fprintf(table,
               "  (friction: its coefficient; Jacobians, residuals: evaluations over all "
               "Newton steps)\n");
  std::fprintf(table,
               "  accuracy over all steps: equilibrium residual %.3e N, penetration %.3e "
               "m, contact "
               "residual %.3e N, friction-law violation %.3e N (%d steps outside %g x "
               "their accuracy)\n",
               s.max_equilibrium_residual, s.max_penetration,
               s.max_complementarity_residual, s.max_friction_residual,
               s.inaccurate_steps, contact::kAccuracySlack);
  std::fprintf(table, "  energy balance error %.3e J\n", s.energy_balance_error);
  if (s.finite_strain_from_step >= 0)
    std::fprintf(table, "  kinematics %s: finite strain (%s) from step %d\n",
                 contact::ToString(scene.kinematics.kinematics), s.material_model.c_str(),
                 s.finite_strain_from_step);
  else
    std::fprintf(table,
                 "  kinematics %s: small strain (largest rotation %.3g rad, spurious "
                 "strain %.3g)\n",
                 contact::ToString(scene.kinematics.kinematics), s.max_rotation,
                 s.max_spurious_strain);
}

/// CPU time of this process so far, user + system, all threads [s].
double ProcessCpuSeconds() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// The --json summary object; cpu_seconds: the CPU time of the run (set-up included).
nlohmann::json JsonSummary(const contact::Scene& scene, const contact::SceneResult& r,
                           int ranks, double cpu_seconds) {
  const contact::DynamicSummary& s = r.summary;
  nlohmann::json j;
  j["scene"] = scene.name;
  j["status"] = contact::ToString(s.status);
  j["message"] = s.message;
  j["steps"] = s.steps;
  j["newton_iterations"] = s.newton_iterations;
  j["jacobian_evaluations"] =
      s.jacobian_evaluations;  // the names of contact.run().summary
  j["residual_evaluations"] = s.residual_evaluations;
  j["friction_restarts"] = s.friction_restarts;
  // The sparse step's GMRES iterations (one solve with M each), in all and per Newton
  // step and per time step (0 for the other methods).
  j["krylov_iterations"] = s.krylov_iterations;
  j["krylov_iterations_per_newton_step"] =
      s.newton_iterations > 0 ? static_cast<double>(s.krylov_iterations) /
                                    static_cast<double>(s.newton_iterations)
                              : 0.0;
  j["krylov_iterations_per_step"] =
      s.steps > 0 ? static_cast<double>(s.krylov_iterations) / s.steps : 0.0;
  j["seconds"] = s.seconds;
  // CPU time of the whole run (model build and set-up included, every thread): on a
  // shared machine the wall time also counts the time other processes held the cores.
  j["cpu_seconds"] = cpu_seconds;
  // Time per phase (flat keys: the summary stays one level deep).
  j["assembly_seconds"] = s.assembly_seconds;
  j["mass_solve_seconds"] = s.mass_solve_seconds;
  j["contact_solve_seconds"] = s.contact_solve_seconds;
  j["accuracy_check_seconds"] = s.accuracy_check_seconds;
  j["mass_solves"] = s.mass_solves;
  // The prediction of step = auto (seconds per step, -1: the method does not apply).
  j["predicted_explicit_step_seconds"] = s.predicted_cost.explicit_seconds;
  j["predicted_condensed_step_seconds"] = s.predicted_cost.condensed_seconds;
  j["predicted_sparse_step_seconds"] = s.predicted_cost.sparse_seconds;
  j["auto_choice"] = contact::ToString(s.predicted_cost.choice);
  j["max_penetration"] = s.max_penetration;
  j["max_equilibrium_residual"] = s.max_equilibrium_residual;
  j["max_complementarity_residual"] = s.max_complementarity_residual;
  j["max_friction_residual"] = s.max_friction_residual;
  j["inaccurate_steps"] = s.inaccurate_steps;
  j["energy_balance_error"] = s.energy_balance_error;
  j["dt"] = scene.dynamics.dt;
  j["critical_time_step"] = s.critical_time_step;
  j["friction_coefficient"] = scene.friction_coefficient;
  j["ncp_function"] = ncp::ToString(scene.dynamics.ncp.ncp_function);
  j["step_method"] = contact::ToString(s.step_method);  // auto resolved
  j["friction_formulation"] = contact::ToString(scene.dynamics.friction_formulation);
  // Finite strain (docs/finite-strain.md): what ran and the step of the switch.
  j["kinematics"] = s.kinematics;
  j["kinematics_requested"] = contact::ToString(scene.kinematics.kinematics);
  j["finite_strain_from_step"] = s.finite_strain_from_step;
  j["material_model"] = s.material_model;
  j["max_rotation"] = s.max_rotation;
  j["max_spurious_strain"] = s.max_spurious_strain;
  j["small_strain_invalid_step"] = s.small_strain_invalid_step;
  j["tolerance"] = scene.dynamics.ncp.tolerance;
  j["dofs"] = r.num_dofs;
  j["free_dofs"] = r.num_free_dofs;
  j["contact_nodes"] = r.num_contact_nodes;
  j["ranks"] = ranks;
  if (s.max_ipopt_relative_difference >= 0)
    j["max_ipopt_relative_difference"] = s.max_ipopt_relative_difference;
  return j;
}

/// The scene on the MPI ranks (contact::petsc): the explicit or the condensed step
/// (contact::petsc::WhyNotDistributed); a scene it cannot run is refused alike on every
/// rank. SIGINT/SIGTERM (mpiexec passes them on to every rank) stop it after the step in
/// progress, agreed by the ranks at the step's end.
contact::SceneResult RunDistributed(const contact::Scene& scene, const MpiSession& mpi,
                                    bool progress) {
#ifdef CONTACT_SIM_WITH_PETSC
  const std::string why_not = contact::petsc::WhyNotDistributed(scene);
  if (!why_not.empty())
    throw contact::SceneError(why_not + " [" + std::to_string(mpi.size()) +
                              " MPI ranks]");
  try {
    return contact::petsc::RunSceneDistributed(scene, PETSC_COMM_WORLD, progress);
  } catch (const contact::SceneError&) {
    throw;  // refused on every rank
  } catch (const std::exception& e) {
    mpi.AbortRun(e.what());
  }
#else
  (void)scene, (void)progress;
  mpi.AbortRun("built without PETSc");
#endif
}

}  // namespace

// Exit codes: 0 completed, 1 refused input (scene, mesh, option value, a --resume without
// a usable checkpoint of the same scene) or a run that did not complete, 2 usage error
// (unknown option, missing scene, option without its value), 3 an output file could not
// be written (its name and the reason on stderr), 128 + the signal (130 SIGINT, 143
// SIGTERM) for a run stopped by a signal after a finished step.
// A scene with several bodies (docs/several-bodies.md): one process, a JSON or one-line
// summary; exit 0 when completed, 1 otherwise.
int RunBodiesScene(const cxxopts::ParseResult& args, bool distributed) {
  for (const char* option : {"step", "ncp-function", "dt", "end-time", "friction",
                             "friction-formulation", "tolerance", "resume"})
    if (args.count(option)) {
      std::cerr << "contact-sim: usage error: --" << option
                << " is not supported with several bodies ([[bodies]]); set it in the "
                   "scene file\n";
      return 2;
    }
  if (distributed) {
    std::cerr << "contact-sim: scenes with several bodies run on one process; MPI ranks "
                 "are not supported yet\n";
    return 1;
  }
  std::optional<std::string> output;
  if (args.count("output")) output = args["output"].as<std::string>();
  if (args.count("no-output")) output = std::string();
  contact::BodiesSceneSummary r;
  try {
    r = contact::RunBodiesScene(args["scene"].as<std::string>(), output);
  } catch (const std::exception& e) {
    std::cerr << "contact-sim: " << e.what() << std::endl;
    return 1;
  }
  nlohmann::json j;
  j["status"] = r.status;
  j["message"] = r.message;
  j["analysis"] = r.analysis;
  j["steps"] = r.steps;
  j["newton_iterations"] = r.newton_iterations;
  j["constraints"] = r.constraints;
  j["pairs"] = r.pair_names;
  j["pair_force"] = r.pair_force;
  j["max_penetration"] = r.max_penetration;
  if (args.count("json"))
    std::cout << j.dump(2) << std::endl;
  else if (!args.count("quiet") || r.status != "completed")
    std::cout << "contact-sim: " << r.status << ": " << r.message << std::endl;
  return r.status == "completed" ? 0 : 1;
}

int main(int argc, char** argv) {
  const MpiSession mpi;
  cxxopts::Options cli = MakeCli();
  cxxopts::ParseResult args;
  try {
    args = cli.parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "contact-sim: usage error: " << e.what() << "\n"
              << cli.help() << std::endl;
    return 2;
  }
  if (args.count("help")) {
    std::cout << cli.help() << std::endl;
    return 0;
  }
  if (args.count("version")) {
    std::cout << "contact-sim " << NCP_VERSION << std::endl;
    return 0;
  }
  if (args.count("solver")) {
    std::cerr << "contact-sim: usage error: --solver was replaced: --ncp-function "
                 "fb|min|penalized-fb "
                 "for the semismooth Newton steps, --step ipopt for Ipopt\n";
    return 2;
  }
  if (!args.count("scene")) {
    std::cerr << "contact-sim: usage error: no scene file given\n"
              << cli.help() << std::endl;
    return 2;
  }
  if (args.count("distributed") && !mpi.active()) {
    std::cerr << "contact-sim: usage error: --distributed needs a contact-sim built with "
                 "PETSc and started "
                 "by mpiexec\n";
    return 2;
  }
  const bool distributed =
      mpi.active() && (mpi.size() > 1 || args.count("distributed") > 0);
  try {
    if (contact::IsBodiesScene(args["scene"].as<std::string>()))
      return RunBodiesScene(args, distributed);
  } catch (const std::exception& e) {
    std::cerr << "contact-sim: " << e.what() << std::endl;
    return 1;
  }
  const bool json = args.count("json") > 0, quiet = args.count("quiet") > 0;
  contact::Scene scene;
  contact::SceneResult r;
  double cpu_seconds = -1.0;  // of RunScene (one-process runs)
  try {
    scene = contact::LoadScene(args["scene"].as<std::string>(), OverridesOf(args));
    if (!quiet)
      for (const std::string& w : scene.warnings)
        std::fprintf(stderr, "contact-sim: warning: %s\n", w.c_str());
    if (args.count("output")) scene.output_directory = args["output"].as<std::string>();
    if (args.count("no-output")) scene.output_directory.clear();
    scene.dynamics.stop_requested = &g_stop_requested;
    InstallSignalHandlers();
    if (distributed) {
      if (args.count("resume"))
        throw contact::SceneError(
            "--resume is not supported on MPI ranks yet (checkpoints are "
            "written by one-process runs only) [" +
            std::to_string(mpi.size()) + " MPI ranks]");
      r = RunDistributed(scene, mpi, !quiet);
    } else {
      contact::SceneRunOptions run;
      run.progress = !quiet;
      run.resume = args.count("resume") > 0;
      const double cpu_start = ProcessCpuSeconds();
      r = contact::RunScene(scene, run);
      cpu_seconds = ProcessCpuSeconds() - cpu_start;
    }
  } catch (const contact::CheckpointError& e) {
    std::cerr << "contact-sim: cannot resume: " << e.what() << std::endl;
    return 1;
  } catch (const ncp::OutputError& e) {
    std::cerr << "contact-sim: output failed, the run is incomplete: " << e.what()
              << std::endl;
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "contact-sim: " << e.what() << std::endl;
    return 1;
  }
  const contact::DynamicSummary& s = r.summary;
  if (r.resumed_from_step >= 0 && !quiet)
    std::fprintf(stderr, "contact-sim: resumed from the checkpoint of step %d\n",
                 r.resumed_from_step);
  // The JSON first: if stdout cannot take it, the run's result is lost - exit 3 without a
  // report that says completed.
  if (json)
    std::cout << JsonSummary(scene, r, mpi.size(), cpu_seconds).dump(2) << std::endl;
  if (json && (std::fflush(stdout) != 0 || std::ferror(stdout))) {
    std::fprintf(
        stderr,
        "contact-sim: writing the JSON summary to stdout failed: the result is lost\n");
    return 3;
  }
  std::FILE* table = json ? stderr : stdout;
  // A run that did not complete says why, once, on stderr (with --quiet and --json too);
  // a refused run (nothing run) or a quiet one prints no table after it.
  const bool completed = s.status == contact::DynamicStatus::kCompleted;
  if (!completed)
    std::fprintf(stderr, "contact-sim: %s: %s (%s)\n", scene.source.c_str(),
                 contact::ToString(s.status), s.message.c_str());
  if (s.status == contact::DynamicStatus::kInterrupted && r.checkpoint_step >= 0)
    std::fprintf(stderr,
                 "contact-sim: checkpoint of step %d written into %s; the same command "
                 "with --resume "
                 "continues the run\n",
                 r.checkpoint_step, scene.output_directory.c_str());
  if (completed || (!quiet && s.steps > 0)) PrintReport(table, scene, r);
  if (!quiet) mpi.WarnAboutUnusedPetscOptions();
  if (!r.files_written.empty() && !quiet)
    std::fprintf(stderr, "  wrote %zu files into %s\n", r.files_written.size(),
                 scene.output_directory.c_str());
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "contact-sim: writing the report to stdout failed\n");
    return 3;
  }
  // (On MPI ranks a rank the signal missed stops with the others: as if by SIGINT.)
  int code = s.status == contact::DynamicStatus::kCompleted ? 0 : 1;
  if (s.status == contact::DynamicStatus::kInterrupted)
    code = 128 + static_cast<int>(g_stop_signal ? g_stop_signal : SIGINT);
  return mpi.AfterRankZero(code);
}
