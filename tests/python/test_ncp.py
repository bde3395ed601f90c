"""The ncp package against the C++ API on the same problems (same iterates to round-off),
residuals recomputed here from the problem data, and the error paths."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse as sp

import ncp

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python"))
import nash_cournot  # noqa: E402


def natural_residual(x, Fx, lower, upper):
    """||x - mid(lower, upper, x - F(x))||_inf: 0 exactly at a solution of the box MCP."""
    return np.abs(x - np.clip(x - Fx, lower, upper)).max()


def assert_same_solve(py, ref):
    """Same status, counts, residual per iteration and iterate (to round-off)."""
    (x_py, s_py), (x_ref, s_ref) = py, ref
    assert s_py.termination == s_ref.termination
    assert s_py.iterations == s_ref.iterations
    assert s_py.residual_evaluations == s_ref.residual_evaluations
    phi_py = np.array([r.phi_inf for r in s_py.trace])
    phi_ref = np.array([r.phi_inf for r in s_ref.trace])
    assert phi_py.size == phi_ref.size == s_ref.iterations + 1
    np.testing.assert_allclose(phi_py, phi_ref, rtol=1e-10, atol=1e-13 * max(1.0, phi_ref[0]))
    np.testing.assert_allclose(x_py, x_ref, rtol=1e-12, atol=1e-14)


CASES = [("kojshin", "1"), ("josephy", "1"), ("nash5", "tens"), ("hs35-lcp", "zero"),
         ("path-lcp", "zero"), ("billups", "0"), ("obstacle1d-band-100", "zero"),
         ("random-plcp-200", "zero")]


@pytest.mark.parametrize("function", ["fb", "min", "penalized-fb"])
@pytest.mark.parametrize("name,start", CASES)
def test_collection_problem_through_python_callbacks_matches_cpp(name, start, function):
    p = ncp._reference.problem(name)
    starts = p["starts"]
    x0 = starts[start] if start in starts else next(iter(starts.values()))
    options = ncp.make_options(keep_trace=True, ncp_function=function)
    ref = ncp._reference.solve(name, x0, options)
    py = ncp.solve(p["F"], p["J"], x0, p["lower"], p["upper"], options=options)
    assert_same_solve(py, ref)
    if py[1].is_solution_usable:
        x = py[0]
        assert natural_residual(x, p["F"](x), p["lower"], p["upper"]) <= 1e-8


def test_hybrid_default_records_its_switches_and_solves_where_one_strategy_does_not():
    # hansmcp from GAMS' start with the min function: min alone ends at max_iterations; the
    # hybrid default leaves it for slow progress and converges (docs/ncp.md, Hybrid default).
    p = ncp._reference.problem("hansmcp")
    x0 = p["starts"]["gams"]
    x, s = ncp.solve(p["F"], p["J"], x0, p["lower"], p["upper"], ncp_function="min")
    assert s.termination == ncp.TerminationType.CONVERGED
    assert natural_residual(x, p["F"](x), p["lower"], p["upper"]) <= 1e-8
    assert len(s.strategy_switches) >= 1
    first = s.strategy_switches[0]
    assert first.from_strategy.ncp_function == ncp.NcpFunction.MIN
    assert first.to_strategy.ncp_function != ncp.NcpFunction.MIN
    assert first.reason in (ncp.SwitchReason.SLOW_PROGRESS, ncp.SwitchReason.BUDGET, ncp.SwitchReason.STUCK)
    assert 0 <= first.best_iteration <= first.iteration and first.best_psi >= 0.0
    assert "strategies: min -> " in s.message
    x1, s1 = ncp.solve(p["F"], p["J"], x0, p["lower"], p["upper"], ncp_function="min", hybrid=False)
    assert s1.termination != ncp.TerminationType.CONVERGED and not s1.strategy_switches


def test_numpy_nash_cournot_matches_cpp_nash5():
    options = ncp.make_options(keep_trace=True)
    x0 = np.full(5, 10.0)
    py = ncp.solve_ncp(nash_cournot.F, nash_cournot.J, x0, options=options)
    ref = ncp._reference.solve("nash5", x0, options)
    assert_same_solve(py, ref)
    q = py[0]
    np.testing.assert_allclose(q, [15.4293, 12.4986, 9.6635, 7.1651, 5.1326], atol=1e-4)
    assert natural_residual(q, nash_cournot.F(q), 0.0, np.inf) <= 1e-10


@pytest.mark.parametrize("dense", [True, False])
def test_solve_lcp_matches_cpp_hs35(dense):
    M = np.array([[4.0, 2, 2, 1], [2, 4, 0, 1], [2, 0, 2, 2], [-1, -1, -2, 0]])
    q = np.array([-8.0, -6, -4, 3])
    x0 = np.zeros(4)
    options = ncp.make_options(keep_trace=True)
    py = ncp.solve_lcp(M if dense else sp.csr_matrix(M), q, options=options)
    assert_same_solve(py, ncp._reference.solve("hs35-lcp", x0, options))
    z = py[0]
    w = M @ z + q
    assert z.min() >= 0 and w.min() >= -1e-10 and abs(z @ w) <= 1e-10
    np.testing.assert_allclose(z, [4 / 3, 7 / 9, 4 / 9, 2 / 9], rtol=1e-10)


def test_ncp_example_command_line_gives_the_python_solution(bin_dir):
    """examples/ncp/ncp_example.cpp: F(x) = M x + q + x^3/10, solved from x = 0."""
    exe = os.path.join(bin_dir, "ncp-example")
    if not os.path.exists(exe):
        pytest.skip("ncp-example not built")
    out = subprocess.run([exe], capture_output=True, text=True, check=True).stdout
    rows = re.findall(r"^\s+(\d)\s+(\S+)\s+(\S+)$", out, re.M)
    x_cpp = np.array([float(r[1]) for r in rows])
    iterations_cpp = int(re.search(r"converged: (\d+) iterations", out).group(1))
    M = np.array([[4.0, -1, 0], [-1, 4, -1], [0, -1, 4]])
    q = np.array([-3.0, 1, -2])
    x, s = ncp.solve_ncp(lambda x: M @ x + q + x**3 / 10, lambda x: M + np.diag(0.3 * x**2), np.zeros(3))
    assert s.is_solution_usable and s.iterations == iterations_cpp
    np.testing.assert_allclose(x, x_cpp, atol=1e-10)  # printed with 10 decimals


def test_mixed_problem_simplex_projection_against_closed_form():
    """Projection of a onto the unit simplex: E = sum x - 1, pairs x_j >= 0 perp x_j - a_j - y >= 0."""
    a = np.array([0.9, 0.5, -0.3, 0.1])  # solution (0.7, 0.3, 0, 0), nondegenerate
    k = a.size

    def evaluate(z):
        y, x = z[0], z[1:]
        return np.array([x.sum() - 1.0]), x, x - a - y

    def jacobian(z):
        JE = np.hstack([[0.0], np.ones(k)])[None, :]
        JA = sp.hstack([sp.csr_matrix((k, 1)), sp.identity(k)])
        JB = np.hstack([-np.ones((k, 1)), np.eye(k)])
        return JE, JA, JB

    z, s = ncp.solve_mixed(evaluate, jacobian, np.zeros(k + 1), num_equations=1)
    assert s.is_solution_usable, s.message
    u = np.sort(a)[::-1]  # closed form (Held, Wolfe and Crowder 1974)
    css = np.cumsum(u) - 1.0
    rho = np.nonzero(u - css / np.arange(1, k + 1) > 0)[0][-1]
    tau = css[rho] / (rho + 1)
    np.testing.assert_allclose(z[1:], np.maximum(a - tau, 0.0), atol=1e-12)
    np.testing.assert_allclose(z[0], -tau, atol=1e-12)


def test_bounds_of_1e20_are_infinite_and_dense_equals_sparse_jacobian():
    p = ncp._reference.problem("obstacle1d-band-100")
    x0 = p["starts"]["zero"]
    lower = np.where(np.isinf(p["lower"]), -1e20, p["lower"])
    upper = np.where(np.isinf(p["upper"]), 1e25, p["upper"])
    a = ncp.solve(p["F"], p["J"], x0, p["lower"], p["upper"], keep_trace=True)
    b = ncp.solve(p["F"], lambda x: p["J"](x).toarray(), x0, lower, upper, keep_trace=True)
    assert_same_solve(a, b)


def test_summary_and_options_read_like_the_cpp_ones():
    assert repr(ncp.Summary()) == "<ncp.Summary not solved yet>"
    assert ncp.Summary().iterations == -1
    o = ncp.Options()
    assert o.tolerance == 1e-10 and o.max_iterations == 500
    assert "tolerance=1e-10" in repr(o) and "ncp_function" in repr(o)
    _, s = ncp.solve_lcp(np.eye(2), [-1.0, 1.0])
    assert s.termination == ncp.TerminationType.CONVERGED and s.termination.label == "converged"
    assert "converged" in repr(s) and str(s.iterations) in repr(s)
    assert s.final_phi_inf <= 1e-10 and s.jacobian_evaluations >= 1 and "iterations" in s.full_report()


# ---- error paths ---------------------------------------------------------------------

M3 = np.array([[4.0, -1, 0], [-1, 4, -1], [0, -1, 4]])
q3 = np.array([-3.0, 1, -2])


def F3(x):
    return M3 @ x + q3


def J3(x):
    return M3


@pytest.mark.parametrize("kwargs,message", [
    ({"tolerance": -1.0}, "Options::tolerance"),
    ({"armijo_beta": 0.7}, "armijo_beta"),
    ({"toleranse": 1e-8}, "unknown option 'toleranse'"),
    ({"ncp_function": "fb2"}, "fb, min, penalized-fb"),
    ({"ncp_function": "fischer-burmeister"}, "renamed: use 'fb'"),
    ({"ncp_function": "penalized-fischer-burmeister"}, "renamed: use 'penalized-fb'"),
    ({"max_iterations": "many"}, "max_iterations"),
])
def test_bad_options_raise_value_error_with_the_cpp_message(kwargs, message):
    with pytest.raises(ValueError, match=message):
        ncp.solve_ncp(F3, J3, np.zeros(3), **kwargs)


@pytest.mark.parametrize("F,J,x0,lower,upper,message", [
    (lambda x: np.zeros(2), J3, np.zeros(3), 0.0, np.inf, r"F\(x\) returned 2 values, expected 3"),
    (F3, lambda x: np.eye(2), np.zeros(3), 0.0, np.inf, r"J\(x\) returned a 2 x 2 matrix, expected 3 x 3"),
    (F3, lambda x: sp.eye(4), np.zeros(3), 0.0, np.inf, r"J\(x\) returned a 4 x 4 sparse matrix"),
    (lambda x: "price", J3, np.zeros(3), 0.0, np.inf, r"F\(x\) must return a 1-D array of floats or None, got str"),
    (F3, lambda x: [[1.0]], np.zeros(3), 0.0, np.inf, r"J\(x\) returned a 1 x 1 matrix"),
    (F3, lambda x: np.zeros((3, 3, 3)), np.zeros(3), 0.0, np.inf, r"J\(x\) must return a 2-D array"),
    (F3, J3, np.zeros(3), [1.0, 0, 0], [0.0, 1, 1], r"lower\[0\] = 1.0+ > upper\[0\]"),
    (F3, J3, np.array([0.0, np.nan, 0.0]), 0.0, np.inf, r"x\[1\]"),
    (F3, J3, np.zeros(3), [0.0, 0.0], np.inf, "lower has 2 entries, expected 3"),
])
def test_misuse_raises_value_error(F, J, x0, lower, upper, message):
    with pytest.raises(ValueError, match=message):
        ncp.solve(F, J, x0, lower, upper)


def test_lcp_and_mixed_misuse():
    with pytest.raises(ValueError, match=r"M has shape \(3, 3\), expected \(2, 2\)"):
        ncp.solve_lcp(M3, [1.0, 2.0])
    with pytest.raises(ValueError, match=r"M has shape \(2,\)"):
        ncp.solve_lcp([1.0, 2.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="tuple"):
        ncp.solve_mixed(lambda z: (z, z), lambda z: None, np.zeros(2), num_equations=0)
    with pytest.raises(ValueError, match="NumEquations"):
        ncp.solve_mixed(lambda z: None, lambda z: None, np.zeros(2), num_equations=3)


def test_exception_in_a_callback_reaches_the_caller():
    class ModelError(Exception):
        pass

    def F(x):
        raise ModelError("demand curve undefined")
    with pytest.raises(ModelError, match="demand curve undefined"):
        ncp.solve_ncp(F, J3, np.zeros(3))


def test_numerical_trouble_is_a_status_not_an_exception():
    x, s = ncp.solve_ncp(lambda x: np.full(3, np.nan), J3, np.ones(3))
    assert s.termination == ncp.TerminationType.NON_FINITE_VALUES and not s.is_solution_usable
    x, s = ncp.solve_ncp(lambda x: None, J3, np.ones(3))
    assert not s.is_solution_usable and s.message
    x, s = ncp.solve_ncp(F3, lambda x: None, np.ones(3))
    assert s.termination == ncp.TerminationType.EVALUATION_FAILURE
    x, s = ncp.solve_ncp(nash_cournot.F, nash_cournot.J, np.full(5, 10.0), max_iterations=1)
    assert s.termination == ncp.TerminationType.MAX_ITERATIONS and s.iterations == 1


def test_callback_observes_and_stops():
    seen = []
    x, s = ncp.solve_ncp(nash_cournot.F, nash_cournot.J, np.full(5, 10.0),
                         callback=lambda r: seen.append(r.phi_inf))  # None: go on
    assert s.is_solution_usable and len(seen) == s.iterations + 1
    x, s = ncp.solve_ncp(nash_cournot.F, nash_cournot.J, np.full(5, 10.0),
                         callback=lambda r: r.iteration < 2)
    assert s.termination == ncp.TerminationType.USER_ABORT and s.iterations == 2


# ---- the docstrings say what the code does ---------------------------------------------

def test_solve_projects_a_start_point_outside_the_box_as_its_docstring_says():
    assert "projected" in ncp.solve.__doc__ and "not projected" not in ncp.solve.__doc__
    F = lambda x: x - np.array([0.5, 2.0])          # solution (0.5, 1): upper bound active
    J = lambda x: np.eye(2)
    x, s = ncp.solve(F, J, x0=[-3.0, 7.0], lower=[0.0, 0.0], upper=[1.0, 1.0])
    assert s.projected_start_components == 2 and s.is_solution_usable
    np.testing.assert_allclose(x, [0.5, 1.0], atol=1e-10)
    x, s = ncp.solve(F, J, x0=[-3.0, 7.0], lower=[0.0, 0.0], upper=[1.0, 1.0], project_start_point=False)
    assert s.projected_start_components == 0


def test_default_tolerance_is_the_documented_one():
    assert ncp.Options().tolerance == 1e-10
    assert "tolerance=1e-10" in ncp.__doc__ and "1e-10" in ncp.solve.__doc__


def test_is_solution_usable_is_a_property_like_every_other_field():
    x, s = ncp.solve_lcp(np.eye(2), [-1.0, 2.0])
    assert s.is_solution_usable is True
    assert isinstance(type(s).is_solution_usable, property)


def test_ncp_function_names_are_the_scene_file_names():
    assert [m.label for m in ncp.NcpFunction.__members__.values()] == ["fb", "min", "penalized-fb"]
    # solver.linear_solver of a scene file: auto, dense, sparse-lu, umfpack, klu (+ cholmod here)
    labels = [m.label for m in ncp.LinearSolverType.__members__.values()]
    assert {"auto", "dense", "sparse-lu", "umfpack", "klu"} <= set(labels) and "dense-lu" not in labels
    with pytest.raises(ValueError, match="renamed: use 'dense'"):
        ncp.make_options(linear_solver="dense-lu")
    assert ncp.make_options(linear_solver="dense").linear_solver == ncp.LinearSolverType.DENSE


def test_infeasible_lcp_is_reported_and_can_raise():
    """M = -I, q = -1: F(x) < 0 on the whole orthant, no solution. The status
    says so, its certificate y is checked here (y >= 0, M'y <= 0, q'y < 0), x stays >= 0,
    and raise_on_failure=True raises with the message."""
    M, q = -np.eye(2), -np.ones(2)
    x, summary = ncp.solve_lcp(M, q)
    assert summary.termination == ncp.TerminationType.INFEASIBLE, summary.message
    y = np.asarray(summary.infeasibility_certificate)
    assert y.shape == (2,) and (y >= 0).all() and (M.T @ y <= 0).all() and q @ y < 0
    assert (x >= 0).all()
    with pytest.raises(ncp.SolveError, match="infeasible: no solution exists") as err:
        ncp.solve_lcp(M, q, raise_on_failure=True)
    assert err.value.summary.termination == ncp.TerminationType.INFEASIBLE
    # A solvable LCP does not raise; a general F is never called infeasible.
    x, summary = ncp.solve_lcp(np.eye(2), -np.ones(2), raise_on_failure=True)
    assert np.allclose(x, 1.0)
    with pytest.raises(ncp.SolveError) as err:
        ncp.solve_ncp(lambda x: -x - 1.0, lambda x: -np.eye(2), np.zeros(2), raise_on_failure=True)
    assert err.value.summary.termination != ncp.TerminationType.INFEASIBLE
    assert (err.value.x >= 0).all()


def test_solve_without_bounds_is_refused():
    # Without bounds the box MCP is the equation F(x) = 0: refused, asking for the bounds.
    with pytest.raises(ValueError, match=r"give the bounds lower and upper explicitly"):
        ncp.solve(F3, J3, np.zeros(3))
    # Explicit infinite bounds solve F(x) = 0; one bound given, the other is infinite.
    x, s = ncp.solve(lambda x: x - 2.0, lambda x: np.eye(2), np.zeros(2),
                     lower=-np.inf, upper=np.inf)
    assert s.is_solution_usable and np.allclose(x, 2.0)
    x, s = ncp.solve(lambda x: x + 2.0, lambda x: np.eye(2), np.ones(2), lower=0.0)
    assert s.is_solution_usable and np.allclose(x, 0.0, atol=1e-9)



def test_a_tolerance_below_double_precision_ends_at_the_roundoff_floor_not_converged():
    """F(x) = a (x^2 - 2), a = 1e9 N: the root sqrt(2) has no double, so at the best double x
    |F(x)| = a |x^2 - 2| >= a * 2 ulp(2) / 2 ~ 4e-7 > the tolerance 1e-10 - no iterate can
    meet it. The status says so (AT_ROUNDOFF_FLOOR, not CONVERGED), x is still usable, and
    with the round-off floor switched off the same request is reported as not reached."""
    a = 1e9
    F = lambda x: a * (x * x - 2.0)
    J = lambda x: np.diag(2.0 * a * x)
    x, s = ncp.solve(F, J, [1.0, 1.5], lower=0.0, upper=np.inf)
    assert s.termination == ncp.TerminationType.AT_ROUNDOFF_FLOOR, s.message
    assert s.is_solution_usable and s.roundoff_limited
    assert "round-off floor" in s.message
    residual = np.abs(F(x)).max()  # recomputed here: above the tolerance, at the floor
    assert 1e-10 < residual <= 10 * np.finfo(float).eps * (2 * a * x * x).max()
    # |F| = 2 a x |x - sqrt 2| <= 10 eps (2 a x^2): x within 10 eps of sqrt(2), relative
    np.testing.assert_allclose(x, np.sqrt(2.0), rtol=10 * np.finfo(float).eps)
    x, s = ncp.solve(F, J, [1.0, 1.5], lower=0.0, upper=np.inf, roundoff_ulps=0.0,
                     max_iterations=50)
    assert s.termination != ncp.TerminationType.CONVERGED and not s.is_solution_usable
    with pytest.raises(ncp.SolveError):
        ncp.solve(F, J, [1.0, 1.5], lower=0.0, upper=np.inf, roundoff_ulps=0.0,
                  max_iterations=50, raise_on_failure=True)
