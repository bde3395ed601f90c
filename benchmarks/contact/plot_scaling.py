#!/usr/bin/python3
"""Figures of contact-scaling-bench's CSV.

  /usr/bin/python3 benchmarks/contact/plot_scaling.py scaling.csv [--out DIR]

scaling_cube.png: time per step against dofs (log-log) on the cube series, one line per
step method and friction coefficient, the fitted exponent in the legend; the dotted black
line is one product K x. Right panel: the step time in units of K x.
scaling_column.png: the column series (fixed 14 x 14 contact face, growing height): time
per step and Newton iterations per step against dofs.
scaling_face.png: the face series (slab with a growing contact face, f_c = 0.3): time per
step and one Cholesky factorization of M against contact nodes (log-log, fitted exponent),
the step in units of that factorization, and Newton iterations per step.
"""
import argparse
import csv
import math
import os
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {"full": ("C3", "s"), "condensed": ("C0", "o"), "explicit": ("C2", "^"), "sparse": ("C1", "D")}


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else math.nan


def finish(ax, xlabel, ylabel, title=None):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def save(fig, out, name):
    fig.tight_layout()
    fig.savefig(os.path.join(out, name), dpi=130)
    plt.close(fig)


def load(path):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if r["status"] == "completed"]


def groups(rows, series):
    out = defaultdict(list)
    for r in rows:
        if r["series"] == series:
            out[(r["method"], float(r["friction"]))].append(r)
    for key in out:
        out[key].sort(key=lambda r: int(r["dofs"]))
    return out


def plot_cube(rows, out):
    g = groups(rows, "cube")
    if not g:
        return
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    matvec = {}
    for (method, fc), rs in sorted(g.items()):
        color, marker = STYLE[method]
        x = [int(r["dofs"]) for r in rs]
        y = [float(r["step_s"]) for r in rs]
        ls = "-" if fc == 0 else "--"
        fill = color if fc == 0 else "none"
        p = slope(x, y) if len(x) >= 3 else math.nan
        label = f"{method}, f_c = {fc:g}" + (f" (p = {p:.2f})" if not math.isnan(p) else "")
        ax.loglog(x, y, ls, color=color, marker=marker, mfc=fill, label=label)
        ax2.semilogx(x, [float(r["step_over_matvec"]) for r in rs], ls, color=color,
                     marker=marker, mfc=fill, label=f"{method}, f_c = {fc:g}")
        for r in rs:
            matvec.setdefault(int(r["dofs"]), float(r["matvec_s"]))
    xs = sorted(matvec)
    ax.loglog(xs, [matvec[x] for x in xs], "k:", label=f"one K x (p = {slope(xs, [matvec[x] for x in xs]):.2f})")
    finish(ax, "dofs", "time per step [s]", "Hex8 cube on a flat floor: time per step")
    ax2.set_yscale("log")
    ax2.axhline(3.0, color="k", lw=0.8, ls=":")
    ax2.text(xs[0], 3.3, "target for explicit: 3 K x", fontsize=7)
    finish(ax2, "dofs", "time per step / time of one K x", "step cost in units of one sparse K x")
    save(fig, out, "scaling_cube.png")


def plot_column(rows, out):
    g = groups(rows, "column")
    if not g:
        return
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    for (method, fc), rs in sorted(g.items()):
        color, marker = STYLE[method]
        x = [int(r["dofs"]) for r in rs]
        ls = "-" if fc == 0 else "--"
        fill = color if fc == 0 else "none"
        label = f"{method}, f_c = {fc:g}"
        ax.loglog(x, [float(r["step_s"]) for r in rs], ls, color=color, marker=marker, mfc=fill, label=label)
        ax2.semilogx(x, [float(r["newton_per_step"]) for r in rs], ls, color=color, marker=marker,
                     mfc=fill, label=label)
    finish(ax, "dofs (contact face fixed: 15 x 15 nodes)", "time per step [s]",
           "growing interior, fixed contact surface")
    finish(ax2, "dofs", "Newton iterations per step")
    save(fig, out, "scaling_column.png")


def plot_face(rows, out):
    g = groups(rows, "face")
    if not g:
        return
    fig, (ax, ax2, ax3) = plt.subplots(1, 3, figsize=(15, 4.6))
    factor = {}
    for (method, fc), rs in sorted(g.items()):
        color, marker = STYLE[method]
        x = [int(r["contact_nodes"]) for r in rs]
        y = [float(r["step_s"]) for r in rs]
        p = slope(x, y) if len(x) >= 3 else math.nan
        label = f"{method}, f_c = {fc:g}" + (f" (p = {p:.2f})" if not math.isnan(p) else "")
        ax.loglog(x, y, "-", color=color, marker=marker, label=label)
        ax2.semilogx(x, [float(r["step_over_factor"]) for r in rs], "-", color=color, marker=marker,
                     label=label)
        ax3.semilogx(x, [float(r["newton_per_step"]) for r in rs], "-", color=color, marker=marker,
                     label=label)
        for r in rs:
            factor.setdefault(int(r["contact_nodes"]), float(r["factor_s"]))
    xs = sorted(factor)
    ys = [factor[x] for x in xs]
    ax.loglog(xs, ys, "k:", label=f"one Cholesky of M (p = {slope(xs, ys):.2f})")
    finish(ax, "contact nodes", "time per step [s]", "slab on a plane, consistent mass")
    ax2.axhline(5.0, color="k", lw=0.8, ls=":")
    ax2.text(xs[0], 5.2, "target: 5 Cholesky factorizations of M", fontsize=7)
    finish(ax2, "contact nodes", "time per step / one Cholesky of M")
    finish(ax3, "contact nodes", "Newton iterations per step")
    save(fig, out, "scaling_face.png")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument("csv")
    parser.add_argument("--out", default=None, help="output directory (default: next to the CSV)")
    args = parser.parse_args()
    out = args.out or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out, exist_ok=True)
    rows = load(args.csv)
    plot_cube(rows, out)
    plot_column(rows, out)
    plot_face(rows, out)


if __name__ == "__main__":
    main()
