#!/usr/bin/python3
"""Accuracy per cost of linear (T3) and quadratic (T6, curved) elements on the 2D Hertz
problem of hertz-example (cylinder on a rigid plane, plane strain): runs
`hertz-example OUT ORDER N...` for both orders, collects the errors of the peak pressure
p0 (at the node x = 0) and the half-width a (least-squares fit of the profile) against dofs and CPU seconds (mesh + assembly + solve), writes
quadratic_hertz.csv and quadratic_hertz.png into the output directory.

    /usr/bin/python3 benchmarks/contact/quadratic_hertz.py build/bin OUT_DIR
"""
import csv
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SIZES = {1: [5, 10, 20, 40], 2: [2, 3, 5, 10]}  # elements per half-width a


def run(bin_dir, out, order):
    subprocess.run([os.path.join(bin_dir, "hertz-example"), out, str(order)]
                   + [str(n) for n in SIZES[order]], check=True, stdout=subprocess.DEVNULL)
    name = "hertz_table_order2.csv" if order == 2 else "hertz_table.csv"
    with open(os.path.join(out, name)) as f:
        rows = list(csv.DictReader(f))
    result = []
    for r in rows:
        n = int(float(r["a_over_h"]))
        profile = os.path.join(out, f"hertz_pressure_a_over_h_{n}"
                               + ("_order2" if order == 2 else "") + ".csv")
        a_fit = half_width_fit(profile, float(r["a_exact_m"]), float(r["p0_exact_Pa"]))
        result.append({
            "element": "T6" if order == 2 else "T3",
            "a_over_h": n,
            "dofs": int(float(r["dofs"])),
            "cpu_seconds": float(r["cpu_seconds"]),
            "p0_error": abs(float(r["p0_Pa"]) / float(r["p0_exact_Pa"]) - 1),
            "a_error": abs(a_fit / float(r["a_exact_m"]) - 1),
        })
    return result


def half_width_fit(path, a, p0):
    """a from the least-squares line p^2 = A - B x^2 through the loaded nodes but the
    last (whose tributary segment straddles the edge of contact): a = sqrt(A / B)."""
    with open(path) as f:
        rows = [(float(r["x_m"]), float(r["p_computed_Pa"])) for r in csv.DictReader(f)]
    loaded = [(x, p) for x, p in sorted(rows) if p > 0][:-1]
    n = len(loaded)
    sx = sum(-(x / a) ** 2 for x, _ in loaded)
    sxx = sum((x / a) ** 4 for x, _ in loaded)
    sy = sum((p / p0) ** 2 for _, p in loaded)
    sxy = sum(-(x / a) ** 2 * (p / p0) ** 2 for x, p in loaded)
    det = n * sxx - sx * sx
    A, B = (sxx * sy - sx * sxy) / det, (n * sxy - sx * sy) / det
    return a * (A / B) ** 0.5


def main():
    bin_dir, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:  # hertz-example's own CSV files
        rows = run(bin_dir, scratch, 1) + run(bin_dir, scratch, 2)
    with open(os.path.join(out, "quadratic_hertz.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, x in zip(axes, ["dofs", "cpu_seconds"]):
        for element, style in [("T3", "o-"), ("T6", "s-")]:
            sel = [r for r in rows if r["element"] == element]
            for key, colour in [("p0_error", "C0"), ("a_error", "C1")]:
                ax.loglog([r[x] for r in sel], [max(r[key], 1e-7) for r in sel], style,
                          color=colour, mfc="none" if element == "T3" else colour,
                          label=f"{element} {key.replace('_error', '')}")
        ax.set_xlabel("unknowns" if x == "dofs" else "CPU seconds (mesh, assembly, solve)")
        ax.set_ylabel("relative error")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Hertz cylinder on a plane (plane strain): linear vs quadratic triangles")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "quadratic_hertz.png"), dpi=120)
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
