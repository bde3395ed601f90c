#!/usr/bin/python3
"""Work-precision diagrams of the contact plug-in: error against the closed form versus CPU
seconds, one curve per configuration, on closed-form scenes, in one run.

    /usr/bin/python3 benchmarks/contact/work_precision.py [--build build] [--out DIR] [--quick]

Scenes (examples/validation, varied here; every error relative to the closed form):
- bar: an elastic bar (nu = 0) hits a rigid wall at v0; 1D waves: the contact lasts
  T = 2 L / c, c = sqrt(E / rho). Error |duration - T| / T, the duration = (steps with a
  contact force above 1 % of rho c v0 h) dt.
- sliding: a block slides on a floor with Coulomb friction mu from v0 under gravity and stops
  at t = v0 / (mu g). Error |t_stop - v0 / (mu g)| / (v0 / (mu g)), t_stop from a line fitted
  to the speed sqrt(2 E_kin / m) between 0.2 v0 and 0.8 v0.
- hertz3d: an elastic sphere (gmsh Tet4 / Tet10, generated here) hits a rigid plane at v0;
  Hertz: the contact lasts 2.9432 delta_max / v0, delta_max = (15 m v0^2 / (16 E* sqrt(R)))^(2/5),
  E* = E / (1 - nu^2). Error as for the bar, threshold 1 % of the Hertz peak force.
Configurations: mass consistent / lumped x step explicit (lumped only) / condensed / sparse /
auto x element linear (quad4, tet4) / quadratic (quad8, tet10), each on 2-4 meshes; a
refused configuration is a row with its status and message. dt = DT_FRACTION of
the configuration's own critical step (asked from contact-sim with a one-step run), so a
finer mesh or a consistent mass pays its smaller stable step.
Cost: the CPU seconds of the run as contact-sim measures them (--json cpu_seconds: model
build, set-up and steps, every thread), each run with OMP_NUM_THREADS=1.
Writes DIR/<scene>.csv and DIR/<scene>.png (log-log error against CPU seconds; the library
default - consistent mass, step auto, linear element - drawn black with its marks circled)
and DIR/summary.md: per scene and mesh, the default's CPU time against the fastest run of
any configuration at the same or a smaller error, and auto's predicted against its measured
seconds per step (steps' wall time / steps)."""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VALIDATION = os.path.join(ROOT, "examples", "validation")
ENV = dict(os.environ, OMP_NUM_THREADS="1")
E, RHO, G = 2e8, 7800.0, 9.81  # Pa, kg/m^3, m/s^2: the validation scenes' steel-like bar
DT_FRACTION = 0.5  # dt / dt_crit of every run
FRONT_TOLERANCE = 1.2  # the default is "on the front" within this factor of the fastest
COLUMNS = ["scene", "config", "mass", "step", "order", "element", "cells", "dt", "dt_crit", "status", "ran",
           "auto_choice", "steps", "dofs", "error", "measured", "exact", "cpu_seconds", "wall_seconds",
           "predicted_step_s", "measured_step_s"]


def replace(text, old, new):
    assert old in text, old
    return text.replace(old, new)


def steps_csv(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: np.atleast_1d(data[name]) for name in data.dtype.names}


def sim_run(sim, scene_text, workdir, args):
    """contact-sim on scene_text with extra args; the JSON summary (or a status dict)."""
    path = os.path.join(workdir, "scene.toml")
    with open(path, "w") as f:
        f.write(scene_text)
    done = subprocess.run([sim, path, "--json", "--quiet", *args], capture_output=True, text=True, env=ENV)
    if not done.stdout.strip():
        lines = done.stderr.strip().splitlines()
        return {"status": "refused", "message": lines[-1] if lines else "no output"}
    return json.loads(done.stdout)


# ------------------------------------------------------------------------------ scenes
class Bar:
    """Elastic bar L x h against a rigid wall: contact for 2 L / c (1D wave theory)."""
    name, file = "bar", "bar_impact.toml"
    L, h, v0 = 1.0, 0.1, 1.0
    elements = {"linear": "quad4", "quadratic": "quad8"}
    end_time = 0.016  # s: past 2 L / c = 12.49 ms

    def meshes(self, quick):
        return [10] if quick else [20, 40, 80, 160]

    def text(self, base, cells, element):
        t = replace(base, "cells = [40, 1]", "cells = [%d, 1]" % cells)
        return replace(t, 'element = "quad4"', 'element = "%s"' % element)

    def error(self, st, dt):
        c = math.sqrt(E / RHO)
        exact = 2 * self.L / c
        on = st["normal_force_sum"] > 0.01 * RHO * c * self.v0 * self.h
        duration = on.sum() * dt
        return abs(duration - exact) / exact, duration, exact


class Sliding:
    """Block sliding to rest with Coulomb friction: stops at v0 / (mu g)."""
    name, file = "sliding", "sliding_block.toml"
    mu, v0, width, height = 0.3, 1.0, 0.4, 0.1
    elements = {"linear": "quad4", "quadratic": "quad8"}
    end_time = 0.4  # s: past v0 / (mu g) = 0.340 s

    def meshes(self, quick):
        return [1] if quick else [1, 2]

    def text(self, base, cells, element):
        t = replace(base, "cells = [8, 2]", "cells = [%d, %d]" % (8 * cells, 2 * cells))
        return replace(t, 'element = "quad4"', 'element = "%s"' % element)

    def error(self, st, dt):
        exact = self.v0 / (self.mu * G)
        mass = RHO * self.width * self.height
        speed = np.sqrt(2 * np.maximum(st["kinetic_energy"], 0.0) / mass)
        fit = (speed > 0.2 * self.v0) & (speed < 0.8 * self.v0)
        slope, intercept = np.polyfit(st["time"][fit], speed[fit], 1)
        stop = -intercept / slope
        return abs(stop - exact) / exact, stop, exact


HERTZ_SCENE = """name = "work-precision-hertz-3d"
[geometry]
type = "msh"
file = "MESH"
dimension = 3
[material]
young_modulus = 1e7        # Pa
poisson_ratio = 0.3
density = 1000             # kg/m^3
mass = "lumped"
[obstacle]
type = "plane"
normal = [0.0, 1.0, 0.0]
offset = OFFSET            # m: the floor touches the lowest node
normal_source = "obstacle"
[time]
dt = 1e-5                  # s (replaced by --dt)
end_time = 0.01            # s
initial_state = "velocity"
initial_velocity = [0.0, -V0, 0.0]   # m/s
"""


class Hertz:
    """Elastic sphere (Tet4 / Tet10) hits a rigid plane: Hertz contact duration.
    2.9432 delta_max / v0, delta_max = (15 m v0^2 / (16 E* sqrt(R)))^(2/5), E* = E / (1 - nu^2)."""
    name, file = "hertz3d", None
    R, v0, young, nu, rho = 0.05, 2.0, 1e7, 0.3, 1000.0
    elements = {"linear": "tet4", "quadratic": "tet10"}
    end_time = 0.008  # s: past the contact duration 5.36 ms

    def __init__(self):
        self.meshdir = None

    def meshes(self, quick):
        return [0.02] if quick else [0.02, 0.014]  # gmsh element size [m]

    def mesh(self, size, element):
        """A gmsh sphere of radius R (msh2), generated once per size and order; its lowest y."""
        if self.meshdir is None:
            self.meshdir = tempfile.mkdtemp(prefix="work_precision_")
        order = 2 if element == "tet10" else 1
        path = os.path.join(self.meshdir, "sphere_%g_%d.msh" % (size, order))
        if not os.path.exists(path):
            geo = os.path.join(self.meshdir, "sphere.geo")
            open(geo, "w").write('SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, %g};\n'
                                 "Mesh.MeshSizeMin = %g;\nMesh.MeshSizeMax = %g;\n"
                                 'Physical Volume("body") = {1};\nPhysical Surface("contact") = {1};\n'
                                 % (self.R, size, size))
            subprocess.run(["gmsh", "-3", "-order", str(order), "-format", "msh2", geo, "-o", path],
                           check=True, capture_output=True)
        lines = open(path).read().split("$Nodes\n")[1].split("$EndNodes")[0].splitlines()[1:]
        return path, min(float(line.split()[2]) for line in lines)

    def text(self, base, size, element):
        path, ymin = self.mesh(size, element)
        return (HERTZ_SCENE.replace("MESH", path).replace("OFFSET", "%.16g" % ymin)
                .replace("V0", "%g" % self.v0))

    def error(self, st, dt):
        e_star = self.young / (1 - self.nu**2)
        m = self.rho * 4.0 / 3.0 * math.pi * self.R**3
        delta = (15 * m * self.v0**2 / (16 * e_star * math.sqrt(self.R))) ** 0.4
        exact = 2.9432 * delta / self.v0
        f_max = 4.0 / 3.0 * e_star * math.sqrt(self.R) * delta**1.5
        on = st["normal_force_sum"] > 0.01 * f_max
        duration = on.sum() * dt
        return abs(duration - exact) / exact, duration, exact


SCENES = [Bar(), Sliding(), Hertz()]


def configurations():
    for order in ("linear", "quadratic"):
        for mass in ("consistent", "lumped"):
            for step in (["explicit"] if mass == "lumped" else []) + ["condensed", "sparse", "auto"]:
                yield {"mass": mass, "step": step, "order": order,
                       "config": "%s %s %s" % (mass, step, order)}


def is_default(row):
    return row["mass"] == "consistent" and row["step"] == "auto" and row["order"] == "linear"


def run_case(sim, scene, base, cfg, cells):
    element = scene.elements[cfg["order"]]
    text = scene.text(base, cells, element)
    text = replace(text, 'mass = "lumped"', 'mass = "%s"' % cfg["mass"])
    row = {"scene": scene.name, "config": cfg["config"], "mass": cfg["mass"], "step": cfg["step"],
           "order": cfg["order"], "element": element, "cells": cells}
    with tempfile.TemporaryDirectory() as d:
        probe = sim_run(sim, text, d, ["--no-output", "--step", cfg["step"], "--dt", "1e-9", "--end-time", "1e-9"])
        dt_crit = probe.get("critical_time_step", float("nan"))
        if probe.get("status") != "completed" or not dt_crit > 0:
            row.update(status=probe.get("status", "refused"), ran=probe.get("message", "")[:120])
            return row
        dt = DT_FRACTION * dt_crit
        out = os.path.join(d, "out")
        j = sim_run(sim, text, d, ["--output", out, "--step", cfg["step"], "--dt", "%.9e" % dt,
                                   "--end-time", "%g" % scene.end_time])
        row.update(dt=dt, dt_crit=dt_crit, status=j.get("status"), ran=j.get("step_method", ""),
                   auto_choice=j.get("auto_choice", ""), steps=j.get("steps", ""), dofs=j.get("free_dofs", ""),
                   cpu_seconds=j.get("cpu_seconds", ""), wall_seconds=j.get("seconds", ""))
        if j.get("status") != "completed":
            row["ran"] = j.get("message", "")[:120]
            return row
        row["error"], row["measured"], row["exact"] = scene.error(steps_csv(os.path.join(out, "steps.csv")), dt)
    predicted = j.get("predicted_%s_step_seconds" % row["ran"], -1.0)
    row["predicted_step_s"] = predicted if predicted is not None and predicted > 0 else ""
    row["measured_step_s"] = j["seconds"] / j["steps"] if j.get("steps") else ""
    return row


# ------------------------------------------------------------------------------ output
def plot(rows, scene, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5))
    done = [r for r in rows if r["status"] == "completed" and r["error"] != "" and float(r["error"]) > 0]
    styles = {"linear": "-", "quadratic": "--"}
    markers = {"explicit": "s", "condensed": "^", "sparse": "v", "auto": "o"}
    colours = {"consistent": "C0", "lumped": "C1"}
    for config in dict.fromkeys(r["config"] for r in done):
        pts = sorted((float(r["cpu_seconds"]), float(r["error"])) for r in done if r["config"] == config)
        r0 = next(r for r in done if r["config"] == config)
        default = is_default(r0)
        ax.plot(*zip(*pts), styles[r0["order"]],
                marker=markers[r0["step"]], color="k" if default else colours[r0["mass"]],
                lw=2.2 if default else 1.0, ms=7 if default else 5, alpha=1.0 if default else 0.75,
                label=config + (" (default)" if default else ""))
        if default:
            ax.plot(*zip(*pts), "o", ms=14, mfc="none", mec="k")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU seconds of the run (one thread)")
    ax.set_ylabel("relative error against the closed form")
    ax.set_title(scene.__doc__.strip().split(":")[0])
    ax.grid(alpha=0.3, which="both")
    if done:
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def front_lines(rows):
    """Per scene and mesh of the default: its CPU time over the fastest completed run of any
    configuration whose error is at most the default's, and auto's prediction error."""
    lines = ["| scene | cells | default ran | default error | default CPU [s] | fastest at <= that error | "
             "its CPU [s] | default / fastest | auto predicted / measured s per step |",
             "|---|---|---|---|---|---|---|---|---|"]
    done = [r for r in rows if r["status"] == "completed" and r["error"] != ""]
    for d in (r for r in done if is_default(r)):
        err = float(d["error"])
        peers = [r for r in done if r["scene"] == d["scene"] and float(r["error"]) <= err]
        best = min(peers, key=lambda r: float(r["cpu_seconds"]))
        ratio = float(d["cpu_seconds"]) / float(best["cpu_seconds"])
        pred = ("%.2f" % (float(d["predicted_step_s"]) / float(d["measured_step_s"]))
                if d["predicted_step_s"] != "" and d["measured_step_s"] else "-")
        lines.append("| %s | %s | %s | %.2e | %.3f | %s (cells %s) | %.3f | %.2f%s | %s |" % (
            d["scene"], d["cells"], d["ran"], err, float(d["cpu_seconds"]), best["config"], best["cells"],
            float(best["cpu_seconds"]), ratio, " (off the front)" if ratio > FRONT_TOLERANCE else "", pred))
    lines += ["", "auto's prediction per run of step = auto (predicted / measured seconds per step, "
              "measured = the steps' wall seconds / steps):", "",
              "| scene | config | cells | chose | predicted [s/step] | measured [s/step] | ratio |",
              "|---|---|---|---|---|---|---|"]
    for r in done:
        if r["step"] == "auto" and r["predicted_step_s"] != "":
            lines.append("| %s | %s | %s | %s | %.2e | %.2e | %.2f |" % (
                r["scene"], r["config"], r["cells"], r["ran"], float(r["predicted_step_s"]),
                float(r["measured_step_s"]), float(r["predicted_step_s"]) / float(r["measured_step_s"])))
    return lines


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in COLUMNS})


def verify(out, scenes):
    """Every scene's CSV has the columns; every completed run a finite error and CPU time;
    each scene at least one completed run of the default. Returns the problems found."""
    problems = []
    for scene in scenes:
        rows = list(csv.DictReader(open(os.path.join(out, scene.name + ".csv"))))
        if not rows or list(rows[0]) != COLUMNS:
            problems.append("%s.csv: columns %s" % (scene.name, list(rows[0]) if rows else "none"))
            continue
        done = [r for r in rows if r["status"] == "completed"]
        for r in done:
            for k in ("error", "cpu_seconds", "dt", "dt_crit"):
                if not math.isfinite(float(r[k] or "nan")) or float(r[k] or "nan") < 0:
                    problems.append("%s %s cells %s: %s = %r" % (scene.name, r["config"], r["cells"], k, r[k]))
        if not any(is_default(r) for r in done):
            problems.append("%s: no completed run of the default" % scene.name)
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--sim", help="the contact-sim binary (default BUILD/bin/contact-sim)")
    parser.add_argument("--out", default=os.path.join(ROOT, "benchmarks/results/contact/work-precision"))
    parser.add_argument("--quick", action="store_true", help="one mesh per scene: a smoke run of ~1 minute")
    parser.add_argument("--no-plot", action="store_true")
    args = parser.parse_args()
    sim = args.sim or os.path.join(args.build, "bin", "contact-sim")
    scenes = [s for s in SCENES if s.file or shutil.which("gmsh")]
    if len(scenes) < len(SCENES):
        print("work_precision: no gmsh on PATH, the 3D Hertz scene is left out", file=sys.stderr)
    os.makedirs(args.out, exist_ok=True)
    everything = []
    for scene in scenes:
        base = open(os.path.join(VALIDATION, scene.file)).read() if scene.file else ""
        rows = []
        for cfg in configurations():
            for cells in scene.meshes(args.quick):
                rows.append(run_case(sim, scene, base, cfg, cells))
                r = rows[-1]
                print("%-8s %-30s cells %3s  %-10s err %-10s cpu %s" % (
                    scene.name, cfg["config"], cells, r["status"], r.get("error", ""), r.get("cpu_seconds", "")),
                    flush=True)
        write_csv(rows, os.path.join(args.out, scene.name + ".csv"))
        if not args.no_plot:
            plot(rows, scene, os.path.join(args.out, scene.name + ".png"))
        everything += rows
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(front_lines(everything)) + "\n")
    problems = verify(args.out, scenes)
    for p in problems:
        print("work_precision: " + p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
