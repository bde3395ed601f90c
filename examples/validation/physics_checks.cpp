#include "physics_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "contact/scene.hpp"

namespace contact::validation {
namespace {

constexpr double kG = 9.81;  // [m/s^2]
constexpr double kPi = 3.14159265358979323846;

std::string Num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

// A scene written in a unit system: every SI value is divided by its unit,
// l^a t^b m^c for a quantity of dimension L^a T^b M^c.
class SceneWriter {
 public:
  explicit SceneWriter(const Units& u) : u_(u) {}
  std::string Length(double x) const { return Num(x / u_.length); }
  std::string Time(double x) const { return Num(x / u_.time); }
  std::string Velocity(double x) const { return Num(x * u_.time / u_.length); }
  std::string Stress(double x) const {
    return Num(x * u_.length * u_.time * u_.time / u_.mass);
  }
  std::string Density(double x) const {
    return Num(x * std::pow(u_.length, 3) / u_.mass);
  }
  std::string BodyForce(double x) const {
    return Num(x * u_.length * u_.length * u_.time * u_.time / u_.mass);
  }
  std::string Lengths(const std::vector<double>& v) const {
    return List(v, &SceneWriter::Length);
  }
  std::string Velocities(const std::vector<double>& v) const {
    return List(v, &SceneWriter::Velocity);
  }
  std::string BodyForces(const std::vector<double>& v) const {
    return List(v, &SceneWriter::BodyForce);
  }

 private:
  std::string List(const std::vector<double>& v,
                   std::string (SceneWriter::*f)(double) const) const {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + (this->*f)(v[i]);
    return s + "]";
  }
  Units u_;
};

// A block W x H (x D in 3D) resting on (or `lift` above) the floor y >= 0 of a plane
// obstacle, or a bar along x against the wall x <= L: the geometry and material sections.
struct Body {
  std::vector<double> origin, size;
  std::vector<int> cells;
  std::string contact_side = "ymin";
  double poisson = 0.3;
};

std::string BodySections(const Case& c, const Body& b, const SceneWriter& w) {
  std::ostringstream s;
  s << "[geometry]\ntype = \"" << (c.dim == 2 ? "rectangle" : "box")
    << "\"\norigin = " << w.Lengths(b.origin) << "\nsize = " << w.Lengths(b.size)
    << "\ncells = [";
  for (size_t i = 0; i < b.cells.size(); ++i) s << (i ? ", " : "") << b.cells[i];
  s << "]\nelement = \"" << (c.dim == 2 ? "quad4" : "hex8") << "\"\ncontact = [\""
    << b.contact_side << "\"]\n[material]\nyoung_modulus = " << w.Stress(c.young_modulus)
    << "\npoisson_ratio = " << Num(b.poisson) << "\ndensity = " << w.Density(c.density)
    << "\nmass = \"" << (c.lumped ? "lumped" : "consistent") << "\"\n";
  if (c.dim == 2)
    s << "plane = \"" << (b.poisson == 0.0 ? "stress" : "strain")
      << "\"\nthickness = " << w.Length(1.0) << "\n";
  return s.str();
}

std::string SolverSection(const Case& c) {
  std::string s = "[solver]\n";
  // c.solver "ipopt" is the Ipopt step; the others name the NCP function of the Newton
  // steps.
  if (c.solver == "ipopt")
    s += "step = \"ipopt\"\n";
  else if (!c.step.empty())
    s += "step = \"" + c.step + "\"\n";
  if (!c.solver.empty() && c.solver != "ipopt")
    s += "ncp_function = \"" + c.solver + "\"\n";
  if (!c.friction_formulation.empty())
    s += "friction = \"" + c.friction_formulation + "\"\n";
  if (c.tolerance > 0.0) s += "tolerance = " + Num(c.tolerance) + "\n";
  return s;
}

// Writes the scene into the temporary directory and loads it (as a user's file would be).
Scene Load(const std::string& name, const Case& c, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "contact_physics_checks";
  fs::create_directories(dir);
  std::string file = name + "_" + c.Label() + ".toml";
  for (char& ch : file)
    if (ch == ' ' || ch == '/' || ch == '=') ch = '_';
  const fs::path p = dir / file;
  std::ofstream(p) << "name = \"" << name << "\"\n" << text;
  return LoadScene(p.string());
}

// The time step: dt_fraction of dt_crit of the body (which its position does not change);
// `text` is the body and obstacle sections.
double TimeStep(const std::string& name, const Case& c, const std::string& text) {
  const Scene s = Load(name + "_dtcrit", c, text + "[time]\ndt = 1\nend_time = 1\n");
  const SceneModel m = BuildSceneModel(s);
  return c.dt_fraction * EstimateCriticalTimeStep(m.model.K, m.model.M).dt_crit *
         c.units.time;
}

// Runs a scene and records, per step, the time, the total normal contact force and the
// mass-weighted mean displacement (SI), and the largest tangential displacement of a
// contact node at the end.
struct Run {
  Outcome out;
  std::vector<double> normal_force, kinetic;
  double mass = 0.0;                // [kg] (per metre of thickness in 2D)
  double contact_tangential = 0.0;  // max_c |u_t| at the end [m]
};

Run Execute(const Scene& scene, const Units& u) {
  SceneModel built = BuildSceneModel(scene);
  const DynamicModel& model = built.model;
  const int dim = model.dim;
  // Mean displacement weights: the mass of each free dof (row sums of M), per component.
  const Eigen::VectorXd m = model.M * Eigen::VectorXd::Ones(model.M.rows());
  const Eigen::VectorXd full_m = built.dofs.Expand(m);
  Run run;
  double component_mass = 0.0;
  for (Eigen::Index i = 0; i < full_m.size(); i += dim) component_mass += full_m(i);
  run.mass = component_mass * u.mass;
  const double force_unit = u.mass * u.length / (u.time * u.time);
  built.options.on_step = [&](const StepRecord& r, const Eigen::VectorXd& x,
                              const ContactSystem::Result&, double) {
    run.out.time.push_back(r.time * u.time);
    run.normal_force.push_back(r.normal_force_sum * force_unit);
    run.kinetic.push_back(r.kinetic * force_unit * u.length);
    const Eigen::VectorXd full = built.dofs.Expand(x);
    std::vector<double> mean(static_cast<size_t>(dim), 0.0);
    for (Eigen::Index i = 0; i < full.size(); ++i)
      mean[static_cast<size_t>(i % dim)] += full_m(i) * full(i);
    for (double& v : mean) v *= u.length / component_mass;
    run.out.mean_u.push_back(mean);
    double slip = 0.0;
    for (const ContactNode& node : model.contact_nodes)
      for (int b = 0; b < dim; ++b)
        if (node.dofs[b] >= 0) slip += node.tangent1(b) * x(node.dofs[b]);
    run.out.contact_slip.push_back(slip * u.length /
                                   static_cast<double>(model.contact_nodes.size()));
  };
  const DynamicSummary s = RunDynamics(model, built.options);
  for (const ContactNode& node : model.contact_nodes)
    for (int a = 1; a < dim; ++a) {
      const Eigen::Vector3d& t = a == 1 ? node.tangent1 : node.tangent2;
      double ut = 0.0;
      for (int b = 0; b < dim; ++b)
        if (node.dofs[b] >= 0) ut += t(b) * s.u(node.dofs[b]);
      run.contact_tangential = std::max(run.contact_tangential, std::abs(ut) * u.length);
    }
  run.out.status = s.status;
  run.out.message = s.message;
  run.out.steps = s.steps;
  run.out.seconds = s.seconds;
  run.out.newton_per_step =
      s.steps ? static_cast<double>(s.newton_iterations) / s.steps : 0.0;
  return run;
}

// Least-squares slope of y(t) for t in [t0, t1].
double Slope(const std::vector<double>& t, const std::vector<double>& y, double t0,
             double t1) {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] < t0 || t[i] > t1) continue;
    n += 1, st += t[i], sy += y[i], stt += t[i] * t[i], sty += t[i] * y[i];
  }
  return n >= 2 ? (n * sty - st * sy) / (n * stt - st * st) : NAN;
}

std::string Fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, f, a, b, c, d);
  return buffer;
}

// A block 0.2 x 0.05 (x 0.1) m, 4 x 2 (x 2) cells.
Body Block(const Case& c, double lift) {
  Body b;
  b.origin =
      c.dim == 2 ? std::vector<double>{0.0, lift} : std::vector<double>{0.0, lift, 0.0};
  b.size =
      c.dim == 2 ? std::vector<double>{0.2, 0.05} : std::vector<double>{0.2, 0.05, 0.1};
  b.cells = c.dim == 2 ? std::vector<int>{4, 2} : std::vector<int>{4, 2, 2};
  return b;
}

std::string Floor(const Case& c, const SceneWriter&) {
  return std::string("[obstacle]\ntype = \"plane\"\nnormal = ") +
         (c.dim == 2 ? "[0.0, 1.0]" : "[0.0, 1.0, 0.0]") + "\noffset = 0.0\n";
}

std::vector<double> Vec(int dim, double x, double y) {
  return dim == 2 ? std::vector<double>{x, y} : std::vector<double>{x, y, 0.0};
}

}  // namespace

std::string Case::Label() const {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%dD E=%.0e dt=%.2fcrit ", dim, young_modulus,
                dt_fraction);
  return buffer + std::string(lumped ? "lumped" : "consistent") +
         (step.empty() ? "" : " " + step) + (solver.empty() ? "" : " " + solver) +
         (friction_formulation.empty() ? "" : " " + friction_formulation) + " " +
         units.name;
}

Outcome FreeFall(const Case& c) {
  const SceneWriter w(c.units);
  const double dt = TimeStep("fall", c, BodySections(c, Block(c, 0.0), w) + Floor(c, w));
  // Drop height: the fall takes 300.37 steps (not a whole number of steps).
  const double t_fall = 300.37 * dt, h = 0.5 * kG * t_fall * t_fall;
  const double rho_g = c.density * kG;
  const Scene scene =
      Load("fall", c,
           BodySections(c, Block(c, h), w) + "[loads]\nbody_force = " +
               w.BodyForces(Vec(c.dim, 0.0, -rho_g)) + "\n" + Floor(c, w) +
               "[time]\ndt = " + w.Time(dt) + "\nend_time = " + w.Time(t_fall + 30 * dt) +
               "\ninitial_state = \"velocity\"\ninitial_velocity = " +
               w.Velocities(Vec(c.dim, 0.0, 0.0)) + "\n" + SolverSection(c));
  Run run = Execute(scene, c.units);
  Outcome& out = run.out;
  out.check = "free fall";
  const double weight = run.mass * kG, limit = 1e-6 * weight;
  double in_flight = 0.0, first = NAN;
  for (size_t k = 0; k < out.time.size(); ++k) {
    if (out.time[k] < t_fall - 1e-9 * dt)
      in_flight = std::max(in_flight, std::abs(run.normal_force[k]));
    if (std::isnan(first) && run.normal_force[k] > limit) first = out.time[k];
  }
  out.measured = first;
  out.expected = t_fall;
  // The step that first carries a force ends at t_{k+1} >= sqrt(2h/g) > t_k.
  out.passed = out.status == DynamicStatus::kCompleted && in_flight <= limit &&
               first >= t_fall && first - t_fall <= dt * (1 + 1e-9);
  out.detail =
      Fmt("largest force in flight %.2e N (limit 1e-6 m g = %.2e N), first contact at "
          "%.6e s, "
          "sqrt(2h/g) = %.6e s",
          in_flight, limit, first, t_fall);
  return out;
}

Outcome Incline(const Case& c, double degrees) {
  const SceneWriter w(c.units);
  const double theta = std::atan(c.friction) + degrees * kPi / 180.0;
  const double dt =
      TimeStep("incline", c, BodySections(c, Block(c, 0.0), w) + Floor(c, w));
  // Gravity ramped over 200 crossings of the block's height by the dilatational wave, so
  // that the normal force follows the load within a fraction of the 6% margin that 1
  // degree leaves (the ringing of the block otherwise makes it creep), then at least 1000
  // steps and 200 crossings of observation. Sliding, the block is thrown down the slope
  // at v0 = 100 g t_wave, well above the velocities of its ringing, so that every contact
  // node slides all along (at low speed the ringing makes nodes stick now and then and
  // lowers the mean friction force: an elastic effect that the rigid-body answer does not
  // contain).
  const double wave = 0.05 / std::sqrt(c.young_modulus / c.density);
  const bool slides = degrees > 0.0;
  const double ramp =
      slides ? std::max(20 * wave, 50 * dt) : std::max(200 * wave, 100 * dt);
  const double end = ramp + std::max(1000 * dt, 200 * wave),
               v0 = slides ? 100 * kG * wave : 0.0;
  const double rho_g = c.density * kG;
  const Scene scene = Load(
      "incline", c,
      BodySections(c, Block(c, 0.0), w) + "[loads]\nbody_force = " +
          w.BodyForces(Vec(c.dim, rho_g * std::sin(theta), -rho_g * std::cos(theta))) +
          "\nhistory = \"ramp\"\nramp_time = " + w.Time(ramp) + "\n" + Floor(c, w) +
          "[friction]\ncoefficient = " + Num(c.friction) +
          "\n[time]\ndt = " + w.Time(dt) + "\nend_time = " + w.Time(end) +
          "\ninitial_state = \"velocity\"\ninitial_velocity = " +
          w.Velocities(Vec(c.dim, v0, 0.0)) + "\n" + SolverSection(c));
  Run run = Execute(scene, c.units);
  Outcome& out = run.out;
  out.check = slides ? "incline, slides" : "incline, sticks";
  if (slides) {
    // Mean velocity down the slope by differences; its slope after ramp + 5 wave
    // crossings.
    std::vector<double> t, v;
    for (size_t k = 1; k < out.time.size(); ++k) {
      t.push_back(0.5 * (out.time[k] + out.time[k - 1]));
      v.push_back((out.mean_u[k][0] - out.mean_u[k - 1][0]) /
                  (out.time[k] - out.time[k - 1]));
    }
    out.measured = Slope(t, v, ramp + 5 * wave, end);
    out.expected = kG * (std::sin(theta) - c.friction * std::cos(theta));
    out.passed = out.status == DynamicStatus::kCompleted &&
                 std::abs(out.measured - out.expected) <= 0.01 * out.expected;
    out.detail = Fmt(
        "theta = %.2f deg: a = %.6e m/s^2, g (sin - mu cos) = %.6e m/s^2 (%.2e relative)",
        theta * 180 / kPi, out.measured, out.expected,
        (out.measured - out.expected) / out.expected);
  } else {
    // Slip after the load is on: the mean tangential motion of the contact nodes from the
    // end of the ramp (+ 5 wave crossings) to the end (before it, the contact edge takes
    // up the block's elastic Poisson expansion and shear, which is not slip of the
    // block).
    double before = NAN;
    for (size_t k = 0; k < out.time.size() && std::isnan(before); ++k)
      if (out.time[k] >= ramp + 5 * wave) before = out.contact_slip[k];
    //
    // The limit is a tenth of the block's own elastic shear deformation under the load,
    // delta = rho g sin(theta) H^2 / (2 G) (a layer of height H sheared by the weight
    // above each depth), not an absolute length: an undamped elastic block at 94% of the
    // friction limit lets contact nodes slip at instants of its ringing, a motion
    // proportional to delta (measured: ~7e-3 delta for E = 1e6 to 2e11 Pa, converged in
    // dt, the same at tolerance 1e-14), which the rigid-body closed form does not
    // contain. Sliding 1 degree steeper would move the block ~1e4 to 6e4 times this limit
    // over the same window (estimate: 0.5 g (sin - mu cos) t^2 over the observation
    // window).
    const Body block = Block(c, 0.0);
    const double shear_modulus = c.young_modulus / (2.0 * (1.0 + block.poisson)),
                 height = block.size[1];
    const double delta =
        rho_g * std::sin(theta) * height * height / (2.0 * shear_modulus);
    const double limit = 0.1 * delta;
    out.measured =
        out.contact_slip.empty() ? NAN : std::abs(out.contact_slip.back() - before);
    out.expected = 0.0;
    out.passed = out.status == DynamicStatus::kCompleted && out.measured <= limit;
    out.detail =
        Fmt("theta = %.2f deg: slip after the ramp %.2e m = %.2e of the elastic shear "
            "deformation "
            "rho g sin H^2 / 2G = %.2e m (limit 0.1)",
            theta * 180 / kPi, out.measured, out.measured / delta, delta);
  }
  return out;
}

Outcome Sliding(const Case& c) {
  const SceneWriter w(c.units);
  const double dt =
      TimeStep("sliding", c, BodySections(c, Block(c, 0.0), w) + Floor(c, w));
  // Thrown at v0 so that it slides for at least 600 steps and 200 crossings of the
  // block's height by the dilatational wave (the ringing from the suddenly applied weight
  // averages out); observed 15% longer.
  const double wave = 0.05 / std::sqrt(c.young_modulus / c.density);
  const double stop = std::max(600 * dt, 200 * wave), v0 = c.friction * kG * stop;
  const double rho_g = c.density * kG;
  const Scene scene =
      Load("sliding", c,
           BodySections(c, Block(c, 0.0), w) +
               "[loads]\nbody_force = " + w.BodyForces(Vec(c.dim, 0.0, -rho_g)) + "\n" +
               Floor(c, w) + "[friction]\ncoefficient = " + Num(c.friction) +
               "\n[time]\ndt = " + w.Time(dt) + "\nend_time = " + w.Time(1.15 * stop) +
               "\ninitial_state = \"velocity\"\ninitial_velocity = " +
               w.Velocities(Vec(c.dim, v0, 0.0)) + "\n" + SolverSection(c));
  Run run = Execute(scene, c.units);
  Outcome& out = run.out;
  out.check = "sliding block";
  // Mean velocity along x by differences: a line of slope -mu g while sliding (fitted
  // between 0.2 v0 and 0.8 v0); its root is the stopping time.
  std::vector<double> t, v;
  for (size_t k = 1; k < out.time.size(); ++k) {
    const double vk =
        (out.mean_u[k][0] - out.mean_u[k - 1][0]) / (out.time[k] - out.time[k - 1]);
    if (vk > 0.2 * v0 && vk < 0.8 * v0)
      t.push_back(0.5 * (out.time[k] + out.time[k - 1])), v.push_back(vk);
  }
  const double slope = Slope(t, v, 0.0, 1e300);
  double mean_t = 0, mean_v = 0;
  for (size_t k = 0; k < t.size(); ++k)
    mean_t += t[k] / t.size(), mean_v += v[k] / t.size();
  out.measured = mean_t + mean_v / -slope;
  out.expected = stop;
  out.passed = out.status == DynamicStatus::kCompleted &&
               std::abs(out.measured - stop) <= 0.01 * stop;
  out.detail = Fmt("stops at %.6e s, v0 / (mu g) = %.6e s (%.2e relative)", out.measured,
                   stop, (out.measured - stop) / stop);
  return out;
}

Outcome BarImpact(const Case& c) {
  const SceneWriter w(c.units);
  // Bar L = 1 m x 0.02 m (x 0.02 m), nu = 0, 100 cells along x, thrown at v0 against the
  // wall x <= L at gap 0: 1D waves, contact for 2L/c.
  Body b;
  b.poisson = 0.0;
  b.contact_side = "xmax";
  b.origin =
      c.dim == 2 ? std::vector<double>{0.0, 0.0} : std::vector<double>{0.0, 0.0, 0.0};
  b.size =
      c.dim == 2 ? std::vector<double>{1.0, 0.02} : std::vector<double>{1.0, 0.02, 0.02};
  b.cells = c.dim == 2 ? std::vector<int>{100, 1} : std::vector<int>{100, 1, 1};
  const std::string wall = std::string("[obstacle]\ntype = \"plane\"\nnormal = ") +
                           (c.dim == 2 ? "[-1.0, 0.0]" : "[-1.0, 0.0, 0.0]") +
                           "\noffset = " + w.Length(-1.0) + "\n";
  const double dt = TimeStep("bar", c, BodySections(c, b, w) + wall);
  const double wave_speed = std::sqrt(c.young_modulus / c.density), T = 2.0 / wave_speed;
  const double v0 = 1e-6 * wave_speed;  // strain 1e-6
  const Scene scene =
      Load("bar", c,
           BodySections(c, b, w) + wall + "[time]\ndt = " + w.Time(dt) + "\nend_time = " +
               w.Time(1.3 * T) + "\ninitial_state = \"velocity\"\ninitial_velocity = " +
               w.Velocities(Vec(c.dim, v0, 0.0)) + "\n" + SolverSection(c));
  Run run = Execute(scene, c.units);
  Outcome& out = run.out;
  out.check = "bar impact";
  // Contact while the force exceeds 1% of rho c v0 A.
  const double area = c.dim == 2 ? 0.02 : 0.02 * 0.02,
               force = c.density * wave_speed * v0 * area;
  int on = 0;
  for (double f : run.normal_force) on += f > 0.01 * force;
  out.measured = on * dt;
  out.expected = T;
  out.passed =
      out.status == DynamicStatus::kCompleted && std::abs(out.measured - T) <= 0.01 * T;
  out.detail = Fmt("contact for %.6e s, 2L/c = %.6e s (%.2e relative, dt = %.2e s)",
                   out.measured, T, (out.measured - T) / T, dt);
  return out;
}

double TrajectoryDifference(const Outcome& a, const Outcome& b, double fraction) {
  double diff = 0.0, scale = 0.0;
  if (a.mean_u.size() != b.mean_u.size()) return INFINITY;
  const auto n =
      static_cast<size_t>(std::ceil(fraction * static_cast<double>(a.mean_u.size())));
  for (size_t k = 0; k < n; ++k)
    for (size_t i = 0; i < a.mean_u[k].size(); ++i) {
      diff = std::max(diff, std::abs(a.mean_u[k][i] - b.mean_u[k][i]));
      scale = std::max(scale, std::abs(b.mean_u[k][i]));
    }
  return scale > 0.0 ? diff / scale : diff;
}

}  // namespace contact::validation
