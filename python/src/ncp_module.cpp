// The `ncp._ncp` extension: the solver of ncp/include/ncp/solver.hpp with the problem
// given by Python callables. The pure-Python layer (python/ncp/__init__.py) turns keyword
// arguments into Options, infinite bounds into +-inf, and any scipy.sparse Jacobian into
// canonical CSC before it reaches this file.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "enum_binding.hpp"
#include "ncp/ncp.hpp"
#include "ncp_collection/collection.hpp"

namespace py = pybind11;

namespace {

using ncp::SparseMatrix;
using ncp::Vector;

/// A fresh NumPy copy of x: a callback may keep its argument, the solver reuses x's
/// storage.
py::array_t<double> ToNumpy(const Vector& x) {
  return py::array_t<double>(x.size(), x.data());
}

/// py::cast<T>(value), with a failed conversion reported as misuse (ValueError) naming
/// the callback.
template <typename T>
T CastResult(const py::handle& value, const std::string& what, const char* expected) {
  try {
    return py::cast<T>(value);
  } catch (const py::cast_error&) {
    throw std::invalid_argument(
        what + " must return " + expected + " or None, got " +
        std::string(py::str(py::type::handle_of(value).attr("__name__"))));
  }
}

/// result (an array-like of `expected` numbers) -> *out. A size mismatch is misuse.
void ToVector(const py::handle& result, Eigen::Index expected, const std::string& what,
              Vector* out) {
  Vector v = CastResult<Vector>(result, what, "a 1-D array of floats");
  if (v.size() != expected)
    throw std::invalid_argument(what + " returned " + std::to_string(v.size()) +
                                " values, expected " + std::to_string(expected));
  *out = std::move(v);
}

/// A dense ndarray or a scipy.sparse.csc_matrix (canonical: sorted, no duplicates) of
/// shape rows x cols -> *out. A dense matrix keeps all rows*cols entries, explicit zeros
/// included, so the sparsity pattern (and the symbolic factorization) stays the same
/// between calls.
void ToSparse(const py::handle& result, Eigen::Index rows, Eigen::Index cols,
              const std::string& what, SparseMatrix* out) {
  if (py::isinstance<py::array>(result)) {
    const Eigen::MatrixXd dense =
        CastResult<Eigen::MatrixXd>(result, what, "a 2-D array");
    if (dense.rows() != rows || dense.cols() != cols)
      throw std::invalid_argument(what + " returned a " + std::to_string(dense.rows()) +
                                  " x " + std::to_string(dense.cols()) +
                                  " matrix, expected " + std::to_string(rows) + " x " +
                                  std::to_string(cols));
    out->resize(rows, cols);
    out->reserve(Eigen::VectorXi::Constant(cols, static_cast<int>(rows)));
    for (Eigen::Index j = 0; j < cols; ++j)
      for (Eigen::Index i = 0; i < rows; ++i) out->insert(i, j) = dense(i, j);
    out->makeCompressed();
    return;
  }
  SparseMatrix sparse =
      CastResult<SparseMatrix>(result, what, "a scipy.sparse matrix or a 2-D ndarray");
  if (sparse.rows() != rows || sparse.cols() != cols)
    throw std::invalid_argument(what + " returned a " + std::to_string(sparse.rows()) +
                                " x " + std::to_string(sparse.cols()) +
                                " sparse matrix, expected " + std::to_string(rows) +
                                " x " + std::to_string(cols));
  *out = std::move(sparse);
}

/// F : R^n -> R^n from two callables; either may return None for "cannot evaluate at x".
class PythonSquareFunction : public ncp::SquareFunction {
 public:
  PythonSquareFunction(int n, py::function F, py::function J, bool affine)
      : n_(n), F_(std::move(F)), J_(std::move(J)), affine_(affine) {}
  int NumVariables() const override { return n_; }
  bool IsAffine() const override { return affine_; }
  bool Evaluate(const Vector& x, Vector* F) override {
    py::object r = F_(ToNumpy(x));
    if (r.is_none()) return false;
    ToVector(r, n_, "F(x)", F);
    return true;
  }
  bool Jacobian(const Vector& x, SparseMatrix* J) override {
    py::object r = J_(ToNumpy(x));
    if (r.is_none()) return false;
    ToSparse(r, n_, n_, "J(x)", J);
    return true;
  }

 private:
  int n_;
  py::function F_, J_;
  bool affine_;  // F(x) = M x + q (solve_lcp): a stuck solve may prove infeasibility
};

/// The mixed problem of ncp/problem.hpp: evaluate(x) -> (E, A, B), jacobian(x) -> (JE,
/// JA, JB).
class PythonMixedProblem : public ncp::MixedProblem {
 public:
  PythonMixedProblem(int n, int m, py::function evaluate, py::function jacobian)
      : n_(n), m_(m), evaluate_(std::move(evaluate)), jacobian_(std::move(jacobian)) {}
  int NumVariables() const override { return n_; }
  int NumEquations() const override { return m_; }
  bool Evaluate(const Vector& x, Vector* E, Vector* A, Vector* B) override {
    py::object r = evaluate_(ToNumpy(x));
    if (r.is_none()) return false;
    const py::tuple t = Triple(r, "evaluate(x)");
    ToVector(t[0], m_, "evaluate(x)[0] (E)", E);
    ToVector(t[1], n_ - m_, "evaluate(x)[1] (A)", A);
    ToVector(t[2], n_ - m_, "evaluate(x)[2] (B)", B);
    return true;
  }
  bool Jacobian(const Vector& x, SparseMatrix* JE, SparseMatrix* JA,
                SparseMatrix* JB) override {
    py::object r = jacobian_(ToNumpy(x));
    if (r.is_none()) return false;
    const py::tuple t = Triple(r, "jacobian(x)");
    ToSparse(t[0], m_, n_, "jacobian(x)[0] (dE/dx)", JE);
    ToSparse(t[1], n_ - m_, n_, "jacobian(x)[1] (dA/dx)", JA);
    ToSparse(t[2], n_ - m_, n_, "jacobian(x)[2] (dB/dx)", JB);
    return true;
  }

 private:
  static py::tuple Triple(const py::object& r, const std::string& what) {
    if (!py::isinstance<py::tuple>(r) || py::len(r) != 3)
      throw std::invalid_argument(what + " must return a tuple of 3 arrays (or None)");
    return r.cast<py::tuple>();
  }
  int n_, m_;
  py::function evaluate_, jacobian_;
};

/// Binds the fields of a plain-data struct from a table, one line per field, and records
/// the names so that Python can list them (keyword arguments, repr, as_dict).
template <typename Struct>
class FieldTable {
 public:
  FieldTable(py::class_<Struct>& cls, bool writable) : cls_(cls), writable_(writable) {}
  template <typename T>
  FieldTable& operator()(const char* name, T Struct::*member, const char* doc) {
    if (writable_)
      cls_.def_readwrite(name, member, doc);
    else
      cls_.def_readonly(name, member, doc);
    names_.emplace_back(name);
    return *this;
  }
  ~FieldTable() { cls_.attr("_fields") = py::tuple(py::cast(names_)); }

 private:
  py::class_<Struct>& cls_;
  bool writable_;
  std::vector<std::string> names_;
};

void BindOptions(py::module_& m) {
  using ncp::Options;
  py::class_<Options> cls(m, "Options",
                          "ncp::Options: every field with its C++ default.");
  cls.def(py::init<>());
  // One line per field of ncp/include/ncp/solver.hpp (the doc states the test it
  // controls).
  // clang-format off
  FieldTable<Options>(cls, true)
      ("ncp_function", &Options::ncp_function, "NCP function phi of the reformulation Phi(x) = 0")
      ("min_tie_takes_b", &Options::min_tie_takes_b, "min function at A_j = B_j: grad B_j (True) or grad A_j")
      ("penalized_fb_lambda", &Options::penalized_fb_lambda, "lambda of the penalized FB function, in (0, 1]")
      ("tolerance", &Options::tolerance, "converged when ||Phi(x)||_inf <= tolerance (relative to the problem's own scales when it gives them)")
      ("max_seconds", &Options::max_seconds, "wall-time limit [s] (TIME_LIMIT)")
      ("factorization_flop_rate", &Options::factorization_flop_rate, "flop/s predicting a factorization's time (0: the backend's)")
      ("nonmonotone_memory", &Options::nonmonotone_memory, "Armijo reference: largest psi of the last this many iterates (1: monotone)")
      ("regularized_direction", &Options::regularized_direction, "try a Levenberg-Marquardt direction before -grad psi")
      ("merit_restarts", &Options::merit_restarts, "stuck FB-family solve: restart with the other member (FB <-> penalized FB), at most this often")
      ("hybrid", &Options::hybrid, "a strategy that stops progressing hands its best point to the next (penalized FB, min, FB+LM, penalized FB+LM)")
      ("hybrid_window", &Options::hybrid_window, "iterations of the hybrid's slow-progress test (0: off)")
      ("hybrid_decrease", &Options::hybrid_decrease, "slow progress: min psi fell by less than this factor over the window, in (0, 1)")
      ("hybrid_budget_per_unknown", &Options::hybrid_budget_per_unknown, "a strategy's budget: max(hybrid_window, this * n) iterations")
      ("infinite_bound", &Options::infinite_bound, "box MCP: |bound| >= this is infinite")
      ("project_start_point", &Options::project_start_point, "box MCP: project the start point onto [l, u]")
      ("roundoff_ulps", &Options::roundoff_ulps,
       "converged also when every row is within tolerance + this many ulps of its |J||x| (0: off)")
      ("max_iterations", &Options::max_iterations, "stop with MAX_ITERATIONS after this many steps")
      ("descent_rho", &Options::descent_rho, "Newton step kept if grad psi'd <= -rho ||d||^p (eq. 22)")
      ("descent_p", &Options::descent_p, "p of the descent test (eq. 22)")
      ("armijo_beta", &Options::armijo_beta, "Armijo constant beta in (0, 1/2) (eq. 23)")
      ("max_backtracks", &Options::max_backtracks, "largest i tried in the step 2^-i")
      ("degenerate_tolerance", &Options::degenerate_tolerance, "pair degenerate when hypot(A_j, B_j) <= this")
      ("stationarity_tolerance", &Options::stationarity_tolerance,
       "stationary point if ||grad psi||_inf <= this * ||Phi||_inf when the line search fails")
      ("stagnation_window", &Options::stagnation_window, "iterations of the stagnation test (0: off)")
      ("stagnation_tolerance", &Options::stagnation_tolerance, "relative psi decrease of the stagnation test")
      ("gradient_fallback", &Options::gradient_fallback, "fall back to d = -grad psi (Algorithm 1 step 2)")
      ("scale_newton_system", &Options::scale_newton_system, "dense LU: equilibrate J when its rows or columns spread over more than 2^20")
      ("minimum_norm_step", &Options::minimum_norm_step, "singular J: the rank-revealing least-squares step before LM and -grad psi")
      ("linear_solver", &Options::linear_solver, "linear solver of the Newton system")
      ("dense_threshold", &Options::dense_threshold, "AUTO: dense LU for n <= dense_threshold, else UMFPACK")
      ("blas_threads", &Options::blas_threads, "at most this many BLAS threads during a solve (OpenBLAS; 0: leave alone)")
      ("keep_trace", &Options::keep_trace, "store an IterationRecord per iteration in Summary.trace")
      ("log_to_stderr", &Options::log_to_stderr, "print one line per iteration to stderr")
      ("callback", &Options::callback, "callable(IterationRecord) -> bool; False stops (USER_ABORT)");
  // clang-format on
  cls.def(
      "validate",
      [](const Options& o) {
        std::string error;
        if (!o.IsValid(&error)) throw std::invalid_argument("ncp::Options: " + error);
      },
      "Raises ValueError naming the first option out of its range.");
}

void BindSummary(py::module_& m) {
  using ncp::IterationRecord;
  using ncp::Summary;
  py::class_<IterationRecord> record(
      m, "IterationRecord", "State after one iteration (k = 0: the start point).");
  // clang-format off
  FieldTable<IterationRecord>(record, false)
      ("iteration", &IterationRecord::iteration, "k")
      ("phi_inf", &IterationRecord::phi_inf, "||Phi(x^k)||_inf")
      ("psi", &IterationRecord::psi, "1/2 ||Phi(x^k)||_2^2")
      ("grad_psi_inf", &IterationRecord::grad_psi_inf, "||J' Phi||_inf")
      ("step_length", &IterationRecord::step_length, "2^-i of the step that reached x^k")
      ("direction_norm", &IterationRecord::direction_norm, "||d||_2 of that step")
      ("backtracks", &IterationRecord::backtracks, "i of that step")
      ("gradient_step", &IterationRecord::gradient_step, "that step was d = -grad psi")
      ("regularized_step", &IterationRecord::regularized_step, "that step was the Levenberg-Marquardt direction")
      ("minimum_norm_step", &IterationRecord::minimum_norm_step, "that step was the rank-revealing least-squares direction")
      ("degenerate_pairs", &IterationRecord::degenerate_pairs, "pairs with A = B = 0 at x^k")
      ("time_s", &IterationRecord::time_s, "wall time since the start [s]");
  // clang-format on

  py::class_<ncp::Strategy> strategy(m, "Strategy", "A strategy of the hybrid default.");
  // clang-format off
  FieldTable<ncp::Strategy>(strategy, false)
      ("ncp_function", &ncp::Strategy::ncp_function, "the NCP function")
      ("regularized_direction", &ncp::Strategy::regularized_direction, "the Levenberg-Marquardt direction before -grad psi");
  // clang-format on
  strategy.def("__repr__", [](const ncp::Strategy& s) {
    return std::string("<ncp.Strategy ") + ToString(s.ncp_function) +
           (s.regularized_direction ? "+lm" : "") + ">";
  });
  py::class_<ncp::StrategySwitch> change(
      m, "StrategySwitch", "A switch of the hybrid default (Options.hybrid).");
  // clang-format off
  FieldTable<ncp::StrategySwitch>(change, false)
      ("iteration", &ncp::StrategySwitch::iteration, "k at which the new strategy starts")
      ("from_strategy", &ncp::StrategySwitch::from_strategy, "the strategy left")
      ("to_strategy", &ncp::StrategySwitch::to_strategy, "the strategy taken")
      ("reason", &ncp::StrategySwitch::reason, "STUCK, SLOW_PROGRESS or BUDGET")
      ("best_iteration", &ncp::StrategySwitch::best_iteration, "k of the point the new strategy starts from")
      ("best_psi", &ncp::StrategySwitch::best_psi, "psi of the strategy left at that point");
  // clang-format on

  py::class_<Summary> cls(m, "Summary",
                          "ncp::Summary: status, message, counts, residuals, timings.");
  cls.def(py::init<>());
  // clang-format off
  FieldTable<Summary>(cls, false)
      ("termination", &Summary::termination, "why the solve stopped (CONVERGED and AT_ROUNDOFF_FLOOR: x usable, see is_solution_usable)")
      ("message", &Summary::message, "human-readable reason")
      ("num_variables", &Summary::num_variables, "n")
      ("num_equations", &Summary::num_equations, "m (smooth equations)")
      ("num_pairs", &Summary::num_pairs, "n - m complementarity pairs")
      ("ncp_function", &Summary::ncp_function, "the NCP function used")
      ("linear_solver_requested", &Summary::linear_solver_requested, "Options.linear_solver")
      ("linear_solver_used", &Summary::linear_solver_used, "the linear solver actually used")
      ("iterations", &Summary::iterations, "steps taken")
      ("jacobian_evaluations", &Summary::jacobian_evaluations, "calls of J")
      ("residual_evaluations", &Summary::residual_evaluations, "calls of F (line search included)")
      ("gradient_steps", &Summary::gradient_steps, "steps with d = -grad psi")
      ("linear_solver_failures", &Summary::linear_solver_failures, "failed Newton solves")
      ("descent_test_failures", &Summary::descent_test_failures, "Newton directions rejected by eq. 22")
      ("backtracks", &Summary::backtracks, "total halvings in the line search")
      ("regularized_steps", &Summary::regularized_steps, "steps along the Levenberg-Marquardt direction")
      ("minimum_norm_steps", &Summary::minimum_norm_steps, "steps along the rank-revealing least-squares direction")
      ("equilibrated_factorizations", &Summary::equilibrated_factorizations, "dense LU factorizations of an equilibrated J")
      ("merit_restarts", &Summary::merit_restarts, "restarts switching FB <-> penalized FB")
      ("strategy_switches", &Summary::strategy_switches, "StrategySwitch per switch of the hybrid default")
      ("projected_start_components", &Summary::projected_start_components, "start components moved onto [l, u]")
      ("projected_final_components", &Summary::projected_final_components, "components of the last iterate moved onto [l, u]")
      ("infeasibility_certificate", &Summary::infeasibility_certificate, "INFEASIBLE: the Farkas certificate y (else empty)")
      ("predicted_factorization_flops", &Summary::predicted_factorization_flops, "largest predicted factorization cost [flop]")
      ("weighted_residual", &Summary::weighted_residual, "residuals are relative to the problem's own scales")
      ("roundoff_limited", &Summary::roundoff_limited, "converged at the round-off floor, above the tolerance")
      ("symbolic_factorizations", &Summary::symbolic_factorizations, "sparse analyses")
      ("cholesky_fallbacks", &Summary::cholesky_fallbacks, "cholmod backend: Newton matrices factored by UMFPACK instead")
      ("initial_phi_inf", &Summary::initial_phi_inf, "||Phi(x^0)||_inf")
      ("final_phi_inf", &Summary::final_phi_inf, "||Phi(x)||_inf at the returned x")
      ("final_psi", &Summary::final_psi, "psi at the returned x")
      ("total_time_s", &Summary::total_time_s, "[s]")
      ("evaluation_time_s", &Summary::evaluation_time_s, "total_time_s - linear_solver_time_s: F and J (the Python callbacks), the assembly of Phi and J, line search and tests [s]")
      ("linear_solver_time_s", &Summary::linear_solver_time_s, "computing the directions: factorizations and solves [s]")
      ("trace", &Summary::trace, "IterationRecord per iteration (Options.keep_trace)");
  // clang-format on
  cls.def("brief_report", &Summary::BriefReport)
      .def("full_report", &Summary::FullReport)
      .def_property_readonly(
          "is_solution_usable", &Summary::IsSolutionUsable,
          "converged (also at the round-off floor): x solves the problem "
          "to the tolerance")
      .def("__repr__", [](const Summary& s) {
        return "<ncp.Summary " +
               (s.termination == ncp::TerminationType::kNotSolved ? s.message
                                                                  : s.BriefReport()) +
               ">";
      });
}

/// The problems of ncp/collection, solved in C++ alone, so that the tests can check the
/// bindings iterate for iterate against the C++ API.
void BindReference(py::module_& m) {
  py::module_ ref =
      m.def_submodule("_reference", "C++ reference problems and solves (for the tests).");
  ref.def("problem_names", [] {
    std::vector<std::string> names;
    for (const auto& p : ncp::collection::StandardCollection()) names.push_back(p.name);
    return names;
  });
  auto find = [](const std::string& name) {
    for (auto& p : ncp::collection::StandardCollection())
      if (p.name == name)
        return std::make_shared<ncp::collection::TestProblem>(std::move(p));
    throw std::invalid_argument("no collection problem named '" + name + "'");
  };
  ref.def(
      "problem",
      [find](const std::string& name) {
        std::shared_ptr<ncp::collection::TestProblem> p = find(name);
        py::dict starts;
        for (const auto& s : p->starts) starts[py::str(s.label)] = ToNumpy(s.x);
        const int n = p->NumVariables();
        auto F = [p, n](const Vector& x) {
          Vector Fx(n);
          if (!p->F->Evaluate(x, &Fx)) return py::object(py::none());
          return py::object(ToNumpy(Fx));
        };
        auto J = [p](const Vector& x) {
          SparseMatrix Jx;
          if (!p->F->Jacobian(x, &Jx)) return py::object(py::none());
          return py::cast(Jx);
        };
        py::dict d;
        d["n"] = n;
        d["lower"] = ToNumpy(p->lower);
        d["upper"] = ToNumpy(p->upper);
        d["starts"] = starts;
        d["F"] = py::cpp_function(F);
        d["J"] = py::cpp_function(J);
        return d;
      },
      "dict(n, lower, upper, starts, F, J) of a collection problem");
  ref.def(
      "solve",
      [find](const std::string& name, const Vector& x0, const ncp::Options& options) {
        std::shared_ptr<ncp::collection::TestProblem> p = find(name);
        Vector x = x0;
        ncp::Summary summary;
        ncp::Solver(options).Solve(*p->F, p->lower, p->upper, &x, &summary);
        return py::make_tuple(ToNumpy(x), summary);
      },
      "(x, Summary) of the box MCP solved by the C++ API alone");
}

}  // namespace

PYBIND11_MODULE(_ncp, m) {
  m.doc() =
      "Semismooth Newton for complementarity problems (C++ core of the ncp package)";
  bindings::BindEnum(m, "NcpFunction", ncp::kLastNcpFunction, "NCP function phi(a, b)");
  bindings::BindEnum(m, "LinearSolverType", ncp::kLastLinearSolverType,
                     "linear solver of J d = -Phi");
  bindings::BindEnum(m, "TerminationType", ncp::kLastTerminationType,
                     "why a solve stopped");
  bindings::BindEnum(m, "SwitchReason", ncp::kLastSwitchReason,
                     "why the hybrid default left a strategy");
  BindOptions(m);
  BindSummary(m);

  m.def(
      "solve_box",
      [](int n, py::function F, py::function J, const Vector& lower, const Vector& upper,
         const Vector& x0, const ncp::Options& options, bool affine) {
        PythonSquareFunction problem(n, std::move(F), std::move(J), affine);
        Vector x = x0;
        ncp::Summary summary;
        ncp::Solver(options).Solve(problem, lower, upper, &x, &summary);
        return py::make_tuple(ToNumpy(x), summary);
      },
      py::arg("n"), py::arg("F"), py::arg("J"), py::arg("lower"), py::arg("upper"),
      py::arg("x0"), py::arg("options"), py::arg("affine") = false,
      "Box MCP lower <= x <= upper perp F(x); returns (x, Summary). affine: F(x) = M x + "
      "q "
      "(then a stuck solve checks for a Farkas certificate of infeasibility).");
  m.def(
      "solve_mixed",
      [](int n, int m_eq, py::function evaluate, py::function jacobian, const Vector& x0,
         const ncp::Options& options) {
        PythonMixedProblem problem(n, m_eq, std::move(evaluate), std::move(jacobian));
        Vector x = x0;
        ncp::Summary summary;
        ncp::Solver(options).Solve(problem, &x, &summary);
        return py::make_tuple(ToNumpy(x), summary);
      },
      py::arg("n"), py::arg("m"), py::arg("evaluate"), py::arg("jacobian"), py::arg("x0"),
      py::arg("options"),
      "Mixed problem E(x) = 0, 0 <= A(x) perp B(x) >= 0; returns (x, Summary).");
  BindReference(m);
}
