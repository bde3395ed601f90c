// contact-bench: dynamic contact scenes (the thesis's scenes of sections 6.1-6.3 and the
// validation scenes with exact solutions) under every step solver. One row per
// (scene, solver, setting) with a shared status vocabulary, counts, CPU time, an error
// recomputed here from the displacements, the maximum penetration and the energy balance.
//
// Sweeps
//  - tolerance: the solver's tolerance (semismooth Newton: ||Phi||_inf in metres;
//    Ipopt: its `tol`) on the scene's own mesh and dt;
//  - dt: fractions of dt_crit = 2 / omega_max of central differences, dt = end_time / N;
//  - mesh: the scene's cells times a factor, dt a fixed fraction of that mesh's dt_crit;
//  - stability: dt from 0.25 to 2 dt_crit times f_c in {0, 0.1, 0.5, 1, 5}.
// Errors (the "error" column, relative):
//  - bar impact: max of the errors of the contact duration (2L/c), the plateau contact
//    stress (rho c v0) and the rebound velocity (-v0) of the mass-weighted mean;
//  - sliding block: stopping distance v0^2 / (2 mu g) of the mass-weighted mean;
//  - incline: acceleration g (sin theta - mu cos theta) fitted after t = 0.1 s;
//  - thesis scenes (no exact solution): tolerance and dt sweeps: ||u - u_ref||_2 /
//  ||u_ref||_2
//    of the final displacement against the same mesh at the smallest dt / 1e-12 tolerance
//    (FB); mesh sweep: the final displacement of the scene's marked point against the
//    finest mesh.
// "reference_error" (tolerance sweep only) is the final-field difference against the FB
// run at tolerance 1e-12 on the same discretization: the solver's part of the error.
//
// Independent check: for every step from the third on, the contact forces are recomputed
// from three consecutive displacements, r = M (u^{k+1} - 2 u^k + u^{k-1}) / dt^2 + K u^k
// - f^k, lambda_c = -n_c . r_c, gap_c = s_c - n_c . u_c^{k+1}, and the normal
// complementarity residual max_c |min(gap_c, lambda_c dt^2 / M_max)| (metres, the units
// of the solver's tolerance) is compared with the claimed convergence: above max(10 tol,
// 1e-9) m (Ipopt: 1e-6 m) a "completed" run is reported as "inaccurate". (Friction is not
// checked.)
//
// Statuses: converged, failed (solver failure in some step), unstable (energy blow-up),
// refused (dt > dt_crit without allow_unstable_time_step), inaccurate, skipped.
//
// Usage: contact-bench [--quick] [--csv FILE] [--json] [--examples DIR]
//                      [--only workprecision|stability]
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <contact/scene.hpp>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ncp/output_file.hpp"

#ifndef CONTACT_EXAMPLES_DIR
#define CONTACT_EXAMPLES_DIR "examples"
#endif

namespace {

using contact::DynamicStatus;
/// The per-step solvers compared: semismooth Newton with one NCP function, or Ipopt's QP
/// (StepMethod::kIpopt). The names are the "solver" column of the results.
enum class StepSolver { kFischerBurmeister, kMin, kPenalizedFischerBurmeister, kIpopt };

enum class ErrorKind { kBarImpact, kSlidingBlock, kIncline, kReference };

struct SceneEntry {
  std::string family;  ///< "validation" or "thesis"
  std::string file;    ///< relative to the examples directory
  ErrorKind kind;
  std::vector<double> mesh_factors;  ///< cells times these
  std::vector<double> dt_fractions;  ///< dt / dt_crit of the dt sweep
  double mesh_courant = 0.5;         ///< dt / dt_crit of the mesh sweep
  double end_time = -1.0;            ///< override of the scene's end time (< 0: keep)
};

/// One benchmark row.
struct Row {
  std::string family, scene, sweep, setting, solver;
  double tolerance = 0, dt = 0, dt_crit = 0, dt_ratio = 0, friction = 0, mesh_factor = 1;
  int dofs = 0;
  std::string status = "skipped", message;
  int steps = -1;
  long newton = -1, jacobians = -1, residuals = -1;
  double seconds = -1, error = NAN, reference_error = NAN, max_penetration = NAN,
         energy_balance = NAN, recomputed_residual = NAN;
  std::string error_detail;
};

/// What one run left behind for the error measurement.
struct Track {
  std::vector<double> time, normal_force, mean_x;
  Eigen::VectorXd u_final;       ///< free dofs
  Eigen::VectorXd marked_final;  ///< displacement of the marked node
  double recomputed_residual = 0.0, max_penetration = 0.0;
};

const char* SolverName(StepSolver s) {
  switch (s) {
    case StepSolver::kFischerBurmeister:
      return "fb";
    case StepSolver::kMin:
      return "min";
    case StepSolver::kPenalizedFischerBurmeister:
      return "penalized-fb";
    case StepSolver::kIpopt:
      return "ipopt";
  }
  return "unknown";
}

/// Ipopt: the Ipopt step method; else the scene's step method with the NCP function.
void UseSolver(StepSolver s, contact::DynamicOptions* options) {
  switch (s) {
    case StepSolver::kIpopt:
      options->step_method = contact::StepMethod::kIpopt;
      return;
    case StepSolver::kMin:
      options->ncp.ncp_function = ncp::NcpFunction::kMin;
      return;
    case StepSolver::kPenalizedFischerBurmeister:
      options->ncp.ncp_function = ncp::NcpFunction::kPenalizedFischerBurmeister;
      return;
    case StepSolver::kFischerBurmeister:
      options->ncp.ncp_function = ncp::NcpFunction::kFischerBurmeister;
      return;
  }
}

std::string Status(const contact::DynamicSummary& s) {
  switch (s.status) {
    case DynamicStatus::kCompleted:
      return "converged";
    case DynamicStatus::kSolverFailure:
      return "failed";
    case DynamicStatus::kEnergyBlowUp:
      return "unstable";
    case DynamicStatus::kRefusedUnstable:
      return "refused";
    case DynamicStatus::kAccuracyNotReached:
      return "inaccurate";
    default:
      return "not-run";
  }
}

std::string Fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

/// A scene discretized once and reused by every run on it.
struct Built {
  contact::Scene scene;
  contact::SceneModel model;
  double dt_crit = 0.0;
  double m_max = 0.0;
  Eigen::VectorXd mass_x;  ///< row sums of M on the x free dofs (0 elsewhere)
  int marked_node = -1;
};

std::unique_ptr<Built> Build(const contact::Scene& base, double mesh_factor,
                             double end_time) {
  auto b = std::make_unique<Built>();
  b->scene = base;
  b->scene.output_directory.clear();
  if (end_time > 0) b->scene.dynamics.end_time = end_time;
  auto scale = [&](int c) {
    return c == 1 ? 1 : std::max(1, static_cast<int>(std::lround(c * mesh_factor)));
  };
  if (b->scene.rectangle)
    for (int& c : b->scene.rectangle->cells) c = scale(c);
  if (b->scene.box)
    for (int& c : b->scene.box->cells) c = scale(c);
  b->model = contact::BuildSceneModel(b->scene);
  const auto& M = b->model.model.M;
  b->dt_crit = contact::EstimateCriticalTimeStep(b->model.model.K, M).dt_crit;
  b->m_max = 0.0;
  for (int k = 0; k < M.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(M, k); it; ++it)
      b->m_max = std::max(b->m_max, std::abs(it.value()));
  const int dim = b->model.model.dim;
  const Eigen::VectorXd row_sums = M * Eigen::VectorXd::Ones(M.cols());
  b->mass_x = Eigen::VectorXd::Zero(M.rows());
  const auto& free = b->model.dofs.FreeDofs();
  for (size_t i = 0; i < free.size(); ++i)
    if (free[i] % dim == 0)
      b->mass_x(static_cast<Eigen::Index>(i)) = row_sums(static_cast<Eigen::Index>(i));
  if (b->scene.marked_point) {
    const Eigen::MatrixXd& nodes = b->model.body->mesh().nodes;
    double best = INFINITY;
    for (int i = 0; i < nodes.cols(); ++i) {
      const double d = (nodes.col(i) - *b->scene.marked_point).norm();
      if (d < best) best = d, b->marked_node = i;
    }
  }
  return b;
}

/// dt <= fraction * dt_crit with end_time / dt an integer (all runs end at the same
/// time).
double StepFor(const Built& b, double fraction) {
  const double span = b.scene.dynamics.end_time - b.scene.dynamics.start_time;
  const double n = std::ceil(span / (fraction * b.dt_crit) - 1e-9);
  return span / n;
}

struct RunSettings {
  StepSolver solver = StepSolver::kFischerBurmeister;
  double tolerance = 1e-10;
  double dt = 0.0;
  double friction = 0.0;
};

Row RunOne(const Built& b, const RunSettings& rs, Track* track) {
  Row row;
  row.solver = SolverName(rs.solver);
  row.tolerance = rs.tolerance;
  row.dt = rs.dt;
  row.dt_crit = b.dt_crit;
  row.dt_ratio = rs.dt / b.dt_crit;
  row.friction = rs.friction;
  row.dofs = static_cast<int>(b.model.model.K.rows());
  if (rs.solver == StepSolver::kIpopt && rs.friction > 0.0) {
    row.status = "skipped";
    row.message = "Ipopt solves frictionless steps only";
    return row;
  }
  const contact::DynamicModel& model = b.model.model;
  contact::DynamicOptions options = b.model.options;
  UseSolver(rs.solver, &options);
  options.dt = rs.dt;
  options.friction_coefficient = rs.friction;
  options.allow_unstable_time_step = rs.dt > b.dt_crit;
  options.progress = false;
  options.ncp.tolerance = rs.tolerance;

  *track = Track();
  const int dim = model.dim;
  const double dt = rs.dt, mass_total_x = b.mass_x.sum();
  Eigen::VectorXd u_km1, u_k, f(model.K.rows()), r;
  int seen = 0;
  options.on_step = [&](const contact::StepRecord& rec, const Eigen::VectorXd& u,
                        const contact::ContactSystem::Result&, double) {
    track->time.push_back(rec.time);
    track->normal_force.push_back(rec.normal_force_sum);
    track->mean_x.push_back(b.mass_x.dot(u) / mass_total_x);
    ++seen;
    if (seen >= 3) {
      model.load(rec.time - dt, &f);
      r = model.M * (u - 2 * u_k + u_km1) / (dt * dt) + model.K * u_k - f;
      for (const contact::ContactNode& c : model.contact_nodes) {
        double un = 0.0, rn = 0.0;
        for (int a = 0; a < dim; ++a)
          if (c.dofs[a] >= 0)
            un += c.normal(a) * u(c.dofs[a]), rn += c.normal(a) * r(c.dofs[a]);
        const double gap = c.gap - un, lambda_m = -rn * dt * dt / b.m_max;
        track->recomputed_residual =
            std::max(track->recomputed_residual, std::abs(std::min(gap, lambda_m)));
        track->max_penetration = std::max(track->max_penetration, -gap);
      }
    }
    u_km1 = std::move(u_k);
    u_k = u;
  };
  const contact::DynamicSummary s = contact::RunDynamics(model, options);
  row.status = Status(s);
  row.message = s.message;
  row.steps = s.steps;
  row.newton = s.newton_iterations;
  row.jacobians = s.jacobian_evaluations;
  row.residuals = s.residual_evaluations;
  row.seconds = s.seconds;
  row.max_penetration = s.max_penetration;
  row.energy_balance = s.energy_balance_error;
  row.recomputed_residual = track->recomputed_residual;
  track->u_final = u_k;
  if (b.marked_node >= 0 && u_k.size()) {
    const Eigen::VectorXd full = b.model.dofs.Expand(u_k);
    track->marked_final = full.segment(dim * b.marked_node, dim);
  }
  if (row.status == "converged") {
    const double limit =
        rs.solver == StepSolver::kIpopt ? 1e-6 : std::max(10 * rs.tolerance, 1e-9);
    if (row.recomputed_residual > limit) {
      row.status = "inaccurate";
      row.message = "recomputed normal complementarity residual " +
                    Fmt("%.3g", row.recomputed_residual) + " m > " + Fmt("%.3g", limit) +
                    " m";
    }
  }
  return row;
}

// ------------------------------------------------------------------- exact solutions
double Slope(const std::vector<double>& t, const std::vector<double>& y, double t0,
             double t1) {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] < t0 || t[i] > t1) continue;
    n += 1, st += t[i], sy += y[i], stt += t[i] * t[i], sty += t[i] * y[i];
  }
  if (n < 2) return NAN;
  return (n * sty - st * sy) / (n * stt - st * st);
}

/// Fills row.error (relative) from the exact solution of the validation scene.
void ExactError(const Built& b, ErrorKind kind, const Track& t, Row* row) {
  const contact::Scene& s = b.scene;
  const double E = s.material.youngs_modulus, rho = s.material.density;
  if (t.time.empty()) return;
  if (kind == ErrorKind::kBarImpact) {
    const double L = s.rectangle->size[0], h = s.rectangle->size[1],
                 v0 = s.initial_velocity(0);
    const double c = std::sqrt(E / rho), T = 2 * L / c, sigma = rho * c * v0;
    int on = 0, plateau = 0;
    double plateau_force = 0;
    for (size_t k = 0; k < t.time.size(); ++k) {
      if (t.normal_force[k] <= 0.01 * sigma * h) continue;
      ++on;
      if (t.time[k] > 0.1 * T && t.time[k] < 0.9 * T)
        plateau_force += t.normal_force[k], ++plateau;
    }
    const double duration = (on * row->dt - T) / T;
    const double stress = plateau ? (plateau_force / plateau / h - sigma) / sigma : NAN;
    const double rebound = (Slope(t.time, t.mean_x, 1.15 * T, 1e9) + v0) / v0;
    row->error = std::max({std::abs(duration), std::abs(stress), std::abs(rebound)});
    row->error_detail = "duration=" + Fmt("%+.3e", duration) +
                        ";stress=" + Fmt("%+.3e", stress) +
                        ";rebound=" + Fmt("%+.3e", rebound);
  } else if (kind == ErrorKind::kSlidingBlock) {
    const double g = -s.body_force(1) / rho, v0 = s.initial_velocity(0),
                 mu = row->friction;
    const double exact = v0 * v0 / (2 * mu * g);
    row->error = std::abs(t.mean_x.back() - exact) / exact;
    row->error_detail =
        "distance=" + Fmt("%.6e", t.mean_x.back()) + ";exact=" + Fmt("%.6e", exact);
  } else if (kind == ErrorKind::kIncline) {
    const double g = s.body_force.norm() / rho, sin_t = s.body_force(0) / (rho * g),
                 cos_t = -s.body_force(1) / (rho * g), mu = row->friction;
    const double exact = std::max(0.0, g * (sin_t - mu * cos_t));
    std::vector<double> tm, v;
    for (size_t k = 1; k < t.time.size(); ++k) {
      tm.push_back(0.5 * (t.time[k] + t.time[k - 1]));
      v.push_back((t.mean_x[k] - t.mean_x[k - 1]) / (t.time[k] - t.time[k - 1]));
    }
    const double a = Slope(tm, v, 0.1, 1e9);
    row->error = exact > 0 ? std::abs(a - exact) / exact : std::abs(a);
    row->error_detail = "acceleration=" + Fmt("%.6e", a) + ";exact=" + Fmt("%.6e", exact);
  }
}

double RelativeDifference(const Eigen::VectorXd& u, const Eigen::VectorXd& ref) {
  if (u.size() != ref.size() || ref.size() == 0) return NAN;
  return (u - ref).norm() / std::max(ref.norm(), 1e-300);
}

// ------------------------------------------------------------------- output
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s)
    q += ch == '"' ? std::string("\"\"") : std::string(1, ch == '\n' ? ' ' : ch);
  return q + "\"";
}
std::string Num(double x) {
  if (!std::isfinite(x)) return "";
  return Fmt("%.6e", x);
}
std::string JsonString(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\')
      q += '\\', q += ch;
    else if (ch == '\n')
      q += "\\n";
    else if (static_cast<unsigned char>(ch) < 0x20)
      q += ' ';
    else
      q += ch;
  }
  return q + "\"";
}
std::string JsonNum(double x) { return std::isfinite(x) ? Fmt("%.9g", x) : "null"; }

const char* kCsvHeader =
    "family,scene,sweep,setting,solver,status,steps,newton_iterations,jacobian_"
    "evaluations,"
    "residual_evaluations,seconds,error,reference_error,max_penetration,energy_balance_"
    "error,"
    "recomputed_residual,tolerance,dt,dt_crit,dt_ratio,friction,mesh_factor,dofs,error_"
    "detail,message";

std::string CsvRow(const Row& r) {
  std::ostringstream o;
  o << CsvField(r.family) << ',' << CsvField(r.scene) << ',' << r.sweep << ','
    << CsvField(r.setting) << ',' << r.solver << ',' << r.status << ',' << r.steps << ','
    << r.newton << ',' << r.jacobians << ',' << r.residuals << ',' << Num(r.seconds)
    << ',' << Num(r.error) << ',' << Num(r.reference_error) << ','
    << Num(r.max_penetration) << ',' << Num(r.energy_balance) << ','
    << Num(r.recomputed_residual) << ',' << Num(r.tolerance) << ',' << Num(r.dt) << ','
    << Num(r.dt_crit) << ',' << Num(r.dt_ratio) << ',' << Num(r.friction) << ','
    << Num(r.mesh_factor) << ',' << r.dofs << ',' << CsvField(r.error_detail) << ','
    << CsvField(r.message);
  return o.str();
}

std::string JsonRow(const Row& r) {
  std::ostringstream o;
  o << "{\"family\":" << JsonString(r.family) << ",\"scene\":" << JsonString(r.scene)
    << ",\"sweep\":" << JsonString(r.sweep) << ",\"setting\":" << JsonString(r.setting)
    << ",\"solver\":" << JsonString(r.solver) << ",\"status\":" << JsonString(r.status)
    << ",\"steps\":" << r.steps << ",\"newton_iterations\":" << r.newton
    << ",\"jacobian_evaluations\":" << r.jacobians
    << ",\"residual_evaluations\":" << r.residuals
    << ",\"seconds\":" << JsonNum(r.seconds) << ",\"error\":" << JsonNum(r.error)
    << ",\"reference_error\":" << JsonNum(r.reference_error)
    << ",\"max_penetration\":" << JsonNum(r.max_penetration)
    << ",\"energy_balance_error\":" << JsonNum(r.energy_balance)
    << ",\"recomputed_residual\":" << JsonNum(r.recomputed_residual)
    << ",\"tolerance\":" << JsonNum(r.tolerance) << ",\"dt\":" << JsonNum(r.dt)
    << ",\"dt_crit\":" << JsonNum(r.dt_crit) << ",\"dt_ratio\":" << JsonNum(r.dt_ratio)
    << ",\"friction\":" << JsonNum(r.friction)
    << ",\"mesh_factor\":" << JsonNum(r.mesh_factor) << ",\"dofs\":" << r.dofs
    << ",\"error_detail\":" << JsonString(r.error_detail)
    << ",\"message\":" << JsonString(r.message) << "}";
  return o.str();
}

// ------------------------------------------------------------------- the benchmark
struct Bench {
  std::string examples;
  bool quick = false;
  std::vector<Row> rows;
  ncp::OutputFile csv;  // one committed row per run: a stopped benchmark keeps whole rows
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  void Add(Row r) {
    // A run that did not reach the end has no error (its partial trajectory is not
    // compared).
    if (r.status != "converged" && r.status != "inaccurate")
      r.error = r.reference_error = NAN;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(
        stderr, "[%6.1fs] %-10s %-28s %-9s %-16s %-12s %-10s err %-9s %6.3fs %s\n",
        elapsed, r.family.c_str(), r.scene.c_str(), r.sweep.c_str(), r.setting.c_str(),
        r.solver.c_str(), r.status.c_str(), Num(r.error).c_str(), r.seconds,
        r.status == "converged" ? "" : r.message.substr(0, 90).c_str());
    csv.stream() << CsvRow(r) << '\n';
    csv.Commit();
    rows.push_back(std::move(r));
  }

  std::vector<StepSolver> Solvers(double friction) const {
    std::vector<StepSolver> s = {StepSolver::kFischerBurmeister, StepSolver::kMin,
                                 StepSolver::kPenalizedFischerBurmeister};
    if (friction == 0.0) s.push_back(StepSolver::kIpopt);
    return s;
  }

  void WorkPrecision(const SceneEntry& e) {
    const contact::Scene base = contact::LoadScene(examples + "/" + e.file);
    const double fc = base.friction_coefficient;
    const bool exact = e.kind != ErrorKind::kReference;
    auto fill = [&](Row* r, const char* sweep, const std::string& setting,
                    double mesh_factor) {
      r->family = e.family;
      r->scene = base.name;
      r->sweep = sweep;
      r->setting = setting;
      r->mesh_factor = mesh_factor;
    };

    // Tolerance sweep on the scene's mesh and dt.
    {
      auto b = Build(base, 1.0, e.end_time);
      const double dt = base.dynamics.dt;
      Track ref_track;
      RunOne(*b, {StepSolver::kFischerBurmeister, 1e-12, dt, fc}, &ref_track);
      const std::vector<double> ncp_tols =
          quick ? std::vector<double>{1e-4, 1e-10}
                : std::vector<double>{1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
      const std::vector<double> ipopt_tols =
          quick ? std::vector<double>{1e-6, 1e-14}
                : std::vector<double>{1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
      for (StepSolver solver : Solvers(fc))
        for (double tol : solver == StepSolver::kIpopt ? ipopt_tols : ncp_tols) {
          Track t;
          Row r = RunOne(*b, {solver, tol, dt, fc}, &t);
          fill(&r, "tolerance", "tol=" + Fmt("%.0e", tol), 1.0);
          if (r.status != "skipped") {
            r.reference_error = RelativeDifference(t.u_final, ref_track.u_final);
            if (exact)
              ExactError(*b, e.kind, t, &r);
            else
              r.error = r.reference_error;
          }
          Add(std::move(r));
        }
    }
    if (quick) return;

    // dt sweep on the scene's mesh; thesis scenes against dt_min / 2.
    {
      auto b = Build(base, 1.0, e.end_time);
      Track ref_track;
      if (!exact) {
        const double dt_ref = StepFor(*b, 0.5 * e.dt_fractions.back());
        RunOne(*b, {StepSolver::kFischerBurmeister, 1e-12, dt_ref, fc}, &ref_track);
      }
      for (double fraction : e.dt_fractions) {
        const double dt = StepFor(*b, fraction);
        for (StepSolver solver : Solvers(fc)) {
          Track t;
          Row r = RunOne(
              *b, {solver, solver == StepSolver::kIpopt ? 1e-14 : 1e-10, dt, fc}, &t);
          fill(&r, "dt", "dt=" + Fmt("%.3g", fraction) + "dt_crit", 1.0);
          if (r.status != "skipped") {
            if (exact)
              ExactError(*b, e.kind, t, &r);
            else
              r.error = RelativeDifference(t.u_final, ref_track.u_final);
          }
          Add(std::move(r));
        }
      }
    }

    // Mesh sweep at a fixed dt / dt_crit; thesis scenes against the finest mesh (marked
    // point).
    {
      Eigen::VectorXd ref_marked;
      if (!exact) {
        auto b = Build(base, e.mesh_factors.back(), e.end_time);
        Track t;
        const Row r = RunOne(
            *b, {StepSolver::kFischerBurmeister, 1e-10, StepFor(*b, e.mesh_courant), fc},
            &t);
        ref_marked = t.marked_final;
      }
      for (size_t i = 0; i < e.mesh_factors.size(); ++i) {
        const double factor = e.mesh_factors[i];
        if (!exact && i + 1 == e.mesh_factors.size()) break;  // that one is the reference
        auto b = Build(base, factor, e.end_time);
        for (StepSolver solver : Solvers(fc)) {
          Track t;
          Row r = RunOne(*b,
                         {solver, solver == StepSolver::kIpopt ? 1e-14 : 1e-10,
                          StepFor(*b, e.mesh_courant), fc},
                         &t);
          fill(&r, "mesh", "cells x" + Fmt("%g", factor), factor);
          if (r.status != "skipped") {
            if (exact)
              ExactError(*b, e.kind, t, &r);
            else
              r.error = RelativeDifference(t.marked_final, ref_marked);
          }
          Add(std::move(r));
        }
      }
    }
  }

  void Stability(const std::string& file, double end_time) {
    const contact::Scene base = contact::LoadScene(examples + "/" + file);
    auto b = Build(base, 1.0, end_time);
    const std::vector<double> ratios =
        quick ? std::vector<double>{0.5, 1.5}
              : std::vector<double>{0.25, 0.5, 0.75, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0};
    const std::vector<double> frictions =
        quick ? std::vector<double>{0.0, 0.5}
              : std::vector<double>{0.0, 0.1, 0.5, 1.0, 5.0};
    for (double fc : frictions)
      for (double ratio : ratios)
        for (StepSolver solver : Solvers(0.0)) {
          Track t;
          // Exactly ratio * dt_crit (the run's end time may overshoot by < dt).
          Row r = RunOne(*b,
                         {solver, solver == StepSolver::kIpopt ? 1e-14 : 1e-10,
                          ratio * b->dt_crit, fc},
                         &t);
          r.family = "stability";
          r.scene = base.name;
          r.sweep = "stability";
          r.setting = "dt=" + Fmt("%.3g", ratio) + "dt_crit,fc=" + Fmt("%g", fc);
          Add(std::move(r));
        }
  }
};

}  // namespace

int main(int argc, char** argv) {
  Bench bench;
  bench.examples = CONTACT_EXAMPLES_DIR;
  std::string csv_path = "contact_bench.csv", only;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick")
      bench.quick = true;
    else if (a == "--json")
      json = true;
    else if (a == "--csv" && i + 1 < argc)
      csv_path = argv[++i];
    else if (a == "--examples" && i + 1 < argc)
      bench.examples = argv[++i];
    else if (a == "--only" && i + 1 < argc)
      only = argv[++i];
    else {
      std::fprintf(stderr,
                   "usage: %s [--quick] [--csv FILE] [--json] [--examples DIR] "
                   "[--only workprecision|stability]\n",
                   argv[0]);
      return 2;
    }
  }
  std::signal(SIGXFSZ, SIG_IGN);  // a file-size limit: EFBIG, reported, not a kill
  try {
    bench.csv = ncp::OutputFile::Open(csv_path);
    bench.csv.stream() << kCsvHeader << '\n';
    bench.csv.Commit();
  } catch (const ncp::OutputError& e) {
    std::fprintf(stderr, "contact-bench: %s\n", e.what());
    return 3;
  }

  // dt fractions of the scene's dt_crit; the bar's Courant 1 is the exact-wave step.
  std::vector<SceneEntry> scenes = {
      {"validation",
       "validation/bar_impact.toml",
       ErrorKind::kBarImpact,
       {0.25, 0.5, 1, 2},
       {1.0, 0.5, 0.25, 0.125},
       0.5,
       -1},
      {"validation",
       "validation/sliding_block.toml",
       ErrorKind::kSlidingBlock,
       {0.5, 1, 2},
       {0.9, 0.5, 0.25},
       0.5,
       0.4},
      {"validation",
       "validation/incline.toml",
       ErrorKind::kIncline,
       {0.5, 1, 2},
       {0.9, 0.5, 0.25},
       0.5,
       0.25},
      {"thesis",
       "thesis/frictionless_3d.toml",
       ErrorKind::kReference,
       {0.5, 1, 2},
       {0.9, 0.5, 0.25},
       0.5,
       -1},
      {"thesis",
       "thesis/friction_3d.toml",
       ErrorKind::kReference,
       {1, 2, 4},
       {0.9, 0.5, 0.25},
       0.5,
       -1},
      {"thesis",
       "thesis/friction_2d_flat.toml",
       ErrorKind::kReference,
       {1, 2, 4},
       {0.9, 0.5, 0.25},
       0.5,
       -1},
      {"thesis",
       "thesis/friction_2d_curved.toml",
       ErrorKind::kReference,
       {1, 2, 4},
       {0.9, 0.5, 0.25},
       0.5,
       -1},
  };
  try {
    if (only.empty() || only == "workprecision") {
      if (bench.quick) {
        SceneEntry bar = scenes[0];
        bench.WorkPrecision(bar);
        SceneEntry curved = scenes[6];
        curved.end_time = 0.05;
        bench.WorkPrecision(curved);
      } else {
        for (const SceneEntry& e : scenes) bench.WorkPrecision(e);
      }
    }
    if (only.empty() || only == "stability") {
      if (bench.quick) {
        bench.Stability("thesis/friction_2d_flat.toml", 0.05);
      } else {
        bench.Stability("thesis/friction_2d_flat.toml", -1);
        bench.Stability("thesis/friction_2d_curved.toml", -1);
      }
    }
    bench.csv.Close();
  } catch (const ncp::OutputError& ex) {
    std::fprintf(stderr, "contact-bench: output failed: %s\n", ex.what());
    return 3;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "contact-bench: %s\n", ex.what());
    return 1;
  }
  if (json) {
    std::printf("[\n");
    for (size_t i = 0; i < bench.rows.size(); ++i)
      std::printf("%s%s\n", JsonRow(bench.rows[i]).c_str(),
                  i + 1 < bench.rows.size() ? "," : "");
    std::printf("]\n");
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      std::fprintf(stderr, "contact-bench: writing the JSON to stdout failed\n");
      return 3;
    }
  }
  std::fprintf(stderr, "contact-bench: %zu rows written to %s\n", bench.rows.size(),
               csv_path.c_str());
  return 0;
}
