#!/usr/bin/python3
"""Hertz contact of a cylinder on a rigid plane: computed contact pressure against
p(x) = p0 sqrt(1 - x^2/a^2), from the CSV files of `hertz-example OUT_DIR`.

usage: /usr/bin/python3 examples/plot/plot_hertz.py OUT_DIR [FIGURE.png]
"""
import csv
import glob
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    out_dir = sys.argv[1]
    figure = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out_dir, "hertz_pressure.png")
    files = sorted(glob.glob(os.path.join(out_dir, "hertz_pressure_a_over_h_*.csv")),
                   key=lambda f: int(f.rsplit("_", 1)[1].split(".")[0]))
    if not files:
        sys.exit(f"plot_hertz: no hertz_pressure_a_over_h_*.csv in {out_dir}")
    fig, ax = plt.subplots(figsize=(7, 4.2))
    exact_drawn = False
    markers = ["o", "s", "^", "v"]
    for i, name in enumerate(files):
        with open(name) as f:
            rows = list(csv.DictReader(f))
        x = [float(r["x_over_a"]) for r in rows]
        p = [float(r["p_computed_Pa"]) / 1e9 for r in rows]
        if not exact_drawn:
            import math
            xs = [k / 200 * 1.5 for k in range(201)]
            p0 = float(rows[0]["p_exact_Pa"]) / 1e9 / math.sqrt(max(1e-300, 1 - x[0] ** 2))
            ax.plot(xs, [p0 * math.sqrt(max(0.0, 1 - t * t)) for t in xs], "k-", lw=1.5,
                    label="exact $p_0\\sqrt{1 - x^2/a^2}$")
            exact_drawn = True
        label = "a/h = " + name.rsplit("_", 1)[1].split(".")[0]
        ax.plot(x, p, markers[i % len(markers)], ms=4, mfc="none", label=label)
    ax.set_xlim(0, 1.5)
    ax.set_xlabel("x / a  (a = exact contact half-width)")
    ax.set_ylabel("contact pressure [GPa]")
    ax.set_title("Hertz, cylinder on a rigid plane (plane strain)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(figure, dpi=100)
    print(figure)


if __name__ == "__main__":
    main()
