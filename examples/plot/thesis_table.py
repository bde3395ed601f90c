#!/usr/bin/python3
"""Tables 1-3 of the thesis (section 6) beside our runs.

  thesis_table.py OUTPUT_DIR VARIANT ...

Reads OUTPUT_DIR/VARIANT/run.json (contact-sim --json) and the repeated timing runs
OUTPUT_DIR/VARIANT/timing_*.json for every variant and writes OUTPUT_DIR/table.md and
OUTPUT_DIR/table.csv; prints the markdown table. t_comp is the fastest of the runs (the
median beside it), the speed-up the thesis' t_comp over our fastest. The thesis' values
(Python 3.6 on an Intel i5-7200U laptop, 2017) are the published ones.
"""
import csv
import glob
import json
import os
import statistics
import sys

# variant: (table, note, dt, f_c, k_sim, N_Jac, N_func, t_comp [s]); None = not given.
THESIS = {
    "t1_dt1e-4": ("1", "3D frictionless", 1e-4, 0, 200, 1314, 2689, 48.0),
    "t1_dt2e-4": ("1", "3D frictionless", 2e-4, 0, 100, 598, 1198, 22.3),
    "t1_dt1e-2": ("1", "3D frictionless", 1e-2, 0, None, None, None, None),
    "t2_curved_fc0": ("2", "2D, curved obstacle", 0.0025, 0, 100, 8919, 25727, 43.0),
    "t2_curved_fc0.5": ("2", "2D, curved obstacle", 0.0025, 0.5, 100, 34573, 106539, 146.2),
    "t2_curved_fc5": ("2", "2D, curved obstacle", 0.0025, 5, 100, 38680, 115899, 159.8),
    "t2_flat_fc0": ("2", "2D, flat obstacle", 0.0025, 0, 100, 5737, 16574, 29.6),
    "t2_flat_fc0.5": ("2", "2D, flat obstacle", 0.0025, 0.5, 100, 14659, 53590, 73.3),
    "t2_flat_fc5": ("2", "2D, flat obstacle", 0.0025, 5, 100, 41631, 126486, 188.3),
    "t3_fc0": ("3", "3D with friction", 5e-4, 0, 50, 10495, 126397, 76.1),
    "t3_fc0.5": ("3", "3D with friction", 5e-4, 0.5, 50, 33010, 301389, 172.9),
}


def fmt(v, spec="{}"):
    return "-" if v is None else spec.format(v)


def main():
    out_dir, variants = sys.argv[1], sys.argv[2:]
    header = ["table", "case", "dt [s]", "f_c", "k_sim", "N_Jac", "N_func", "t_comp [s]",
              "median [s] (runs)", "thesis k_sim", "thesis N_Jac", "thesis N_func",
              "thesis t_comp [s]", "speed-up", "status"]
    rows = []
    for v in variants:
        table, note, dt, fc, k, nj, nf, tc = THESIS[v]
        path = os.path.join(out_dir, v, "run.json")
        try:
            with open(path) as f:
                r = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            rows.append([table, note, f"{dt:g}", f"{fc:g}", "-", "-", "-", "-", "-", fmt(k), fmt(nj),
                         fmt(nf), fmt(tc), "-", f"no result ({e})"])
            continue
        status = r["status"]
        if status == "refused-unstable-time-step":
            status += f" (dt_crit = {r['critical_time_step']:.3g} s)"
        elif status != "completed":
            status += ": " + r["message"]
        done = r["status"] == "completed"
        times = [r["seconds"]]
        for timing in glob.glob(os.path.join(out_dir, v, "timing_*.json")):
            try:
                with open(timing) as f:
                    t = json.load(f)
                if t["status"] == "completed":
                    times.append(t["seconds"])
            except (OSError, json.JSONDecodeError, KeyError):
                pass
        fastest = min(times)
        rows.append([table, note, f"{r['dt']:g}", f"{r['friction_coefficient']:g}",
                     str(r["steps"]) if r["steps"] else "-",
                     str(r["jacobian_evaluations"]) if r["steps"] else "-",
                     str(r["residual_evaluations"]) if r["steps"] else "-",
                     f"{fastest:.4f}" if done else "-",
                     f"{statistics.median(times):.4f} ({len(times)})" if done else "-",
                     fmt(k), fmt(nj), fmt(nf), fmt(tc, "{:.1f}"),
                     f"{tc / fastest:.0f}" if done and tc else "-",
                     status + ("; thesis: unstable" if k is None else "")])
    with open(os.path.join(out_dir, "table.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out_dir, "table.md"), "w") as f:
        f.write(text)
    print(text, end="")


if __name__ == "__main__":
    main()
