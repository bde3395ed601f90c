#!/usr/bin/python3
"""Time of each step method and of `auto` on every example scene, in one run.

    /usr/bin/python3 benchmarks/contact/step_cost.py [--build build] [--out DIR] [SCENE.toml ...]

Runs `contact-sim SCENE --json --no-output --quiet --step M` for M in explicit (lumped mass
only), condensed, sparse and auto, one after the other, and writes DIR/step_cost.csv (one row
per scene and method: wall seconds of the run as contact-sim measures it, its CPU seconds
(cpu_seconds: set-up included), the phases, Newton and GMRES iterations, solves with M, steps
outside their accuracy, auto's prediction per step) and DIR/step_cost.md (the table: CPU time
of each method, auto's choice, auto / fastest among the methods that solve the same step).
Every run with OMP_NUM_THREADS=1: on a machine shared with other jobs the wall time counts the
time they held the cores, the CPU time of one thread does not. --table-only rewrites the
table from the CSV.
A run that fails or exceeds --timeout seconds is recorded with its status."""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def run(sim, scene, method, timeout):
    command = [sim, scene, "--json", "--no-output", "--quiet", "--step", method]
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                              env=dict(os.environ, OMP_NUM_THREADS="1"))
    except subprocess.TimeoutExpired:
        return {"status": "timeout > %g s" % timeout}
    if not done.stdout.strip():
        return {"status": "refused: " + done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "no output"}
    return json.loads(done.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "benchmarks/results/contact/step_cost"))
    parser.add_argument("--timeout", type=float, default=600.0)
    parser.add_argument("--table-only", action="store_true", help="rewrite step_cost.md from step_cost.csv")
    parser.add_argument("scenes", nargs="*")
    args = parser.parse_args()
    if args.table_only:
        write_table(list(csv.DictReader(open(os.path.join(args.out, "step_cost.csv")))),
                    os.path.join(args.out, "step_cost.md"))
        return 0
    sim = os.path.join(args.build, "bin", "contact-sim")
    scenes = args.scenes or sorted(
        os.path.join(ROOT, "examples/scenes", f)
        for f in os.listdir(os.path.join(ROOT, "examples/scenes")) if f.endswith(".toml"))
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for scene in scenes:
        mass = "lumped" if 'mass = "lumped"' in open(scene).read() else "consistent"
        methods = (["explicit"] if mass == "lumped" else []) + ["condensed", "sparse", "auto"]
        for method in methods:
            j = run(sim, scene, method, args.timeout)
            phases = {k: j.get(k + "_seconds", "") for k in ("assembly", "mass_solve", "contact_solve", "accuracy_check")}
            predicted = {k: j.get("predicted_%s_step_seconds" % k, "") for k in ("explicit", "condensed", "sparse")}
            predicted["auto_choice"] = j.get("auto_choice", "")
            row = {
                "scene": os.path.basename(scene), "mass": mass, "method": method,
                "ran": j.get("step_method", ""), "status": j.get("status", ""),
                "seconds": j.get("seconds", ""), "cpu_seconds": j.get("cpu_seconds", ""),
                "steps": j.get("steps", ""),
                "assembly_s": phases.get("assembly", ""), "mass_solves_s": phases.get("mass_solve", ""),
                "contact_solve_s": phases.get("contact_solve", ""),
                "accuracy_check_s": phases.get("accuracy_check", ""),
                "mass_solves": j.get("mass_solves", ""), "newton_iterations": j.get("newton_iterations", ""),
                "krylov_iterations": j.get("krylov_iterations", ""),
                "inaccurate_steps": j.get("inaccurate_steps", ""), "dofs": j.get("free_dofs", ""),
                "contact_nodes": j.get("contact_nodes", ""),
                "predicted_explicit_s": predicted.get("explicit", ""),
                "predicted_condensed_s": predicted.get("condensed", ""),
                "predicted_sparse_s": predicted.get("sparse", ""),
                "auto_choice": predicted.get("auto_choice", ""),
                "friction_coefficient": j.get("friction_coefficient", ""),
                "friction_formulation": j.get("friction_formulation", ""),
            }
            rows.append(row)
            print(",".join(str(row[k]) for k in ("scene", "method", "ran", "status", "seconds", "cpu_seconds",
                                                   "newton_iterations", "inaccurate_steps")), flush=True)
    with open(os.path.join(args.out, "step_cost.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    write_table(rows, os.path.join(args.out, "step_cost.md"))
    return 0


def same_step(row):
    """The explicit step solves the same step as the others only frictionless or with the
    lagged bound (with implicit Coulomb it would use the lagged bound instead)."""
    return row["method"] != "explicit" or float(row.get("friction_coefficient") or 0) == 0 or \
        row.get("friction_formulation") == "lagged-bound"


def write_table(rows, path):
    """The table of CPU seconds (wall seconds for a CSV without them)."""
    for r in rows:
        t = r.get("cpu_seconds") if r.get("cpu_seconds") not in ("", None) else r["seconds"]
        r["seconds"] = float(t) if t not in ("", None) else ""
    with open(path, "w") as f:
        f.write("| scene | dofs | contact nodes | mass | explicit [s] | condensed [s] | sparse [s] | "
                "auto [s] (ran) | auto / fastest | condensed / sparse |\n|---|---|---|---|---|---|---|---|---|---|\n")
        for scene in dict.fromkeys(r["scene"] for r in rows):
            by = {r["method"]: r for r in rows if r["scene"] == scene}
            ok = lambda m: m in by and by[m]["status"] == "completed"
            cell = lambda m: (("%.3f" % by[m]["seconds"]) + ("" if same_step(by[m]) else " (lagged bound)")) \
                if ok(m) else (by[m]["status"] if m in by else "-")
            times = [by[m]["seconds"] for m in ("explicit", "condensed", "sparse") if ok(m) and same_step(by[m])]
            a = by.get("auto", {})
            ratio = ("%.2f" % (a["seconds"] / min(times))) if ok("auto") and times else "-"
            cs = ("%.2f" % (by["condensed"]["seconds"] / by["sparse"]["seconds"])) if ok("condensed") and ok("sparse") else "-"
            any_row = next(iter(by.values()))
            f.write("| %s | %s | %s | %s | %s | %s | %s | %s (%s) | %s | %s |\n" % (
                scene, any_row["dofs"], any_row["contact_nodes"], any_row["mass"], cell("explicit"),
                cell("condensed"), cell("sparse"), cell("auto"), a.get("ran", ""), ratio, cs))


if __name__ == "__main__":
    sys.exit(main())
