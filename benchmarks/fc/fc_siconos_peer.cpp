#include "fc_siconos_peer.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "fc_bench_config.hpp"
#include "ncp/fc/io.hpp"

#if FC_BENCH_HAVE_SICONOS
#include "FrictionContactProblem.h"
#include "Friction_cst.h"
#include "NonSmoothDrivers.h"
#include "NumericsVerbose.h"
#include "SolverOptions.h"
#endif

namespace fc_bench {

bool PeerAvailable() { return FC_BENCH_HAVE_SICONOS != 0; }

std::string PeerDescription() {
  return PeerAvailable() ? std::string("Siconos Numerics ") + FC_BENCH_SICONOS_VERSION
                         : "none";
}

std::vector<std::string> PeerSolvers(int dimension) {
  if (!PeerAvailable()) return {};
  if (dimension == 2) return {"siconos-nsgs", "siconos-lemke"};
  return {"siconos-nsn-ac", "siconos-nsn-fb", "siconos-nsn-nm", "siconos-nsgs",
          "siconos-admm"};
}

#if !FC_BENCH_HAVE_SICONOS

PeerRun RunPeer(const std::string&, const std::string&, const ncp::fc::FrictionProblem&,
                double, int, double, double) {
  PeerRun run;
  run.status = "unavailable";
  return run;
}

#else

namespace {

int SolverId(const std::string& name, int dimension) {
  if (dimension == 2) {
    if (name == "siconos-nsgs") return SICONOS_FRICTION_2D_NSGS;
    if (name == "siconos-lemke") return SICONOS_FRICTION_2D_LEMKE;
    return -1;
  }
  if (name == "siconos-nsn-ac") return SICONOS_FRICTION_3D_NSN_AC;
  if (name == "siconos-nsn-fb") return SICONOS_FRICTION_3D_NSN_FB;
  if (name == "siconos-nsn-nm") return SICONOS_FRICTION_3D_NSN_NM;
  if (name == "siconos-nsgs") return SICONOS_FRICTION_3D_NSGS;
  if (name == "siconos-admm") return SICONOS_FRICTION_3D_ADMM;
  return -1;
}

/// Siconos' problem through its own reader: the .dat file itself, else ours written as a
/// sparse-block .dat (the storage Siconos' reader gives the .dat files too).
FrictionContactProblem* MakeProblem(const std::string& path,
                                    const ncp::fc::FrictionProblem& p) {
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".dat") == 0)
    return frictionContact_new_from_filename(path.c_str());
  const char* tmp = std::getenv("TMPDIR");
  const std::string copy =
      std::string(tmp ? tmp : "/tmp") + "/fc_bench_" + std::to_string(getpid()) + ".dat";
  ncp::fc::WriteSiconosDat(p, copy);
  FrictionContactProblem* problem = frictionContact_new_from_filename(copy.c_str());
  std::remove(copy.c_str());
  return problem;
}

/// The child: repeated solves from r = 0 until min_timing_s has passed, best time kept.
/// Writes status, iterations, time, Siconos' error and r to the pipe.
void ChildSolve(int fd, int solver_id, const std::string& path,
                const ncp::fc::FrictionProblem& p, double tolerance, int max_iterations,
                double min_timing_s) {
  numerics_set_verbose(0);
  FrictionContactProblem* problem = MakeProblem(path, p);
  const int n = p.size();
  std::vector<double> r(n), u(n);
  double best = 1e300, total = 0.0, error = -1.0;
  int info = -1, iterations = -1;
  for (int rep = 0; rep < 20 && (rep == 0 || total < min_timing_s); ++rep) {
    SolverOptions* options = solver_options_create(solver_id);
    options->dparam[SICONOS_DPARAM_TOL] = tolerance;
    options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
    std::fill(r.begin(), r.end(), 0.0);
    std::fill(u.begin(), u.end(), 0.0);
    const auto start = std::chrono::steady_clock::now();
    info = p.dimension == 2 ? fc2d_driver(problem, r.data(), u.data(), options)
                            : fc3d_driver(problem, r.data(), u.data(), options);
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, t);
    total += t;
    iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
    error = options->dparam[SICONOS_DPARAM_RESIDU];
    solver_options_delete(options);
  }
  const double header[4] = {static_cast<double>(info), static_cast<double>(iterations),
                            best, error};
  ssize_t ignored = write(fd, header, sizeof(header));
  ignored = write(fd, r.data(), sizeof(double) * n);
  (void)ignored;
  _exit(0);
}

/// Reads exactly size bytes before the deadline; false on timeout or EOF.
bool ReadAll(int fd, char* data, size_t size,
             std::chrono::steady_clock::time_point deadline) {
  size_t got = 0;
  while (got < size) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) return false;
    pollfd pfd{fd, POLLIN, 0};
    if (poll(&pfd, 1, static_cast<int>(left)) <= 0) return false;
    const ssize_t k = read(fd, data + got, size - got);
    if (k <= 0) return false;
    got += static_cast<size_t>(k);
  }
  return true;
}

}  // namespace

PeerRun RunPeer(const std::string& solver, const std::string& path,
                const ncp::fc::FrictionProblem& problem, double tolerance,
                int max_iterations, double time_limit_s, double min_timing_s) {
  PeerRun run;
  const int id = SolverId(solver, problem.dimension);
  if (id < 0) {
    run.status = "unavailable";
    return run;
  }
  int fds[2];
  if (pipe(fds) != 0) {
    run.status = "crashed";
    return run;
  }
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    // Siconos prints its own diagnostics (e.g. every failed LU); the row records the
    // outcome.
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) {
      dup2(null_fd, STDOUT_FILENO);
      dup2(null_fd, STDERR_FILENO);
    }
    ChildSolve(fds[1], id, path, problem, tolerance, max_iterations, min_timing_s);
  }
  close(fds[1]);
  // The repetitions may take up to min_timing_s beyond one solve.
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(time_limit_s + min_timing_s + 1.0));
  double header[4];
  const int n = problem.size();
  run.r.resize(n);
  const bool ok =
      ReadAll(fds[0], reinterpret_cast<char*>(header), sizeof(header), deadline) &&
      ReadAll(fds[0], reinterpret_cast<char*>(run.r.data()), sizeof(double) * n,
              deadline);
  close(fds[0]);
  if (!ok) kill(child, SIGKILL);
  int wstatus = 0;
  waitpid(child, &wstatus, 0);
  if (!ok) {
    run.status =
        WIFSIGNALED(wstatus) && WTERMSIG(wstatus) == SIGKILL ? "time_limit" : "crashed";
    run.r.resize(0);
    return run;
  }
  run.iterations = static_cast<int>(header[1]);
  run.time_s = header[2];
  run.siconos_error = header[3];
  run.status = header[0] == 0 ? "converged" : "not_converged";
  if (run.time_s > time_limit_s) run.status = "time_limit";
  return run;
}

#endif

}  // namespace fc_bench
