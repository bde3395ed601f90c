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
#include "contact/simulation.hpp"
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
    text << "contact.Scene." << name << " = " << v << " " << unit
         << " is outside the accepted range " << (min_open ? "(" : "[") << min << ", "
         << max << "] " << unit << " (the scene key " << key << ")";
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
      ("krylov_iterations", &StepRecord::krylov_iterations)
      ("seconds", &StepRecord::seconds)
      ("solve_seconds", &StepRecord::solve_seconds)
      ("kinetic_energy", &StepRecord::kinetic)
      ("strain_energy", &StepRecord::strain)
      ("external_work", &StepRecord::external_work)
      ("normal_contact_work", &StepRecord::normal_contact_work)
      ("friction_dissipation", &StepRecord::friction_dissipation)
      ("damping_dissipation", &StepRecord::damping_dissipation)
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
      ("krylov_iterations", &DynamicSummary::krylov_iterations)
      ("seconds", &DynamicSummary::seconds)
      ("assembly_seconds", &DynamicSummary::assembly_seconds)
      ("mass_solve_seconds", &DynamicSummary::mass_solve_seconds)
      ("contact_solve_seconds", &DynamicSummary::contact_solve_seconds)
      ("accuracy_check_seconds", &DynamicSummary::accuracy_check_seconds)
      ("mass_solves", &DynamicSummary::mass_solves)
      ("max_penetration", &DynamicSummary::max_penetration)
      ("max_equilibrium_residual", &DynamicSummary::max_equilibrium_residual)
      ("max_complementarity_residual", &DynamicSummary::max_complementarity_residual)
      ("max_friction_residual", &DynamicSummary::max_friction_residual)
      ("inaccurate_steps", &DynamicSummary::inaccurate_steps)
      ("energy_balance_error", &DynamicSummary::energy_balance_error)
      ("critical_time_step", &DynamicSummary::critical_time_step)
      ("max_ipopt_relative_difference", &DynamicSummary::max_ipopt_relative_difference)
      ("finite_strain_from_step", &DynamicSummary::finite_strain_from_step)
      ("max_rotation", &DynamicSummary::max_rotation)
      ("max_spurious_strain", &DynamicSummary::max_spurious_strain)
      ("small_strain_invalid_step", &DynamicSummary::small_strain_invalid_step);
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

/// The summary as a dict: the scalar fields, status, message and the step method that
/// ran.
py::dict SummaryDict(const DynamicSummary& summary) {
  py::dict sum = SummaryColumns().Scalars(summary);
  sum["status"] = std::string(contact::ToString(summary.status));
  sum["message"] = summary.message;
  sum["step_method"] =
      std::string(contact::ToString(summary.step_method));  // auto resolved
  sum["kinematics"] = summary.kinematics;  // "small" or "finite" (docs/finite-strain.md)
  sum["material_model"] = summary.material_model;
  return sum;
}

/// (rows x cols) array of a column-major (cols x rows) block, e.g. NumNodes x dim of a
/// node-major dof vector.
Eigen::MatrixXd NodeRows(const Eigen::VectorXd& v, int dim) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), dim, v.size() / dim).transpose();
}

/// contact.Simulation's core: a scene's contact::Simulation and what contact.run collects
/// from it after every step (no files are written): snapshots at scene.stress_times, at
/// every `every`-th step (0: none) and at the end; with contact_history the contact state
/// of every step.
class SceneStepper {
 public:
  explicit SceneStepper(const contact::Scene& scene)
      : sim_(scene), built_(sim_.scene_model()), pending_(scene.stress_times) {
    std::sort(pending_.begin(), pending_.end());
  }

  void Record(int every, bool contact_history) {
    if (every < 0)
      throw std::invalid_argument("contact.run: every must be >= 0, got " +
                                  std::to_string(every));
    every_ = every;
    contact_history_ = contact_history;
  }

  /// Up to n steps; progress(step, time, end_time) after each if given. Ctrl-C ends it.
  std::string Step(long n, const py::object& progress) {
    if (n < 0)
      throw std::invalid_argument("contact.Simulation.step: n must be >= 0, got " +
                                  std::to_string(n));
    for (long i = 0; i < n && sim_.state() == contact::SimulationState::kRunning; ++i) {
      const int before = sim_.step_index();
      sim_.Step(1);
      if (sim_.step_index() == before) break;  // failed before the step was taken
      Collect();
      if (!progress.is_none())
        progress(sim_.step_index(), sim_.time(),
                 sim_.options().end_time);  // as the record's
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    return contact::ToString(sim_.state());
  }

  /// The state of a checkpoint; the stress times its steps reached are not collected
  /// again.
  void LoadCheckpoint(const std::string& path) {
    sim_.LoadCheckpoint(path);
    const double dt = sim_.options().dt;
    while (sim_.step_index() > 0 && !pending_.empty() &&
           sim_.time() >= pending_.front() - 0.5 * dt)
      pending_.erase(pending_.begin());
  }

  contact::Simulation& sim() { return sim_; }
  const contact::Simulation& sim() const { return sim_; }
  int dim() const { return built_.body->mesh().dim; }

  /// {normal_force (C,) [N], friction_force (C, dim-1) [N], gap (C,) [m], state (C,) int:
  /// 0 open, 1 stick, 2 slip} of the current state.
  py::dict Contact() const {
    const contact::ContactNodeStates c = sim_.contact();
    Eigen::VectorXi state(static_cast<Eigen::Index>(c.state.size()));
    for (size_t i = 0; i < c.state.size(); ++i)
      state(static_cast<Eigen::Index>(i)) = static_cast<int>(c.state[i]);
    py::dict d;
    d["normal_force"] = c.normal_force;
    d["friction_force"] = Eigen::MatrixXd(c.friction_force.transpose());
    d["gap"] = c.gap;
    d["state"] = state;
    return d;
  }

  /// The results of the steps so far, as contact.run returns them.
  py::dict Result() const;

 private:
  /// After a step: same output rule as contact::RunScene - a stress time t is written at
  /// the first step with time >= t - dt/2, and the last step always.
  void Collect() {
    const StepRecord& r = sim_.records().back();
    const double dt = sim_.options().dt;
    const bool last = r.time >= sim_.options().end_time - 1e-9 * dt;
    bool at_time = false;
    while (!pending_.empty() && r.time >= pending_.front() - 0.5 * dt) {
      pending_.erase(pending_.begin());
      at_time = true;
    }
    const contact::ContactNodeStates c = sim_.contact();
    Snapshot s;
    s.time = r.time;
    s.normal_force = c.normal_force;
    s.tangent_force = c.friction_force.transpose();
    s.gap = c.gap;
    if (contact_history_) history_.push_back(s);
    if (at_time || last || (every_ > 0 && r.step % every_ == 0)) {
      s.displacement = NodeRows(sim_.nodal_displacement(), dim());
      snaps_.push_back(std::move(s));
    }
  }

  contact::Simulation sim_;
  const contact::SceneModel& built_;
  std::vector<double> pending_;  // stress times not reached yet, ascending
  int every_ = 0;
  bool contact_history_ = false;
  std::vector<Snapshot> snaps_, history_;
};

py::dict SceneStepper::Result() const {
  const contact::Mesh& mesh = built_.body->mesh();
  const auto& nodes = built_.frames.nodes;
  const Eigen::Index num_contact = static_cast<Eigen::Index>(nodes.size());
  const DynamicSummary& summary = sim_.summary();
  Eigen::VectorXi contact_node(num_contact);
  Eigen::VectorXd area(num_contact);
  Eigen::MatrixXd contact_coordinates(num_contact, dim());
  for (Eigen::Index k = 0; k < num_contact; ++k) {
    contact_node(k) = nodes[static_cast<size_t>(k)].node;
    area(k) = nodes[static_cast<size_t>(k)].area;
    contact_coordinates.row(k) = mesh.nodes.col(contact_node(k)).transpose();
  }
  Eigen::VectorXd times(static_cast<Eigen::Index>(snaps_.size()));
  for (size_t s = 0; s < snaps_.size(); ++s)
    times(static_cast<Eigen::Index>(s)) = snaps_[s].time;

  py::dict out;
  out["summary"] = SummaryDict(summary);
  out["records"] = StepColumns().Arrays(summary.records);
  std::vector<std::string> statuses;
  for (const StepRecord& r : summary.records) statuses.push_back(r.solver_status);
  out["solver_status"] = statuses;
  out["output_times"] = times;
  out["displacement"] = Stack(snaps_, mesh.NumNodes(), dim(),
                              [](const Snapshot& s) { return s.displacement; });
  PutContactArrays(snaps_, num_contact, dim(), "", &out);
  if (contact_history_) PutContactArrays(history_, num_contact, dim(), "history_", &out);
  out["contact_node"] = contact_node;
  out["contact_area"] = area;
  out["contact_coordinates"] = contact_coordinates;
  out["nodes"] = Eigen::MatrixXd(mesh.nodes.transpose());
  out["elements"] = Eigen::MatrixXi(mesh.elements.transpose());
  out["element_type"] = std::string(contact::ToString(mesh.element_type));
  out["final_displacement_free"] = summary.u;
  out["num_free_dofs"] = built_.dofs.NumFreeDofs();
  return out;
}

/// A length-dim vector from Python (a sequence or array) [unit], checked.
Eigen::VectorXd VectorArg(const char* what, const py::object& value, int dim) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a(value);
  if (a.ndim() != 1 || a.shape(0) != dim)
    throw std::invalid_argument(std::string("contact.Simulation: ") + what +
                                " must have " + std::to_string(dim) +
                                " components, got an array of shape " +
                                py::repr(a.attr("shape")).cast<std::string>());
  return Eigen::Map<const Eigen::VectorXd>(a.data(), dim);
}

}  // namespace

PYBIND11_MODULE(_contact, m) {
  m.doc() =
      "Dynamic contact of an elastic body with a rigid obstacle (C++ core of the contact "
      "package)";
  py::register_exception<contact::SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<contact::CheckpointError>(m, "CheckpointError",
                                                   PyExc_ValueError);

  py::class_<contact::Scene>(m, "Scene",
                             "A scene read from a TOML file (examples/scenes/README.md).")
      .def_readonly("name", &contact::Scene::name)
      .def_readonly("source", &contact::Scene::source, "the file it was read from")
      .def_readonly("dim", &contact::Scene::dim)
      .def_readonly("friction_coefficient", &contact::Scene::friction_coefficient)
      .def_readonly(
          "warnings", &contact::Scene::warnings,
          "what the file says that a user probably did not mean (run() warns with them)")
      .def_property_readonly(
          "step",
          [](const contact::Scene& s) {
            return std::string(contact::ToString(s.dynamics.step_method));
          },
          "solver.step of the file: auto, condensed, sparse, full, explicit or ipopt "
          "(the method that ran: "
          "summary['step_method'])")
      .def_property_readonly(
          "friction_formulation",
          [](const contact::Scene& s) {
            return std::string(contact::ToString(s.dynamics.friction_formulation));
          },
          "how friction is posed: coulomb-fc (implicit Coulomb, the default) or "
          "lagged-bound (solver.friction)")
      .def_property(
          "stress_times", [](const contact::Scene& s) { return s.stress_times; },
          [](contact::Scene& s, const std::vector<double>& times) {
            for (const double t : times)
              Checked("stress_times", "output.stress_times", t, 0.0, 1e9, false, "s");
            s.stress_times = times;
          },
          "output times [s]")
      .def_property(
          "dt", [](const contact::Scene& s) { return s.dynamics.dt; },
          [](contact::Scene& s, double v) {
            s.dynamics.dt = Checked("dt", "time.dt", v, 0.0, 1e9, true, "s");
          },
          "time step [s]")
      .def_property_readonly(
          "start_time", [](const contact::Scene& s) { return s.dynamics.start_time; },
          "t_0 [s]")
      .def_property(
          "end_time", [](const contact::Scene& s) { return s.dynamics.end_time; },
          [](contact::Scene& s, double v) {
            s.dynamics.end_time =
                Checked("end_time", "time.end_time", v, 0.0, 1e9, true, "s");
          },
          "[s]")
      .def_property(
          "tolerance", [](const contact::Scene& s) { return s.dynamics.ncp.tolerance; },
          [](contact::Scene& s, double v) {
            s.dynamics.ncp.tolerance =
                Checked("tolerance", "solver.tolerance", v, 0.0, 1.0, true, "");
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
      "Reads and validates a scene file; overrides: [(\"time.dt\", \"1e-4\"), ...] as "
      "TOML "
      "literals, checked like the file's own values (contact-sim's --dt etc.).");
  py::class_<SceneStepper>(
      m, "Simulation",
      "The scene's integrator one step at a time (contact/simulation.hpp); "
      "contact.Simulation wraps it.")
      .def(py::init<const contact::Scene&>(), py::arg("scene"))
      .def("record", &SceneStepper::Record, py::arg("every"), py::arg("contact_history"))
      .def("step", &SceneStepper::Step, py::arg("n") = 1,
           py::arg("progress") = py::none(),
           "up to n steps; returns the state: running, finished or failed")
      .def("result", &SceneStepper::Result)
      .def_property_readonly("state",
                             [](const SceneStepper& s) {
                               return std::string(contact::ToString(s.sim().state()));
                             })
      .def_property_readonly("time", [](const SceneStepper& s) { return s.sim().time(); })
      .def_property_readonly("step_index",
                             [](const SceneStepper& s) { return s.sim().step_index(); })
      .def_property_readonly("num_steps",
                             [](const SceneStepper& s) { return s.sim().num_steps(); })
      .def_property_readonly("dt",
                             [](const SceneStepper& s) { return s.sim().options().dt; })
      .def_property_readonly(
          "end_time", [](const SceneStepper& s) { return s.sim().options().end_time; })
      .def_property_readonly("dim", &SceneStepper::dim)
      .def_property_readonly("displacement",
                             [](const SceneStepper& s) {
                               return NodeRows(s.sim().nodal_displacement(), s.dim());
                             })
      .def_property_readonly("velocity",
                             [](const SceneStepper& s) {
                               return NodeRows(s.sim().nodal_velocity(), s.dim());
                             })
      .def_property_readonly("displacement_free",
                             [](const SceneStepper& s) { return s.sim().displacement(); })
      .def_property_readonly("contact", &SceneStepper::Contact)
      .def_property_readonly("contact_gaps",
                             [](const SceneStepper& s) { return s.sim().contact_gaps(); })
      .def_property_readonly(
          "summary", [](const SceneStepper& s) { return SummaryDict(s.sim().summary()); })
      .def_property_readonly(
          "records",
          [](const SceneStepper& s) { return StepColumns().Arrays(s.sim().records()); })
      .def_property_readonly("body_force",
                             [](const SceneStepper& s) { return s.sim().body_force(); })
      .def_property_readonly(
          "obstacle_translation",
          [](const SceneStepper& s) { return s.sim().obstacle_translation(); })
      .def(
          "set_body_force",
          [](SceneStepper& s, const py::object& b) {
            s.sim().SetBodyForce(VectorArg("the body force [N/m^3]", b, s.dim()));
          },
          py::arg("body_force"))
      .def(
          "save",
          [](const SceneStepper& s, const std::string& path) {
            s.sim().SaveCheckpoint(path);
          },
          py::arg("path"),
          "the checkpoint of the state (contact::Simulation::SaveCheckpoint)")
      .def("load_checkpoint", &SceneStepper::LoadCheckpoint, py::arg("path"),
           "the state of a checkpoint of the same scene "
           "(contact::Simulation::LoadCheckpoint)")
      .def(
          "move_obstacle",
          [](SceneStepper& s, const py::object& d) {
            s.sim().MoveObstacle(VectorArg("the obstacle translation [m]", d, s.dim()));
          },
          py::arg("translation"));
  m.attr("STEP_FIELDS") = py::tuple(StepColumns().Arrays({}).attr("keys")());
  m.attr("SUMMARY_FIELDS") =
      py::tuple(SummaryColumns().Scalars(DynamicSummary()).attr("keys")());
}
