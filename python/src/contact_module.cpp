// The `contact._contact` extension: load a scene file, run its time loop and return the
// results as NumPy arrays instead of CSV files. Units as in contact/include/contact:
// forces [N], stresses [Pa], gaps and displacements [m], energies [J], times [s].
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "contact/scene.hpp"
#include "enum_binding.hpp"

namespace py = pybind11;

namespace {

/// A value set from Python on a Scene, checked at once against the range the scene file
/// accepts for the same key (contact/src/scene/scene_file.cpp), so that dt = -1 or NaN is
/// refused where it is written, not at run().
double Checked(const char* name, const char* key, double v, double min, double max,
               bool min_open, const char* unit) {
  const bool ok = std::isfinite(v) && (min_open ? v > min : v >= min) && v <= max;
  if (!ok) {
    std::ostringstream text;
    text << "contact.Scene." << name << " = " << v << " " << unit << " is outside the accepted range "
         << (min_open ? "(" : "[") << min << ", " << max << "] " << unit << " (the scene key " << key << ")";
    throw contact::SceneError(text.str());
  }
  return v;
}

using contact::DynamicSummary;
using contact::StepRecord;

/// Numeric columns of a struct from a table of (name, pointer to member), one line per
/// field: integers become int64 arrays, the rest float64. A field added to the C++ struct
/// needs one line here.
template <typename Struct>
class ColumnTable {
 public:
  template <typename T>
  ColumnTable& operator()(const char* name, T Struct::*member) {
    static_assert(std::is_arithmetic_v<T>, "numeric fields only");
    columns_.push_back({name, std::is_integral_v<T>,
                        [member](const Struct& s) { return double(s.*member); }});
    return *this;
  }
  /// {name: array over rows}.
  py::dict Arrays(const std::vector<Struct>& rows) const {
    py::dict d;
    for (const Column& c : columns_) {
      std::vector<double> v(rows.size());
      std::transform(rows.begin(), rows.end(), v.begin(), c.get);
      py::array_t<double> a(static_cast<py::ssize_t>(v.size()), v.data());
      d[py::str(c.name)] = c.integer ? a.attr("astype")("int64") : py::object(a);
    }
    return d;
  }
  /// {name: scalar} of one struct.
  py::dict Scalars(const Struct& s) const {
    py::dict d;
    for (const Column& c : columns_)
      d[py::str(c.name)] = c.integer
                               ? py::object(py::int_(static_cast<long long>(c.get(s))))
                               : py::object(py::float_(c.get(s)));
    return d;
  }

 private:
  struct Column {
    std::string name;
    bool integer;
    std::function<double(const Struct&)> get;
  };
  std::vector<Column> columns_;
};

const ColumnTable<StepRecord>& StepColumns() {
  // clang-format off
  static const ColumnTable<StepRecord> table = ColumnTable<StepRecord>()
      ("step", &StepRecord::step)
      ("time", &StepRecord::time)
      ("newton_iterations", &StepRecord::newton_iterations)
      ("jacobian_evaluations", &StepRecord::jacobian_evaluations)
      ("residual_evaluations", &StepRecord::residual_evaluations)
      ("seconds", &StepRecord::seconds)
      ("solve_seconds", &StepRecord::solve_seconds)
      ("kinetic_energy", &StepRecord::kinetic)
      ("strain_energy", &StepRecord::strain)
      ("external_work", &StepRecord::external_work)
      ("normal_contact_work", &StepRecord::normal_contact_work)
      ("friction_dissipation", &StepRecord::friction_dissipation)
      ("energy_balance_error", &StepRecord::energy_balance_error)
      ("normal_force_sum", &StepRecord::normal_force_sum)
      ("friction_force_sum", &StepRecord::tangent_force_sum)
      ("max_penetration", &StepRecord::max_penetration)
      ("active_nodes", &StepRecord::active_nodes)
      ("equilibrium_residual", &StepRecord::equilibrium_residual)
      ("complementarity_residual", &StepRecord::complementarity_residual)
      ("friction_residual", &StepRecord::friction_residual)
      ("force_accuracy", &StepRecord::force_accuracy)
      ("displacement_accuracy", &StepRecord::displacement_accuracy)
      ("accurate", &StepRecord::accurate)
      ("ipopt_relative_difference", &StepRecord::ipopt_relative_difference);
  // clang-format on
  return table;
}

const ColumnTable<DynamicSummary>& SummaryColumns() {
  // clang-format off
  static const ColumnTable<DynamicSummary> table = ColumnTable<DynamicSummary>()
      ("steps", &DynamicSummary::steps)
      ("newton_iterations", &DynamicSummary::newton_iterations)
      ("jacobian_evaluations", &DynamicSummary::jacobian_evaluations)
      ("residual_evaluations", &DynamicSummary::residual_evaluations)
      ("friction_restarts", &DynamicSummary::friction_restarts)
      ("seconds", &DynamicSummary::seconds)
      ("max_penetration", &DynamicSummary::max_penetration)
      ("max_equilibrium_residual", &DynamicSummary::max_equilibrium_residual)
      ("max_complementarity_residual", &DynamicSummary::max_complementarity_residual)
      ("max_friction_residual", &DynamicSummary::max_friction_residual)
      ("inaccurate_steps", &DynamicSummary::inaccurate_steps)
      ("energy_balance_error", &DynamicSummary::energy_balance_error)
      ("critical_time_step", &DynamicSummary::critical_time_step)
      ("max_ipopt_relative_difference", &DynamicSummary::max_ipopt_relative_difference);
  // clang-format on
  return table;
}

/// The state at one output time: displacement of every node and per contact node forces,
/// stresses and gaps.
struct Snapshot {
  double time = 0.0;
  Eigen::MatrixXd displacement;   ///< NumNodes x dim [m]
  Eigen::VectorXd normal_force;   ///< lambda_c [N]
  Eigen::MatrixXd tangent_force;  ///< N_c x (dim - 1) [N]
  Eigen::VectorXd gap;            ///< gap_c [m] (< 0: penetration)
};

/// Stacks snapshots into (num_times, ...) arrays.
template <typename Get>
py::array Stack(const std::vector<Snapshot>& snaps, Eigen::Index rows, Eigen::Index cols,
                Get get) {
  py::array_t<double> a({static_cast<py::ssize_t>(snaps.size()),
                         static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  auto v = a.mutable_unchecked<3>();
  for (size_t s = 0; s < snaps.size(); ++s) {
    const Eigen::MatrixXd m = get(snaps[s]);
    for (Eigen::Index i = 0; i < rows; ++i)
      for (Eigen::Index j = 0; j < cols; ++j)
        v(static_cast<py::ssize_t>(s), i, j) = m(i, j);
  }
  return a;
}

/// out[prefix + "normal_force" | "friction_force" | "gap"]: the contact state of the
/// snapshots as (num_times, N_c), (num_times, N_c, dim - 1) and (num_times, N_c) arrays.
void PutContactArrays(const std::vector<Snapshot>& snaps, Eigen::Index num_contact,
                      int dim, const std::string& prefix, py::dict* out) {
  py::dict& d = *out;
  d[py::str(prefix + "normal_force")] =
      Stack(snaps, num_contact, 1, [](const Snapshot& s) {
        return Eigen::MatrixXd(s.normal_force);
      })[py::make_tuple(py::ellipsis(), 0)];
  d[py::str(prefix + "friction_force")] = Stack(
      snaps, num_contact, dim - 1, [](const Snapshot& s) { return s.tangent_force; });
  d[py::str(prefix + "gap")] = Stack(snaps, num_contact, 1, [](const Snapshot& s) {
    return Eigen::MatrixXd(s.gap);
  })[py::make_tuple(py::ellipsis(), 0)];
}

/// Runs the scene's time loop (no files are written) and returns its results:
/// snapshots at scene.stress_times, at every `every`-th step (0: none) and at the end;
/// with contact_history the contact state of every step; progress(step, time, end_time)
/// after every step if given.
py::dict RunScene(const contact::Scene& scene, int every, bool contact_history,
                  const py::object& progress) {
  if (every < 0)
    throw std::invalid_argument("contact.run: every must be >= 0, got " +
                                std::to_string(every));
  contact::SceneModel built = contact::BuildSceneModel(scene);
  const contact::Mesh& mesh = built.body->mesh();
  const int dim = mesh.dim;
  const auto& nodes = built.frames.nodes;
  const Eigen::Index num_contact = static_cast<Eigen::Index>(nodes.size());
  contact::DynamicOptions& options = built.options;
  const double dt = options.dt;

  std::vector<double> pending = scene.stress_times;
  std::sort(pending.begin(), pending.end());
  std::vector<Snapshot> snaps, history;
  options.on_step = [&](const StepRecord& r, const Eigen::VectorXd& u,
                        const contact::ContactSystem::Result& c, double force_scale) {
    // Same output rule as contact::RunScene: a stress time t is written at the first step
    // with time >= t - dt/2, and the last step always.
    const bool last = r.time >= options.end_time - 1e-9 * dt;
    bool at_time = false;
    while (!pending.empty() && r.time >= pending.front() - 0.5 * dt) {
      pending.erase(pending.begin());
      at_time = true;
    }
    Snapshot s;
    s.time = r.time;
    s.normal_force = force_scale * c.normal_force;
    s.tangent_force = force_scale * c.tangent_force.transpose();
    s.gap = c.gap;
    if (contact_history) history.push_back(s);
    if (at_time || last || (every > 0 && r.step % every == 0)) {
      const Eigen::VectorXd full = built.dofs.Expand(u);
      s.displacement =
          Eigen::Map<const Eigen::MatrixXd>(full.data(), dim, mesh.NumNodes())
              .transpose();
      snaps.push_back(std::move(s));
    }
    if (!progress.is_none()) progress(r.step, r.time, options.end_time);
    if (PyErr_CheckSignals() != 0)
      throw py::error_already_set();  // Ctrl-C ends a long run
  };
  const DynamicSummary summary = contact::RunDynamics(built.model, options);

  Eigen::VectorXi contact_node(num_contact);
  Eigen::VectorXd area(num_contact);
  Eigen::MatrixXd contact_coordinates(num_contact, dim);
  for (Eigen::Index k = 0; k < num_contact; ++k) {
    contact_node(k) = nodes[static_cast<size_t>(k)].node;
    area(k) = nodes[static_cast<size_t>(k)].area;
    contact_coordinates.row(k) = mesh.nodes.col(contact_node(k)).transpose();
  }
  Eigen::VectorXd times(static_cast<Eigen::Index>(snaps.size()));
  for (size_t s = 0; s < snaps.size(); ++s)
    times(static_cast<Eigen::Index>(s)) = snaps[s].time;

  py::dict out;
  py::dict sum = SummaryColumns().Scalars(summary);
  sum["status"] = std::string(contact::ToString(summary.status));
  sum["message"] = summary.message;
  sum["step_method"] = std::string(contact::ToString(summary.step_method));  // auto resolved
  out["summary"] = sum;
  out["records"] = StepColumns().Arrays(summary.records);
  std::vector<std::string> statuses;
  for (const StepRecord& r : summary.records) statuses.push_back(r.solver_status);
  out["solver_status"] = statuses;
  out["output_times"] = times;
  out["displacement"] = Stack(snaps, mesh.NumNodes(), dim,
                              [](const Snapshot& s) { return s.displacement; });
  PutContactArrays(snaps, num_contact, dim, "", &out);
  if (contact_history) PutContactArrays(history, num_contact, dim, "history_", &out);
  out["contact_node"] = contact_node;
  out["contact_area"] = area;
  out["contact_coordinates"] = contact_coordinates;
  out["nodes"] = Eigen::MatrixXd(mesh.nodes.transpose());
  out["elements"] = Eigen::MatrixXi(mesh.elements.transpose());
  out["element_type"] = std::string(contact::ToString(mesh.element_type));
  out["final_displacement_free"] = summary.u;
  out["num_free_dofs"] = built.dofs.NumFreeDofs();
  return out;
}

}  // namespace

PYBIND11_MODULE(_contact, m) {
  m.doc() =
      "Dynamic contact of an elastic body with a rigid obstacle (C++ core of the contact "
      "package)";
  py::register_exception<contact::SceneError>(m, "SceneError", PyExc_ValueError);

  py::class_<contact::Scene>(m, "Scene",
                             "A scene read from a TOML file (examples/scenes/README.md).")
      .def_readonly("name", &contact::Scene::name)
      .def_readonly("source", &contact::Scene::source, "the file it was read from")
      .def_readonly("dim", &contact::Scene::dim)
      .def_readonly("friction_coefficient", &contact::Scene::friction_coefficient)
      .def_readonly("warnings", &contact::Scene::warnings,
                    "what the file says that a user probably did not mean (run() warns with them)")
      .def_property_readonly(
          "step", [](const contact::Scene& s) { return std::string(contact::ToString(s.dynamics.step_method)); },
          "solver.step of the file: auto, condensed, sparse, full, explicit or ipopt (the method that ran: "
          "summary['step_method'])")
      .def_property_readonly(
          "friction_formulation",
          [](const contact::Scene& s) { return std::string(contact::ToString(s.dynamics.friction_formulation)); },
          "how friction is posed: coulomb-fc (implicit Coulomb, the default) or lagged-bound (solver.friction)")
      .def_property(
          "stress_times", [](const contact::Scene& s) { return s.stress_times; },
          [](contact::Scene& s, const std::vector<double>& times) {
            for (const double t : times) Checked("stress_times", "output.stress_times", t, 0.0, 1e9, false, "s");
            s.stress_times = times;
          },
          "output times [s]")
      .def_property(
          "dt", [](const contact::Scene& s) { return s.dynamics.dt; },
          [](contact::Scene& s, double v) { s.dynamics.dt = Checked("dt", "time.dt", v, 0.0, 1e9, true, "s"); },
          "time step [s]")
      .def_property_readonly(
          "start_time", [](const contact::Scene& s) { return s.dynamics.start_time; }, "t_0 [s]")
      .def_property(
          "end_time", [](const contact::Scene& s) { return s.dynamics.end_time; },
          [](contact::Scene& s, double v) {
            s.dynamics.end_time = Checked("end_time", "time.end_time", v, 0.0, 1e9, true, "s");
          },
          "[s]")
      .def_property(
          "tolerance", [](const contact::Scene& s) { return s.dynamics.ncp.tolerance; },
          [](contact::Scene& s, double v) {
            s.dynamics.ncp.tolerance = Checked("tolerance", "solver.tolerance", v, 0.0, 1.0, true, "");
          },
          "tolerance of every step relative to its force and displacement scales")
      .def("__repr__", [](const contact::Scene& s) {
        std::ostringstream text;
        text << "<contact.Scene '" << s.name << "' dim=" << s.dim
             << " dt=" << s.dynamics.dt << " s end_time=" << s.dynamics.end_time
             << " s friction=" << s.friction_coefficient << ">";
        return text.str();
      });
  m.def(
      "load_scene",
      [](const std::string& path, const contact::SceneOverrides& overrides) {
        return contact::LoadScene(path, overrides);
      },
      py::arg("path"), py::arg("overrides") = contact::SceneOverrides{},
      "Reads and validates a scene file; overrides: [(\"time.dt\", \"1e-4\"), ...] as TOML "
      "literals, checked like the file's own values (contact-sim's --dt etc.).");
  m.def("run", &RunScene, py::arg("scene"), py::arg("every") = 0,
        py::arg("contact_history") = true, py::arg("progress") = py::none());
  m.attr("STEP_FIELDS") = py::tuple(StepColumns().Arrays({}).attr("keys")());
  m.attr("SUMMARY_FIELDS") =
      py::tuple(SummaryColumns().Scalars(DynamicSummary()).attr("keys")());
}
