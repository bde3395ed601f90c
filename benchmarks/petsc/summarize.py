#!/usr/bin/python3
"""Markdown summary of benchmarks/results/petsc/obstacle.csv (for the results README).

    /usr/bin/python3 summarize.py obstacle.csv

Prints: the full table; per (ranks, n) ours (ncp-min-seq-mg) against the fastest converged
SNESVI row at equal or smaller error; the log-log slopes of time against n and of error
against h (least squares over the grids of one configuration)."""
import csv
import math
import sys
from collections import defaultdict

OURS = "ncp-min-seq-mg"


def fmt(x, digits=3):
    try:
        v = float(x)
    except ValueError:
        return x
    return f"{v:.{digits}g}"


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den > 0 else float("nan")


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = ["solver", "ranks", "n", "ksp", "newton_iterations", "total_newton_iterations", "ksp_iterations",
            "seconds", "cpu_seconds", "error_vs_exact", "error_l2", "status", "peak_rss_mib",
            "runs"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        print("| " + " | ".join(fmt(r.get(c, "")) if c not in ("solver", "ranks", "n", "status", "ksp") else r[c]
                                for c in cols) + " |")
    print()
    print(f"Ours ({OURS}) against the fastest converged SNESVI row with error_vs_exact <= ours * 1.01:")
    print()
    print("| ranks | n | ours s | ours Newton (finest) | best SNESVI | its s | its Newton | ours / best "
          "| ours CPU s | its CPU s | CPU ours / its |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    by = defaultdict(list)
    for r in rows:
        by[(int(r["ranks"]), int(r["n"]))].append(r)
    for (ranks, n), group in sorted(by.items()):
        ours = [r for r in group if r["solver"] == OURS]
        if not ours:
            continue
        o = ours[0]
        oerr = float(o["error_vs_exact"]) if o["error_vs_exact"] else float("inf")
        peers = [r for r in group if not r["solver"].startswith("ncp") and r["status"] == "converged"
                 and float(r["error_vs_exact"]) <= oerr * 1.01]
        if not peers:
            print(f"| {ranks} | {n} | {fmt(o['seconds'])} | {o['newton_iterations']} | none converged | | | "
                  f"| {fmt(o['cpu_seconds'])} | | |")
            continue
        b = min(peers, key=lambda r: float(r["seconds"]))
        if o["status"] != "converged":  # e.g. time_limit: no CPU time, no ratio
            print(f"| {ranks} | {n} | {fmt(o['seconds'])} ({o['status']}) | | {b['solver']} | "
                  f"{fmt(b['seconds'])} | {b['newton_iterations']} | | | {fmt(b['cpu_seconds'])} | |")
            continue
        print(f"| {ranks} | {n} | {fmt(o['seconds'])} ({o['status']}) | {o['newton_iterations']} | {b['solver']} | "
              f"{fmt(b['seconds'])} | {b['newton_iterations']} | {float(o['seconds']) / float(b['seconds']):.2f} | "
              f"{fmt(o['cpu_seconds'])} | {fmt(b['cpu_seconds'])} | "
              f"{float(o['cpu_seconds']) / float(b['cpu_seconds']):.2f} |")
    print()
    print("Slopes (least squares, converged rows, n >= 10^5 for time):")
    print()
    series = defaultdict(list)
    for r in rows:
        if r["status"] == "converged":
            series[(r["solver"], int(r["ranks"]))].append(r)
    for (solver, ranks), rs in sorted(series.items()):
        if len(rs) < 3:
            continue
        rs.sort(key=lambda r: int(r["n"]))
        big = [r for r in rs if int(r["n"]) >= 100000]
        ts = slope([int(r["n"]) for r in big], [float(r["seconds"]) for r in big]) if len(big) >= 2 else float("nan")
        cs = slope([int(r["n"]) for r in big], [float(r["cpu_seconds"]) for r in big]) if len(big) >= 2 else float("nan")
        hs = [4.0 / (int(r["grid"]) - 1) for r in rs]
        es = slope(hs, [float(r["error_vs_exact"]) for r in rs])
        e2 = slope(hs, [float(r["error_l2"]) for r in rs])
        print(f"- {solver}, {ranks} rank(s), n = {rs[0]['n']}..{rs[-1]['n']}: wall time ~ n^{ts:.2f}, "
              f"CPU ~ n^{cs:.2f} (n >= 1e5); max error ~ h^{es:.2f}, L2 error ~ h^{e2:.2f}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: summarize.py obstacle.csv")
    main(sys.argv[1])
