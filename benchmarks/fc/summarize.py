#!/usr/bin/python3
"""Summary of an fc-bench CSV: solved counts, shifted geometric means of the time (failures
charged the time limit), the time ratio to Siconos NSN_AC on the problems both solve, and a
Dolan-More performance profile.

Usage: summarize.py FC_BENCH.csv OUT_DIR [--time-limit 10] [--shift 0.001]
Writes OUT_DIR/summary.md and OUT_DIR/performance_profile.png."""
import argparse
import csv
import math
import os
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def shifted_geometric_mean(times, shift):
    """exp(mean(log(t + shift))) - shift, in seconds."""
    return math.exp(sum(math.log(t + shift) for t in times) / len(times)) - shift


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("out_dir")
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--shift", type=float, default=1e-3)
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    problems = list(dict.fromkeys(r["problem"] for r in rows))
    # time charged: the measured time if solved, else the time limit
    charged = defaultdict(dict)
    solved = defaultdict(dict)
    for r in rows:
        ok = r["solved"] == "1"
        solved[r["solver"]][r["problem"]] = ok
        charged[r["solver"]][r["problem"]] = float(r["time_s"]) if ok else a.time_limit
    dims = {r["problem"]: r["dimension"] for r in rows}
    p3 = [p for p in problems if dims[p] == "3"]  # Siconos' fc3d_driver runs on these

    p2 = [p for p in problems if dims[p] == "2"]  # fc2d_driver: NSGS and Lemke only

    def cells(s, subset):
        """solved count and shifted geometric mean over subset, '-' if s did not run it all."""
        if not subset or not all(p in solved[s] for p in subset):
            return "-", "-"
        n = sum(solved[s][p] for p in subset)
        return str(n), "%.3g" % shifted_geometric_mean([charged[s][p] for p in subset], a.shift)

    lines = ["| solver | solved 3D (of %d) | solved 2D (of %d) | shifted geo. mean 3D [s] "
             "| shifted geo. mean 2D [s] |" % (len(p3), len(p2)), "|---|---|---|---|---|"]
    for s in solvers:
        (n3, g3), (n2, g2) = cells(s, p3), cells(s, p2)
        lines.append("| %s | %s | %s | %s | %s |" % (s, n3, n2, g3, g2))

    ref = "siconos-nsn-ac"
    cmp_lines = []
    if ref in solved:
        for s in solvers:
            if not s.startswith("ncp-"):
                continue
            both = [p for p in p3 if solved[s].get(p) and solved[ref].get(p)]
            if not both:
                continue
            ours = shifted_geometric_mean([charged[s][p] for p in both], a.shift)
            theirs = shifted_geometric_mean([charged[ref][p] for p in both], a.shift)
            cmp_lines.append("| %s | %d | %.3g | %.3g | %.2f |" % (s, len(both), ours, theirs, ours / theirs))
    fails = ["| %s | %s |" % (p, ", ".join(s for s in solvers if p in solved[s] and not solved[s][p]) or "-")
             for p in problems]

    os.makedirs(a.out_dir, exist_ok=True)
    with open(os.path.join(a.out_dir, "summary.md"), "w") as f:
        f.write("Tolerance: recomputed natural-map error <= tolerance and the solver's own claim.\n")
        f.write("Failures are charged the time limit %g s; shifted geometric mean with shift %g s.\n\n"
                % (a.time_limit, a.shift))
        f.write("\n".join(lines) + "\n\n")
        if cmp_lines:
            f.write("Against Siconos NSN_AC on the problems both solve (shifted geometric means):\n\n")
            f.write("| solver | problems | ours [s] | NSN_AC [s] | ratio |\n|---|---|---|---|---|\n")
            f.write("\n".join(cmp_lines) + "\n\n")
        f.write("Not solved by:\n\n| problem | solvers |\n|---|---|\n" + "\n".join(fails) + "\n")

    # Dolan-More performance profile on the 3D problems: rho_s(tau) = fraction of problems
    # solved within tau times the best time.
    if not p3:
        print(open(os.path.join(a.out_dir, "summary.md")).read())
        return
    best = {p: min(charged[s][p] for s in solvers if p in charged[s] and solved[s][p])
            for p in p3 if any(solved[s].get(p) for s in solvers)}
    taus = [10 ** (k / 20.0) for k in range(0, 81)]
    plt.figure(figsize=(6, 4))
    for s in solvers:
        if not any(p in solved[s] for p in p3):
            continue  # a 2D-only solver
        ratios = [charged[s][p] / best[p] if solved[s].get(p) else math.inf for p in best]
        plt.step(taus, [sum(r <= t for r in ratios) / len(p3) for t in taus], where="post", label=s)
    plt.xscale("log")
    plt.xlabel("tau (time / best time)")
    plt.ylabel("fraction of the %d 3D problems solved" % len(p3))
    plt.ylim(0, 1.02)
    plt.legend(fontsize=7)
    plt.title("fc-bench, tolerance 1e-8")
    plt.tight_layout()
    plt.savefig(os.path.join(a.out_dir, "performance_profile.png"), dpi=120)
    print(open(os.path.join(a.out_dir, "summary.md")).read())


main()
