#!/usr/bin/python3
"""Time against n (log-log) of benchmarks/results/petsc/obstacle.csv, one panel per rank count.

    /usr/bin/python3 plot_obstacle.py obstacle.csv obstacle_time.png

Converged rows are joined by lines; a row that did not converge (or was killed by the time
limit) is drawn as an 'x' at the seconds it used. The dotted line has slope 1 (time ~ n)."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read_rows(path):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if r["seconds"]]


def main(csv_path, png_path):
    rows = read_rows(csv_path)
    ranks_list = sorted({int(r["ranks"]) for r in rows})
    fig, axes = plt.subplots(1, len(ranks_list), figsize=(6.5 * len(ranks_list), 5), squeeze=False, sharey=True)
    solvers = sorted({r["solver"] for r in rows})
    colors = {s: plt.cm.tab20(i % 20) for i, s in enumerate(solvers)}
    for ax, ranks in zip(axes[0], ranks_list):
        series = defaultdict(list)
        for r in rows:
            if int(r["ranks"]) == ranks:
                series[r["solver"]].append((int(r["n"]), float(r["seconds"]), r["status"] == "converged"))
        for solver, points in sorted(series.items()):
            points.sort()
            good = [(n, t) for n, t, ok in points if ok]
            bad = [(n, t) for n, t, ok in points if not ok]
            style = "-" if solver.startswith("ncp") else "--"
            width = 2.5 if solver.startswith("ncp") else 1.2
            if good:
                ax.loglog(*zip(*good), style, marker="o", color=colors[solver], lw=width, label=solver)
            if bad:
                ax.loglog(*zip(*bad), "x", color=colors[solver], ms=9, label=None if good else solver + " (failed)")
        ns = sorted({int(r["n"]) for r in rows})
        if ns:
            t0 = min(float(r["seconds"]) for r in rows if int(r["n"]) == ns[0])
            ax.loglog([ns[0], ns[-1]], [t0, t0 * ns[-1] / ns[0]], ":", color="gray", label="slope 1 (time ~ n)")
        ax.set_title(f"{ranks} rank{'s' if ranks > 1 else ''}")
        ax.set_xlabel("unknowns n")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("wall seconds")
    axes[0][-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("Bueler obstacle problem: ncp vs PETSc SNESVI (x = not converged)")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_obstacle.py obstacle.csv obstacle_time.png")
    main(sys.argv[1], sys.argv[2])
