#!/usr/bin/python3
"""Consistent against lumped mass on every closed-form scene: error against the closed form
and time, in one run.

    /usr/bin/python3 benchmarks/contact/mass_table.py [--build build] [--out DIR] [--full]

1. `contact-physics-check --quick` (or the full sweep with --full): free fall, incline above
   and below the friction angle, thrown block, bar impact; E, dt / dt_crit, 2D and 3D, each
   with the lumped and the consistent mass and every other setting the library default. The
   error per run: |measured - closed form| / |closed form| (incline below the angle: the
   slip after the ramp over the block's elastic shear deformation, as the check measures it).
2. The rolling cylinders of examples/scenes (Tet4 and Hex8) with their rigid-body closed
   form: a cylinder thrown without spin along a floor loses 1/3 of its kinetic energy to
   friction before it rolls. Each runs as written (consistent mass) and with
   `mass = "lumped"`; error: |friction dissipation at the end / initial energy - 1/3| over
   1/3; the initial energy from the energy balance of the first step.
Writes DIR/mass_physics.csv (the check's own table), DIR/mass_table.csv (one row per run:
case, mass, measured value, error, seconds) and DIR/mass_table.md (consistent and lumped side by side, and
per check the median error and time of each mass). Every run with OMP_NUM_THREADS=1."""
import argparse
import csv
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ENV = dict(os.environ, OMP_NUM_THREADS="1")
# The rolling cylinders (Tet4 and unstructured Hex8); not the faceted soft sphere, which
# rocks from node to node and dissipates 0.41 instead of the smooth rigid sphere's 2/7
# (docs/contact.md).
ROLLING = {"cylinder_rolling_3d.toml": 1.0 / 3.0, "cylinder_hex8_rolling_3d.toml": 1.0 / 3.0}


def physics_rows(build, out, full):
    path = os.path.join(out, "mass_physics.csv")
    command = [os.path.join(build, "bin", "contact-physics-check"), "--csv", path]
    if not full:
        command.append("--quick")
    subprocess.run(command, env=ENV, capture_output=True, text=True)  # exit 1 if a check fails
    rows = []
    lines = list(csv.reader(open(path)))
    header = lines[0]
    for fields in lines[1:]:
        # The check's CSV does not quote its check names ("incline, slides"): one field more.
        if len(fields) == len(header) + 1:
            fields = [fields[0] + "," + fields[1]] + fields[2:]
        r = dict(zip(header, fields))
        measured, expected = float(r["measured"]), float(r["expected"])
        if r["check"] == "incline, sticks":
            m = re.search(r"= ([0-9.e+-]+) of the elastic", r["detail"])
            error = float(m.group(1)) if m else float("nan")
        else:
            error = abs(measured - expected) / abs(expected)
        case = "%s, %dD, E = %s, dt = %s dt_crit" % (r["check"], int(r["dim"]), r["young_modulus"],
                                                      r["dt_fraction"])
        rows.append({"case": case, "check": r["check"], "measured": measured, "mass": r["mass"],
                     "passed": r["passed"],
                     "status": r["status"], "error": error, "seconds": float(r["seconds"]),
                     "cpu_seconds": "", "steps": r["steps"]})
    return rows


def steps_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        return [dict(zip(header, map(float, line.split(",")))) for line in f if line.strip()]


def rolling_rows(build, scenes_dir):
    rows = []
    for name, closed in ROLLING.items():
        text = open(os.path.join(scenes_dir, name)).read()
        text = re.sub(r'file = "([^"]+)"', lambda m: 'file = "%s"' % os.path.join(scenes_dir, m.group(1)), text)
        for mass in ("consistent", "lumped"):
            variant = text.replace('mass = "consistent"', 'mass = "%s"' % mass)
            assert 'mass = "%s"' % mass in variant
            with tempfile.TemporaryDirectory() as d:
                scene = os.path.join(d, name)
                open(scene, "w").write(variant)
                done = subprocess.run([os.path.join(build, "bin", "contact-sim"), scene, "--json", "--quiet",
                                       "--output", os.path.join(d, "out")],
                                      env=ENV, capture_output=True, text=True)
                j = json.loads(done.stdout)
                s = steps_csv(os.path.join(d, "out", "steps.csv"))
            first, last = s[0], s[-1]
            energy0 = (first["kinetic_energy"] + first["strain_energy"] + first["friction_dissipation"]
                       - first["external_work"] - first["normal_contact_work"])
            fraction = last["friction_dissipation"] / energy0
            rows.append({"case": "%s, friction dissipation / E0 (closed form %.4f)" % (name, closed),
                         "check": name, "measured": fraction, "mass": mass, "passed": int(j["status"] == "completed"),
                         "status": j["status"], "error": abs(fraction - closed) / closed,
                         "seconds": j["seconds"], "cpu_seconds": j.get("cpu_seconds", ""),
                         "steps": j["steps"]})
            print(name, mass, rows[-1]["error"], j["seconds"], j.get("cpu_seconds"), flush=True)
    return rows


def write_table(rows, path):
    with open(path, "w") as f:
        f.write("| case | error consistent | error lumped | time consistent [s] | time lumped [s] |\n"
                "|---|---|---|---|---|\n")
        cases = dict.fromkeys(r["case"] for r in rows)
        for case in cases:
            by = {r["mass"]: r for r in rows if r["case"] == case}
            if set(by) != {"consistent", "lumped"}:
                continue
            t = lambda r: float(r["cpu_seconds"]) if r["cpu_seconds"] not in ("", None) else float(r["seconds"])
            f.write("| %s | %.2e%s | %.2e%s | %.3f | %.3f |\n" % (
                case, float(by["consistent"]["error"]), "" if int(by["consistent"]["passed"]) else " (failed)",
                float(by["lumped"]["error"]), "" if int(by["lumped"]["passed"]) else " (failed)",
                t(by["consistent"]), t(by["lumped"])))
        f.write("\nPer check: median error and total time of each mass; runs where the lumped "
                "error is smaller / larger.\n\n| check | runs | median error consistent | median error lumped | "
                "lumped smaller / larger | time consistent [s] | time lumped [s] |\n|---|---|---|---|---|---|---|\n")
        for check in dict.fromkeys(r["check"] for r in rows):
            pairs = []
            for case in cases:
                by = {r["mass"]: r for r in rows if r["case"] == case and r["check"] == check}
                if set(by) == {"consistent", "lumped"}:
                    pairs.append(by)
            if not pairs:
                continue
            t = lambda r: float(r["cpu_seconds"]) if r["cpu_seconds"] not in ("", None) else float(r["seconds"])
            ec = [float(p["consistent"]["error"]) for p in pairs]
            el = [float(p["lumped"]["error"]) for p in pairs]
            smaller = sum(l < c for c, l in zip(ec, el))
            larger = sum(l > c for c, l in zip(ec, el))
            f.write("| %s | %d | %.2e | %.2e | %d / %d | %.2f | %.2f |\n" % (
                check, len(pairs), statistics.median(ec), statistics.median(el), smaller, larger,
                sum(t(p["consistent"]) for p in pairs), sum(t(p["lumped"]) for p in pairs)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "benchmarks/results/contact/mass"))
    parser.add_argument("--full", action="store_true", help="the full sweep of contact-physics-check")
    parser.add_argument("--table-only", action="store_true", help="rewrite mass_table.md from mass_table.csv")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    table_csv = os.path.join(args.out, "mass_table.csv")
    if args.table_only:
        write_table(list(csv.DictReader(open(table_csv))), os.path.join(args.out, "mass_table.md"))
        return 0
    rows = rolling_rows(args.build, os.path.join(ROOT, "examples", "scenes"))
    rows += physics_rows(args.build, args.out, args.full)
    with open(table_csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    write_table(rows, os.path.join(args.out, "mass_table.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
