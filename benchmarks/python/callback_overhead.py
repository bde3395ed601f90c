#!/usr/bin/python3
"""Cost of solving from Python: the same problems solved by the C++ API alone and through
the `ncp` package with Python callbacks.

  PYTHONPATH=build/python /usr/bin/python3 benchmarks/python/callback_overhead.py [--repeat R] [--csv OUT]

Per problem three ways, all from the same start and with the default Options, so every way
takes the same iterations (checked):
  cpp      ncp::Solver on the collection's C++ SquareFunction (ncp._reference.solve)
  wrapped  ncp.solve with Python callables that call the same C++ F and J: the cost of the
           binding alone (argument copy to NumPy, result conversion, Jacobian as CSC)
  numpy    ncp.solve with F and J written in NumPy/SciPy (what a user writes): for the LCPs
           F = M x + q with M = J(0), q = F(0); nash5 from examples/python/nash_cournot.py
One row per (problem, way): n, iterations, F and J calls, the shortest wall time of R solves (the ways taking turns) [s],
and the overhead per callback [us] = (time - time_cpp) / (F calls + J calls).
"""
import argparse
import csv
import os
import sys
import time

import numpy as np

import ncp

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python"))
import nash_cournot  # noqa: E402

PROBLEMS = [("hs35-lcp", "zero"), ("nash5", "tens"), ("path-lcp", "zero"), ("obstacle1d-bump-100", "zero"),
            ("obstacle2d-bump-20x20", "zero"), ("random-plcp-200", "zero")]


def numpy_callbacks(name, p):
    if name == "nash5":
        return nash_cournot.F, nash_cournot.J
    M = p["J"](np.zeros(p["n"])).tocsc()
    q = p["F"](np.zeros(p["n"]))
    return (lambda x: M @ x + q), (lambda x: M)


def best_times(ways, repeat):
    """{way: (shortest wall time of `repeat` solves [s], (x, Summary))}, the ways taking
    turns so that a change of the machine's load hits all of them alike."""
    best = {way: (float("inf"), None) for way in ways}
    for _ in range(repeat):
        for way, solve in ways.items():
            t = time.perf_counter()
            result = solve()
            t = time.perf_counter() - t
            best[way] = (min(best[way][0], t), result)
    return best


def main():
    cli = argparse.ArgumentParser(description="ncp: C++ versus Python callbacks")
    cli.add_argument("--repeat", type=int, default=20)
    cli.add_argument("--csv", help="also write the rows to this CSV file")
    args = cli.parse_args()
    options = ncp.make_options()
    rows = []
    for name, start in PROBLEMS:
        p = ncp._reference.problem(name)
        x0 = p["starts"][start]
        F_np, J_np = numpy_callbacks(name, p)
        ways = {
            "cpp": lambda: ncp._reference.solve(name, x0, options),
            "wrapped": lambda: ncp.solve(p["F"], p["J"], x0, p["lower"], p["upper"], options=options),
            "numpy": lambda: ncp.solve(F_np, J_np, x0, p["lower"], p["upper"], options=options),
        }
        base = None
        for way, (t, (x, s)) in best_times(ways, args.repeat).items():
            if not s.is_solution_usable:
                raise SystemExit(f"{name} {way}: {s.message}")
            calls = s.residual_evaluations + s.jacobian_evaluations
            if base is None:
                base = (t, s.iterations)
            elif s.iterations != base[1]:
                raise SystemExit(f"{name} {way}: {s.iterations} iterations, C++ took {base[1]}")
            rows.append(dict(problem=name, way=way, n=p["n"], iterations=s.iterations,
                             F_calls=s.residual_evaluations, J_calls=s.jacobian_evaluations,
                             time_s=t, time_ratio=t / base[0],
                             overhead_per_callback_us=(t - base[0]) / calls * 1e6 if way != "cpp" else 0.0))
    header = f"{'problem':24s} {'way':8s} {'n':>4s} {'it':>3s} {'F':>4s} {'J':>4s} {'time [s]':>10s} {'x C++':>7s} {'us/call':>8s}"
    print(header)
    for r in rows:
        print(f"{r['problem']:24s} {r['way']:8s} {r['n']:4d} {r['iterations']:3d} {r['F_calls']:4d} {r['J_calls']:4d} "
              f"{r['time_s']:10.3e} {r['time_ratio']:7.2f} {r['overhead_per_callback_us']:8.1f}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
