"""Semismooth Newton for complementarity problems (De Luca, Facchinei and Kanzow 1996).

    x, summary = ncp.solve(F, J, x0, lower=..., upper=..., tolerance=1e-10, ncp_function="fb")

solves the box MCP  lower <= x <= upper  perp  F(x)  (a bound of +-inf or of magnitude
>= 1e20 is infinite); ``solve_ncp`` is the standard NCP (lower = 0, upper = +inf),
``solve_lcp(M, q)`` the LCP with F(x) = M x + q, ``solve_mixed`` the mixed problem
E(x) = 0, 0 <= A(x) perp B(x) >= 0.  F(x) returns an array of n numbers, J(x) a
scipy.sparse matrix or a dense ndarray (n x n); either may return None for "cannot
evaluate at x" (the line search then shortens the step).  Keyword arguments are the
fields of ``ncp.Options`` (C++ defaults; enums also as strings such as
``ncp_function="min"``; the NCP functions are "fb", "min" and "penalized-fb", as in scene
files).  Misuse raises ValueError with the C++ message; numerical trouble raises only
with ``raise_on_failure=True`` (``ncp.SolveError``, carrying x and the summary), else read
``summary.termination`` / ``summary.message`` / ``summary.is_solution_usable``.  The
returned x of a box MCP always lies in [lower, upper]; an LCP without a solution ends
``TerminationType.INFEASIBLE`` with its certificate in ``summary.infeasibility_certificate``.
"""
import difflib

import numpy as np
import scipy.sparse as sp

from ._ncp import (IterationRecord, LinearSolverType, NcpFunction, Options, Strategy,
                   StrategySwitch, Summary, SwitchReason, TerminationType, _reference)
from . import _ncp
from ._version import __version__  # the project version (CMake), as the CLIs' --version

__all__ = ["solve", "solve_ncp", "solve_lcp", "solve_mixed", "make_options", "SolveError", "Options",
           "Summary", "IterationRecord", "NcpFunction", "LinearSolverType",
           "TerminationType", "Strategy", "StrategySwitch", "SwitchReason", "INFINITE_BOUND"]

#: Bounds of at least this magnitude are infinite (the GAMS / PATH convention).
INFINITE_BOUND = 1e20

class SolveError(RuntimeError):
    """A solve that did not converge, raised with ``raise_on_failure=True``: str() is the
    status and the C++ message; ``x`` is the returned point, ``summary`` the Summary."""

    def __init__(self, x, summary):
        super().__init__(f"ncp: {summary.termination.label}: {summary.message}")
        self.x = x
        self.summary = summary


def _checked(result, raise_on_failure):
    """(x, summary), or SolveError when asked to raise and the summary is not converged."""
    x, summary = result
    if raise_on_failure and not summary.is_solution_usable:
        raise SolveError(x, summary)
    return x, summary


_ENUM_OPTIONS = {"ncp_function": NcpFunction, "linear_solver": LinearSolverType}


#: Spellings used before the one vocabulary of scene files, contact-sim, C++ and Python.
_RENAMED = {"fischer-burmeister": "fb", "penalized-fischer-burmeister": "penalized-fb",
            "dense-lu": "dense"}


def _enum_value(enum, name, value):
    """An enum member from itself or from its label ("fb", as in scene files and on
    contact-sim's command line) or member name ("FB")."""
    if isinstance(value, enum):
        return value
    if isinstance(value, str):
        if value.lower() in _RENAMED:
            raise ValueError(f"ncp: {name}={value!r} was renamed: use {_RENAMED[value.lower()]!r}")
        for member in enum.__members__.values():
            if value.lower() in (member.label, member.name.lower()):
                return member
        labels = ", ".join(m.label for m in enum.__members__.values())
        raise ValueError(f"ncp: {name}={value!r} is not one of {labels}")
    raise ValueError(f"ncp: {name} must be a {enum.__name__} or a string, got {value!r}")


def _did_you_mean(name, candidates):
    """" - did you mean 'tolerance'?" for a name that is a prefix of, or close to, a candidate."""
    close = ([c for c in candidates if c.startswith(name)]
             or difflib.get_close_matches(name, list(candidates), n=1))
    return f" - did you mean {close[0]!r}?" if close else ""


def make_options(options=None, **kwargs):
    """ncp.Options from a base Options (or None: the C++ defaults) and keyword overrides.

    Unknown names and values out of range raise ValueError."""
    result = Options()
    if options is not None:
        for name in Options._fields:
            setattr(result, name, getattr(options, name))
    for name, value in kwargs.items():
        if name not in Options._fields:
            raise ValueError(f"ncp: unknown option {name!r}{_did_you_mean(name, Options._fields)}; "
                             f"options are {', '.join(Options._fields)}")
        if name in _ENUM_OPTIONS:
            value = _enum_value(_ENUM_OPTIONS[name], name, value)
        elif name == "callback" and value is not None:
            user = value
            value = lambda record: user(record) is not False  # None = go on
        try:
            setattr(result, name, value)
        except TypeError as e:
            raise ValueError(f"ncp: option {name}={value!r}: {e}") from None
    result.validate()
    return result


def _vector(name, value, n=None):
    """A 1-D float64 copy; n checks the size."""
    v = np.array(value, dtype=np.float64).reshape(-1) if np.ndim(value) else None
    if v is None:
        raise ValueError(f"ncp: {name} must be an array, got {value!r}")
    if n is not None and v.size != n:
        raise ValueError(f"ncp: {name} has {v.size} entries, expected {n}")
    return v


def _bound(name, value, n, default):
    """Bounds as float arrays of size n with +-1e20 and beyond made +-inf."""
    if value is None:
        return np.full(n, default)
    b = np.full(n, float(value)) if np.ndim(value) == 0 else _vector(name, value, n)
    b[b >= INFINITE_BOUND] = np.inf
    b[b <= -INFINITE_BOUND] = -np.inf
    return b


def _matrix_callable(J):
    """J wrapped so that the C++ side gets a dense ndarray or a canonical CSC matrix."""
    def wrapped(x):
        value = J(x)
        if value is None or isinstance(value, np.ndarray):
            return value
        if sp.issparse(value):
            csc = sp.csc_matrix(value, dtype=np.float64, copy=True)
            csc.sum_duplicates()  # also sorts the row indices, as Eigen expects
            return csc
        return np.asarray(value, dtype=np.float64)
    return wrapped


def solve(F, J, x0, lower=None, upper=None, options=None, raise_on_failure=False, **kwargs):
    """Box MCP lower <= x <= upper perp F(x) from x0.

    The bounds are required: a call without both raises ValueError (without bounds the box
    MCP is the equation F(x) = 0, which a complementarity solver's caller rarely means;
    pass lower=-np.inf, upper=np.inf for it, or use solve_ncp for x >= 0 perp F(x) >= 0).
    Given one, the other defaults to -inf (lower) or +inf (upper).  A start point outside
    [lower, upper] is projected onto it (summary.projected_start_components counts the moved
    components); project_start_point=False uses it as given.  The returned x is in [lower, upper]
    (summary.projected_final_components).  Converged when ||Phi(x)||_inf <= tolerance
    (default 1e-10), or AT_ROUNDOFF_FLOOR above it when every row is within its round-off
    floor (summary.is_solution_usable for both).  Returns (x, Summary); raise_on_failure=True
    raises SolveError instead of returning a summary that is not usable."""
    if lower is None and upper is None:
        raise ValueError("ncp.solve: give the bounds lower and upper explicitly (lower=0.0, "
                         "upper=np.inf for the NCP x >= 0 perp F(x) >= 0, or ncp.solve_ncp; "
                         "lower=-np.inf, upper=np.inf for the equation F(x) = 0)")
    return _solve_box(F, J, x0, lower, upper, options, raise_on_failure, False, **kwargs)


def _solve_box(F, J, x0, lower, upper, options, raise_on_failure, affine, **kwargs):
    x0 = _vector("x0", x0)
    n = x0.size
    opts = make_options(options, **kwargs)
    return _checked(_ncp.solve_box(n, F, _matrix_callable(J), _bound("lower", lower, n, -np.inf),
                                   _bound("upper", upper, n, np.inf), x0, opts, affine),
                    raise_on_failure)


def solve_ncp(F, J, x0, options=None, raise_on_failure=False, **kwargs):
    """Standard NCP x >= 0, F(x) >= 0, x'F(x) = 0.  Returns (x, Summary)."""
    return solve(F, J, x0, lower=0.0, upper=np.inf, options=options,
                 raise_on_failure=raise_on_failure, **kwargs)


def solve_lcp(M, q, x0=None, lower=0.0, upper=np.inf, options=None, raise_on_failure=False,
              **kwargs):
    """LCP x >= 0 perp w = M x + q >= 0 (or the box LCP with lower/upper).

    M dense or scipy.sparse (n x n); x0 defaults to 0.  Returns (x, Summary).  A problem
    without a solution may end INFEASIBLE with a checked Farkas certificate y
    (summary.infeasibility_certificate); raise_on_failure=True raises SolveError."""
    q = _vector("q", q)
    n = q.size
    M = sp.csc_matrix(M, dtype=np.float64) if sp.issparse(M) else np.array(M, dtype=np.float64)
    if M.ndim != 2 or M.shape != (n, n):
        raise ValueError(f"ncp: M has shape {M.shape}, expected ({n}, {n}) (the size of q)")
    x0 = np.zeros(n) if x0 is None else _vector("x0", x0, n)
    return _solve_box(lambda x: M @ x + q, lambda x: M, x0, lower, upper, options,
                      raise_on_failure, True, **kwargs)


def solve_mixed(evaluate, jacobian, x0, num_equations, options=None, raise_on_failure=False,
                **kwargs):
    """Mixed problem: E(x) = 0 (m rows), 0 <= A_j(x) perp B_j(x) >= 0 (n - m pairs).

    evaluate(x) -> (E, A, B); jacobian(x) -> (dE/dx, dA/dx, dB/dx), each dense or sparse
    with n columns.  Pair j belongs to variable m + j (z-vector rule).  Returns (x, Summary)."""
    x0 = _vector("x0", x0)
    opts = make_options(options, **kwargs)

    def wrapped_jacobian(x):
        value = jacobian(x)
        if value is None:
            return None
        if not isinstance(value, tuple) or len(value) != 3:
            raise ValueError("ncp: jacobian(x) must return a tuple (dE/dx, dA/dx, dB/dx) or None")
        return tuple(_matrix_callable(lambda _, m=m: m)(x) for m in value)

    return _checked(_ncp.solve_mixed(x0.size, int(num_equations), evaluate, wrapped_jacobian, x0, opts),
                    raise_on_failure)


def _options_repr(self):
    fields = ", ".join(f"{k}={getattr(self, k)!r}" for k in Options._fields if k != "callback")
    return f"ncp.Options({fields})"


Options.__repr__ = _options_repr
