// contact-scaling-bench: the cost of one time step against the size of the body, for the
// three step methods of RunDynamics (full thesis system, condensed on the contact
// unknowns, explicit per node with lumped mass).
//
// Scene: a steel box (E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3) of cubic Hex8 cells of
// side h = 1 / n m, resting on the flat rigid floor z >= 0 (its bottom face z = 0 is the
// contact boundary, gap 0) and thrown at it with the uniform velocity (1, 0, -1) m/s:
// from the first step on, the bottom face is pressed onto the floor (and slides on it
// with f_c = 0.5). No Dirichlet condition. dt = 0.3 h / c_p (c_p = sqrt((lambda + 2 mu) /
// rho)), below dt_crit of both masses (RunDynamics checks it). Three series:
//   cube:   n x n x n cells, n = 6 ... 69 (10^3 ... 1.03 x 10^6 dofs);
//   column: a fixed contact face of 14 x 14 cells and 7 ... 448 cells in height: the
//           interior grows, the contact set does not (the condensed step's target);
//   face:   a slab of n x n x --face-layers cells, n = 9 ... 99 (10^2 ... 10^4 contact
//           nodes), consistent mass, f_c = --face-friction (0.3): the contact face grows
//           with the body (the sparse step's target). Per case also one sparse Cholesky
//           factorization of M (CHOLMOD, analysis included) and one solve with it, timed
//           in the same process after the run, and the step's time in units of them.
// Methods: full, condensed and sparse with the consistent mass, explicit with the lumped
// mass; cube and column each frictionless and with f_c = 0.5. Every case runs in its own
// child process (fork), so its peak resident memory (ru_maxrss) is its own, and a case
// over --time-limit is killed.
//
// Per case: dofs, contact nodes, model build time (mesh, K, M, contact frames),
// RunDynamics set-up (dt_crit, factorization, Delassus operator), mean time per step over
// steps 2..N (the first step includes one-off symbolic work and is reported apart) and of
// it the complementarity solve (StepRecord::solve_seconds), Newton iterations per step,
// GMRES iterations per Newton step and per step (sparse; StepRecord::krylov_iterations),
// the time of one product y = K x (SymmetricMultiply, the product RunDynamics uses; the
// fastest of 21 after the run), their ratio, the CPU time of RunDynamics (set-up and all
// steps; run with OMP_NUM_THREADS=1 on a shared machine) and the peak memory. The summary
// fits time per step = c dofs^p per series, method and friction (least squares in
// log-log).
//
// Usage: contact-scaling-bench [--csv FILE] [--max-dofs N] [--steps N] [--quick] ...
//        (--help lists all options)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <contact/dynamics.hpp>
#include <contact/mesh_generation.hpp>
#include <contact/obstacle.hpp>
#include <contact/scene.hpp>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <cxxopts.hpp>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "log_log_slope.hpp"
#include "ncp/output_file.hpp"

namespace {

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of this process so far, user + system, all threads [s].
double CpuSeconds() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

struct Case {
  std::string series;  // "cube", "column" or "face"
  int n = 0, nz = 0;   // cells n x n x nz
  std::string method;  // full, condensed, sparse, explicit
  double friction = 0.0;
  long long Dofs() const { return 3LL * (n + 1) * (n + 1) * (nz + 1); }
};

struct Row {
  Case c;
  std::string status = "not-run", message;
  long long dofs = 0;
  int contact_nodes = 0, steps = 0;
  double build_s = 0, setup_s = 0, first_step_s = 0, step_s = 0, solve_s = 0,
         newton_per_step = 0, krylov_per_newton = 0, krylov_per_step = 0;
  double run_cpu_s = 0;  // CPU time of RunDynamics (set-up and every step, all threads)
  double matvec_s = 0, ratio = 0, peak_mb = 0, dt = 0;
  double factor_s = 0, mass_solve_s = 0,
         step_over_factor = 0;  // Cholesky of M (face series)
};

contact::StepMethod MethodOf(const std::string& m) {
  if (m == "full") return contact::StepMethod::kFull;
  if (m == "explicit") return contact::StepMethod::kExplicit;
  if (m == "sparse") return contact::StepMethod::kSparse;
  return contact::StepMethod::kCondensed;
}

// One sparse Cholesky factorization of M (CHOLMOD's choice of simplicial or supernodal,
// symbolic analysis included) and one solve with it, the fastest of 3 each.
void TimeMassFactorization(const Eigen::SparseMatrix<double>& M, Row* row) {
  row->factor_s = row->mass_solve_s = std::numeric_limits<double>::infinity();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(M.rows());
  Eigen::VectorXd x;
  for (int i = 0; i < 3; ++i) {
    Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky;
    auto t = Clock::now();
    cholesky.compute(M);
    row->factor_s = std::min(row->factor_s, SecondsSince(t));
    t = Clock::now();
    x = cholesky.solve(b);
    row->mass_solve_s = std::min(row->mass_solve_s, SecondsSince(t));
  }
  row->step_over_factor = row->step_s / row->factor_s;
}

// Runs one case in this process and returns its row (without the peak memory).
Row RunCase(const Case& c, int steps, double tolerance) {
  Row row;
  row.c = c;
  const auto build_start = Clock::now();
  contact::Scene scene;
  scene.name = "scaling-" + c.series;
  scene.source = "contact-scaling-bench";
  scene.dim = 3;
  contact::BoxMeshOptions box;
  const double h = (c.series == "face" ? 5.0 : 1.0) / c.n;  // face: a 5 m x 5 m slab
  box.size = {h * c.n, h * c.n, h * c.nz};
  box.cells = {c.n, c.n, c.nz};
  box.side_roles[contact::Side::kZMin] = contact::BoundaryRole::kContact;
  scene.box = box;
  scene.material = contact::IsotropicMaterial{210e9, 0.3, 7850};
  scene.mass = c.method == "explicit" ? contact::MassKind::kLumped
                                      : contact::MassKind::kConsistent;
  scene.body_force = Eigen::VectorXd::Zero(3);
  scene.obstacle =
      std::make_shared<contact::HalfSpace>(contact::HalfSpace::ObstacleBelow(3, 2, 0.0));
  scene.friction_coefficient = c.friction;
  if (c.method == "sparse" ||
      c.series == "face")  // implicit Coulomb (the sparse step's only form)
    scene.dynamics.friction_formulation = contact::FrictionFormulation::kCoulombFc;
  const double E = scene.material.youngs_modulus, nu = scene.material.poisson_ratio;
  const double c_p =
      std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / scene.material.density);
  scene.dynamics.dt = 0.3 * h / c_p;
  scene.dynamics.end_time = steps * scene.dynamics.dt;
  scene.dynamics.step_method = MethodOf(c.method);
  scene.dynamics.initial_state = contact::InitialState::kPrescribed;
  scene.dynamics.ncp.tolerance = tolerance;
  scene.initial_velocity = Eigen::Vector3d(1.0, 0.0, -1.0);
  contact::SceneModel built =
      contact::BuildSceneModel(scene, contact::MakeStructuredBoxMesh(box));
  row.build_s = SecondsSince(build_start);
  row.dofs = built.model.K.rows();
  row.contact_nodes = static_cast<int>(built.model.contact_nodes.size());
  row.dt = scene.dynamics.dt;

  const double cpu_start = CpuSeconds();
  const contact::DynamicSummary s = contact::RunDynamics(built.model, built.options);
  row.run_cpu_s = CpuSeconds() - cpu_start;

  // One K x, right after the run (same cache state as in the loop): the fastest of 21
  // products, so that the ratio step / K x errs on the high side.
  Eigen::VectorXd x = s.u, y;
  double fastest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 21; ++i) {
    const auto t = Clock::now();
    contact::SymmetricMultiply(built.model.K, x, &y);
    fastest = std::min(fastest, SecondsSince(t));
  }
  row.matvec_s = fastest;
  row.status = contact::ToString(s.status);
  row.message = s.message;
  row.steps = s.steps;
  double loop = 0.0, later = 0.0, later_solve = 0.0;
  long newton = 0, krylov = 0;
  for (const contact::StepRecord& r : s.records) {
    loop += r.seconds;
    newton += r.newton_iterations;
    krylov += r.krylov_iterations;
    if (r.step > 1) later += r.seconds, later_solve += r.solve_seconds;
  }
  row.setup_s = s.seconds - loop;
  if (!s.records.empty()) row.first_step_s = s.records.front().seconds;
  row.step_s = s.steps > 1 ? later / (s.steps - 1) : row.first_step_s;
  row.solve_s = s.steps > 1 ? later_solve / (s.steps - 1) : 0.0;
  row.newton_per_step = s.steps > 0 ? static_cast<double>(newton) / s.steps : 0.0;
  row.krylov_per_newton = newton > 0 ? static_cast<double>(krylov) / newton : 0.0;
  row.krylov_per_step = s.steps > 0 ? static_cast<double>(krylov) / s.steps : 0.0;
  row.ratio = row.step_s / row.matvec_s;
  if (c.series == "face") TimeMassFactorization(built.model.M, &row);
  return row;
}

std::string Csv(const std::string& text) {
  std::string out = text;
  std::replace(out.begin(), out.end(), ',', ';');
  std::replace(out.begin(), out.end(), '\n', ' ');
  return out;
}

const char* kHeader =
    "series,n,nz,method,friction,dofs,contact_nodes,dt,status,steps,build_s,setup_s,"
    "first_step_s,step_s,solve_s,newton_per_step,matvec_s,step_over_matvec,peak_mb,"
    "factor_s,mass_solve_s,step_over_factor,krylov_per_newton,krylov_per_step,run_cpu_s,"
    "message";

std::string ToCsv(const Row& r) {
  std::ostringstream o;
  o.precision(6);
  o << r.c.series << ',' << r.c.n << ',' << r.c.nz << ',' << r.c.method << ','
    << r.c.friction << ',' << r.dofs << ',' << r.contact_nodes << ',' << r.dt << ','
    << r.status << ',' << r.steps << ',' << r.build_s << ',' << r.setup_s << ','
    << r.first_step_s << ',' << r.step_s << ',' << r.solve_s << ',' << r.newton_per_step
    << ',' << r.matvec_s << ',' << r.ratio << ',' << r.peak_mb << ',' << r.factor_s << ','
    << r.mass_solve_s << ',' << r.step_over_factor << ',' << r.krylov_per_newton << ','
    << r.krylov_per_step << ',' << r.run_cpu_s << ',' << Csv(r.message);
  return o.str();
}

// Forks, runs the case in the child (which writes its CSV row into a pipe) and returns
// the row with the child's peak memory; a crash or the time limit gives a row saying so.
Row RunIsolated(const Case& c, int steps, double tolerance, int time_limit) {
  Row row;
  row.c = c;
  row.dofs = c.Dofs();
  int fds[2];
  if (pipe(fds) != 0) {
    row.status = "error";
    row.message = "pipe failed";
    return row;
  }
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    alarm(static_cast<unsigned>(time_limit));
    std::string line;
    try {
      line = ToCsv(RunCase(c, steps, tolerance));
    } catch (const std::exception& e) {
      Row failed;
      failed.c = c;
      failed.status = "error";
      failed.message = e.what();
      line = ToCsv(failed);
    }
    line += "\n";
    if (write(fds[1], line.data(), line.size()) < 0) _exit(3);
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buffer[4096];
  ssize_t got;
  while ((got = read(fds[0], buffer, sizeof buffer)) > 0)
    text.append(buffer, static_cast<size_t>(got));
  close(fds[0]);
  int wstatus = 0;
  struct rusage usage {};
  wait4(pid, &wstatus, 0, &usage);
  const double peak_mb =
      static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss in KB
  if (text.empty()) {
    row.status =
        WIFSIGNALED(wstatus) && WTERMSIG(wstatus) == SIGALRM ? "time-limit" : "crashed";
    row.message = row.status == "time-limit"
                      ? "stopped after " + std::to_string(time_limit) + " s"
                      : "child ended with status " + std::to_string(wstatus);
    row.peak_mb = peak_mb;
    return row;
  }
  // Parse the child's row back (the fields we need to print and fit).
  std::vector<std::string> f;
  std::stringstream ss(text.substr(0, text.find('\n')));
  for (std::string item; std::getline(ss, item, ',');) f.push_back(item);
  if (f.size() < 26) {
    row.status = "error";
    row.message = "malformed row from the child: " + text;
    return row;
  }
  row.dofs = std::stoll(f[5]);
  row.contact_nodes = std::stoi(f[6]);
  row.dt = std::stod(f[7]);
  row.status = f[8];
  row.steps = std::stoi(f[9]);
  row.build_s = std::stod(f[10]);
  row.setup_s = std::stod(f[11]);
  row.first_step_s = std::stod(f[12]);
  row.step_s = std::stod(f[13]);
  row.solve_s = std::stod(f[14]);
  row.newton_per_step = std::stod(f[15]);
  row.matvec_s = std::stod(f[16]);
  row.ratio = std::stod(f[17]);
  row.factor_s = std::stod(f[19]);
  row.mass_solve_s = std::stod(f[20]);
  row.step_over_factor = std::stod(f[21]);
  row.krylov_per_newton = std::stod(f[22]);
  row.krylov_per_step = std::stod(f[23]);
  row.run_cpu_s = std::stod(f[24]);
  row.message = f[25];
  row.peak_mb = peak_mb;
  return row;
}

}  // namespace

int RunBenchmark(int argc, char** argv) {
  cxxopts::Options cli(
      "contact-scaling-bench",
      "Time per contact step against the number of dofs (see the file header)");
  cli.add_options()("csv", "write the rows to this CSV file",
                    cxxopts::value<std::string>())(
      "max-dofs", "largest body [dofs]",
      cxxopts::value<double>()->default_value("1.1e6"))(
      "full-max-dofs", "largest body for the full step",
      cxxopts::value<double>()->default_value("4e4"))(
      "condensed-max-unknowns",
      "largest condensed contact system (contact nodes frictionless, "
      "3 x nodes with friction: its dense LU costs O(unknowns^3) per Newton iteration)",
      cxxopts::value<int>()->default_value("1500"))(
      "steps", "time steps per case", cxxopts::value<int>()->default_value("20"))(
      "tolerance",
      "relative tolerance of each step in its own scales (DynamicOptions: ncp.tolerance; "
      "the library default)",
      cxxopts::value<double>()->default_value("1e-10"))(
      "time-limit", "seconds per case (the child is killed after)",
      cxxopts::value<int>()->default_value("900"))(
      "series", "cube, column, face or all",
      cxxopts::value<std::string>()->default_value("all"))(
      "methods",
      "step methods to run (full, condensed, sparse, explicit; the face series "
      "runs only condensed and sparse)",
      cxxopts::value<std::vector<std::string>>()->default_value(
          "full,condensed,sparse,explicit"))("face-layers",
                                             "cells through the slab of the face series",
                                             cxxopts::value<int>()->default_value("8"))(
      "face-friction", "f_c of the face series",
      cxxopts::value<double>()->default_value("0.3"))(
      "frictions", "friction coefficients to run",
      cxxopts::value<std::vector<double>>()->default_value("0,0.5"))(
      "quick", "small sizes and 3 steps (smoke test)")("h,help", "show this help");
  cxxopts::ParseResult args;
  try {
    args = cli.parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "contact-scaling-bench: " << e.what() << "\n" << cli.help() << "\n";
    return 2;
  }
  if (args.count("help")) {
    std::cout << cli.help() << "\n";
    return 0;
  }
  const bool quick = args.count("quick") > 0;
  const double max_dofs = quick ? 2000 : args["max-dofs"].as<double>();
  const double full_max = args["full-max-dofs"].as<double>();
  const int condensed_max_unknowns = args["condensed-max-unknowns"].as<int>();
  const int steps = quick ? 3 : args["steps"].as<int>();
  const double tolerance = args["tolerance"].as<double>();
  const int time_limit = args["time-limit"].as<int>();
  const std::string series = args["series"].as<std::string>();
  const auto methods = args["methods"].as<std::vector<std::string>>();
  const auto frictions = args["frictions"].as<std::vector<double>>();
  for (const std::string& m : methods)
    if (m != "full" && m != "condensed" && m != "sparse" && m != "explicit") {
      std::cerr << "contact-scaling-bench: unknown method '" << m
                << "' (full, condensed, sparse, explicit)\n";
      return 2;
    }
  for (double f : frictions)
    if (!(f >= 0.0)) {
      std::cerr << "contact-scaling-bench: friction coefficients must be >= 0\n";
      return 2;
    }
  if (series != "cube" && series != "column" && series != "face" && series != "all") {
    std::cerr << "contact-scaling-bench: --series must be cube, column, face or all\n";
    return 2;
  }
  const int face_layers = args["face-layers"].as<int>();
  const double face_friction = args["face-friction"].as<double>();
  if (face_layers < 1 || !(face_friction >= 0.0)) {
    std::cerr
        << "contact-scaling-bench: --face-layers >= 1 and --face-friction >= 0 needed\n";
    return 2;
  }
  if (!(max_dofs > 0) || steps < 2 || time_limit < 1) {
    std::cerr << "contact-scaling-bench: --max-dofs > 0, --steps >= 2 and --time-limit "
                 ">= 1 needed\n";
    return 2;
  }

  // Cases over a method's limit are listed as skipped (with the reason), not run.
  std::vector<Case> cases;
  std::vector<Row> skipped;
  auto add = [&](const std::string& name, int n, int nz) {
    for (const std::string& method : methods)
      for (double friction :
           name == "face" ? std::vector<double>{face_friction} : frictions) {
        if (name == "face" && method != "condensed" && method != "sparse") continue;
        Case c{name, n, nz, method, friction};
        if (c.Dofs() > max_dofs) continue;
        const int unknowns = (n + 1) * (n + 1) * (friction > 0 ? 3 : 1);
        std::string reason;
        if (c.method == "full" && c.Dofs() > full_max)
          reason = "full step limited to --full-max-dofs";
        if (c.method == "condensed" && unknowns > condensed_max_unknowns)
          reason = "about " + std::to_string(unknowns) +
                   " condensed unknowns > --condensed-max-unknowns";
        if (reason.empty()) {
          cases.push_back(c);
        } else {
          Row r;
          r.c = c;
          r.dofs = c.Dofs();
          r.contact_nodes = (n + 1) * (n + 1);
          r.status = "skipped";
          r.message = reason;
          skipped.push_back(r);
        }
      }
  };
  if (series == "cube" || series == "all")
    for (int n :
         quick ? std::vector<int>{3, 5} : std::vector<int>{6, 9, 14, 21, 31, 46, 69})
      add("cube", n, n);
  if (series == "column" || series == "all")
    for (int nz :
         quick ? std::vector<int>{2, 4} : std::vector<int>{7, 14, 28, 56, 112, 224, 448})
      add("column", quick ? 3 : 14, nz);
  if (series == "face" || series == "all")
    for (int n :
         quick ? std::vector<int>{4, 6} : std::vector<int>{9, 14, 21, 31, 46, 69, 99})
      add("face", n, quick ? 2 : face_layers);

  ncp::OutputFile
      csv;  // one committed row per case: a stopped benchmark keeps whole rows
  if (args.count("csv")) {
    csv = ncp::OutputFile::Open(args["csv"].as<std::string>());
    csv.stream() << kHeader << "\n";
  }
  for (const Row& r : skipped)
    if (csv.is_open()) csv.stream() << ToCsv(r) << "\n";
  if (csv.is_open()) csv.Commit();
  std::printf(
      "# %zu cases, %d steps each (%zu skipped); times in seconds, memory in MB\n",
      cases.size(), steps, skipped.size());
  std::printf(
      "%-6s %4s %4s %-9s %4s %9s %6s %-10s %8s %8s %10s %10s %7s %10s %8s %8s %9s %9s "
      "%9s %7s %7s %8s\n",
      "series", "n", "nz", "method", "f_c", "dofs", "nodes", "status", "build", "setup",
      "step", "solve", "newton", "K x", "step/Kx", "peak_MB", "chol(M)", "solve(M)",
      "step/chol", "kry/nwt", "kry/stp", "run_cpu");
  std::vector<Row> rows;
  for (const Case& c : cases) {
    const Row r = RunIsolated(c, steps, tolerance, time_limit);
    rows.push_back(r);
    std::printf(
        "%-6s %4d %4d %-9s %4.1f %9lld %6d %-10s %8.3f %8.3f %10.3e %10.3e %7.2f %10.3e "
        "%8.2f %8.0f %9.3e %9.3e %9.3f %7.1f %7.1f %8.2f\n",
        c.series.c_str(), c.n, c.nz, c.method.c_str(), c.friction, r.dofs,
        r.contact_nodes, r.status.substr(0, 10).c_str(), r.build_s, r.setup_s, r.step_s,
        r.solve_s, r.newton_per_step, r.matvec_s, r.ratio, r.peak_mb, r.factor_s,
        r.mass_solve_s, r.step_over_factor, r.krylov_per_newton, r.krylov_per_step,
        r.run_cpu_s);
    if (r.status != "completed") std::printf("       %s\n", r.message.c_str());
    std::fflush(stdout);
    if (csv.is_open()) {
      csv.stream() << ToCsv(r) << "\n";
      csv.Commit();
    }
  }
  if (csv.is_open()) csv.Close();

  // Fitted exponents of the time per step (completed cases with >= 3 sizes).
  std::printf(
      "# fitted exponent p of time per step = c dofs^p (steps 2..N), and of K x\n");
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> fits, matvec;
  for (const Row& r : rows) {
    if (r.status != "completed") continue;
    char key[96];
    std::snprintf(key, sizeof key, "%s %s f_c=%g", r.c.series.c_str(), r.c.method.c_str(),
                  r.c.friction);
    fits[key].first.push_back(static_cast<double>(r.dofs));
    fits[key].second.push_back(r.step_s);
    matvec[r.c.series].first.push_back(static_cast<double>(r.dofs));
    matvec[r.c.series].second.push_back(r.matvec_s);
  }
  for (const auto& [key, xy] : fits)
    if (xy.first.size() >= 3)
      std::printf("#   %-28s p = %.3f over %zu sizes (%.3g .. %.3g dofs)\n", key.c_str(),
                  LogLogSlope(xy.first, xy.second), xy.first.size(), xy.first.front(),
                  xy.first.back());
  for (const auto& [key, xy] : matvec)
    if (xy.first.size() >= 3)
      std::printf("#   %-28s p = %.3f\n", (key + " K x").c_str(),
                  LogLogSlope(xy.first, xy.second));
  int failures = 0;
  for (const Row& r : rows) failures += r.status != "completed";
  return failures == 0 ? 0 : 1;
}

// Exit codes: 0 every case completed, 1 some case did not, 2 usage, 3 the CSV could not
// be written (its name and the reason on stderr).
int main(int argc, char** argv) {
  std::signal(SIGXFSZ, SIG_IGN);  // a file-size limit: EFBIG, reported, not a kill
  try {
    const int code = RunBenchmark(argc, argv);
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      std::fprintf(stderr, "contact-scaling-bench: writing the table to stdout failed\n");
      return 3;
    }
    return code;
  } catch (const ncp::OutputError& e) {
    std::fprintf(stderr, "contact-scaling-bench: output failed: %s\n", e.what());
    return 3;
  }
}
