#!/usr/bin/python3
"""Figures of contact-bench's CSV.

  /usr/bin/python3 benchmarks/contact/plot_bench.py contact_bench.csv [--out DIR]

work_precision_<family>.png: one row per scene, one column per sweep (tolerance, dt, mesh);
error against CPU time, log-log, one line per step solver. Filled markers: converged runs;
hollow: "inaccurate" (claimed convergence, recomputed residual too large); failed, unstable
and refused runs are not drawn (they have no error). In the tolerance column of the
validation scenes the dotted line is the difference to the FB run at tolerance 1e-12 (the
solver's own part of the error), the solid line the error against the exact solution.

stability_<scene>.png: one panel per step solver, dt / dt_crit across, f_c up; each cell
coloured by status with the number of completed steps.
"""
import argparse
import csv
import math
import os
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

SOLVERS = ["fb", "min", "penalized-fb", "ipopt"]
COLORS = {"fb": "C0", "min": "C1", "penalized-fb": "C2", "ipopt": "C3"}
STATUS_COLORS = {"converged": "#7fc97f", "inaccurate": "#fdc086", "failed": "#f0027f",
                 "unstable": "#beaed4", "refused": "#bbbbbb", "skipped": "#ffffff"}
SWEEPS = ["tolerance", "dt", "mesh"]


def num(s):
    try:
        return float(s)
    except ValueError:
        return math.nan


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def work_precision(rows, family, out):
    rows = [r for r in rows if r["family"] == family]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    if not scenes:
        return None
    fig, axes = plt.subplots(len(scenes), 3, figsize=(14, 3.3 * len(scenes)), squeeze=False)
    for i, scene in enumerate(scenes):
        for j, sweep in enumerate(SWEEPS):
            ax = axes[i][j]
            for solver in SOLVERS:
                sel = [r for r in rows if r["scene"] == scene and r["sweep"] == sweep
                       and r["solver"] == solver and r["status"] in ("converged", "inaccurate")]
                sel.sort(key=lambda r: {"tolerance": -num(r["tolerance"]), "dt": -num(r["dt"]),
                                         "mesh": num(r["mesh_factor"])}[sweep])  # coarse to fine
                if not sel:
                    continue
                x = [num(r["seconds"]) for r in sel]
                y = [max(num(r["error"]), 1e-16) for r in sel]
                ax.plot(x, y, "-", color=COLORS[solver], lw=1, alpha=0.7)
                for r, xi, yi in zip(sel, x, y):
                    ax.plot(xi, yi, "o", color=COLORS[solver], ms=5,
                            mfc=COLORS[solver] if r["status"] == "converged" else "none")
                if sweep == "tolerance" and family == "validation":
                    yr = [max(num(r["reference_error"]), 1e-16) for r in sel]
                    ax.plot(x, yr, ":", color=COLORS[solver], lw=1)
                fails = [r for r in rows if r["scene"] == scene and r["sweep"] == sweep
                         and r["solver"] == solver
                         and r["status"] in ("failed", "unstable", "refused")]
                for r in fails:
                    ax.axvline(num(r["seconds"]), color=COLORS[solver], ls="--", lw=0.6)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(alpha=0.3, which="both")
            ax.set_title(f"{scene}: {sweep} sweep", fontsize=9)
            if j == 0:
                ax.set_ylabel("relative error")
            if i == len(scenes) - 1:
                ax.set_xlabel("CPU time of the run [s]")
    handles = [plt.Line2D([], [], color=COLORS[s], marker="o", label=s) for s in SOLVERS]
    handles.append(plt.Line2D([], [], color="k", marker="o", mfc="none", ls="", label="inaccurate"))
    handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.6, label="failed/unstable run (time)"))
    if family == "validation":
        handles.append(plt.Line2D([], [], color="k", ls=":", label="vs tol 1e-12 run"))
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    path = os.path.join(out, f"work_precision_{family}.png")
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def stability(rows, out):
    rows = [r for r in rows if r["sweep"] == "stability"]
    paths = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        sr = [r for r in rows if r["scene"] == scene]
        ratios = sorted({num(r["dt_ratio"]) for r in sr if r["status"] != "skipped"})
        frictions = sorted({num(r["friction"]) for r in sr})
        fig, axes = plt.subplots(1, len(SOLVERS), figsize=(4.2 * len(SOLVERS), 3.6), sharey=True)
        for ax, solver in zip(axes, SOLVERS):
            cells = {}
            for r in sr:
                if r["solver"] != solver:
                    continue
                fi = frictions.index(num(r["friction"]))
                ratio = num(r["dt_ratio"])
                ri = min(range(len(ratios)), key=lambda k: abs(ratios[k] - ratio)) if ratios else 0
                cells[(ri, fi)] = r
            for (ri, fi), r in cells.items():
                ax.add_patch(plt.Rectangle((ri - 0.5, fi - 0.5), 1, 1,
                                           color=STATUS_COLORS.get(r["status"], "k"), ec="w"))
                label = "n/a" if r["status"] == "skipped" else r["steps"]
                ax.text(ri, fi, label, ha="center", va="center", fontsize=7)
            ax.set_xlim(-0.5, len(ratios) - 0.5)
            ax.set_ylim(-0.5, len(frictions) - 0.5)
            ax.set_xticks(range(len(ratios)))
            ax.set_xticklabels([f"{x:g}" for x in ratios], fontsize=8)
            ax.set_yticks(range(len(frictions)))
            ax.set_yticklabels([f"{x:g}" for x in frictions])
            ax.set_xlabel(r"dt / dt$_{crit}$")
            ax.set_title(solver)
        axes[0].set_ylabel("friction coefficient $f_c$")
        handles = [Patch(color=c, label=s) for s, c in STATUS_COLORS.items()
                   if any(r["status"] == s for r in sr)]
        fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=9)
        fig.suptitle(f"{scene}: status (cell text: steps completed)", y=0.9, fontsize=10)
        fig.tight_layout(rect=(0, 0, 1, 0.86))
        path = os.path.join(out, f"stability_{scene}.png")
        fig.savefig(path, dpi=80)
        plt.close(fig)
        paths.append(path)
    return paths


def main():
    p = argparse.ArgumentParser()
    p.add_argument("csv")
    p.add_argument("--out", default=None)
    a = p.parse_args()
    out = a.out or os.path.dirname(os.path.abspath(a.csv))
    os.makedirs(out, exist_ok=True)
    rows = read(a.csv)
    for family in ("validation", "thesis"):
        path = work_precision(rows, family, out)
        if path:
            print(path)
    for path in stability(rows, out):
        print(path)


if __name__ == "__main__":
    main()
