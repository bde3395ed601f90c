#!/usr/bin/python3
"""The explicit contact step on MPI ranks (contact-sim under mpiexec, contact/petsc/) on Hex8
boxes of growing size, on 1 and 2 ranks: time per step, one K x (PETSc's MatMult), the
step in units of K x, peak memory per rank and the strong-scaling efficiency
t(1) / (R t(R)). One run writes mpi_scaling.csv (one row per size and rank count, column
`ranks`) and mpi_scaling.png; the load average of the machine before and after each case
goes into the CSV next to the times (on a shared machine the ranks do not get a core each,
and the efficiency is then not the idle machine's).

The scene: a steel box L x L x L/2 of n x n x n/2 Hex8 cells, its side xmin on a roller
(x fixed), dropped at 0.5 m/s onto a plane 1 mm below it with f_c = 0.3 and a sideways body
force (it lands and slides within the run), dt = 0.3 h / c_p; `steps` steps. The 1-rank
case is `mpiexec -n 1 contact-sim --distributed` (the PETSc code path on one rank).

    /usr/bin/python3 benchmarks/contact/mpi_scaling.py --contact-sim build/bin/contact-sim \\
        --cells 24 46 80 --out benchmarks/results/contact/scaling/mpi
"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys
import time

E, NU, RHO = 2.0e11, 0.3, 7800.0  # steel [Pa], [-], [kg/m^3]
SIZE = 1.0  # box edge L [m]


def scene_text(n, steps):
    h = SIZE / n
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    c_p = math.sqrt((lam + E / (1 + NU)) / RHO)  # P-wave speed [m/s]
    dt = 0.3 * h / c_p
    return f"""
name = "mpi-scaling-{n}"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [{SIZE}, {SIZE}, {SIZE / 2}]
cells = [{n}, {n}, {max(1, n // 2)}]
element = "hex8"
contact = ["zmin"]
fixed = ["xmin"]
fixed_components = [0]
[material]
young_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
mass = "lumped"
[loads]
body_force = [20000.0, 5000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = -0.0001
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = {dt!r}
end_time = {steps * dt * (1 + 1e-9)!r}
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[solver]
step = "explicit"
[output]
snapshot_every = 0
"""


def matmult_seconds(log_path):
    """One MatMult [s]: PETSc -log_view's MatMult time (max over ranks) / its count."""
    with open(log_path) as f:
        for line in f:
            fields = line.split()
            if fields and fields[0] == "MatMult":
                count, seconds = int(fields[1]), float(fields[3])
                return seconds / count, count
    return float("nan"), 0


def run_case(args, n, ranks, workdir):
    case = os.path.join(workdir, f"n{n}_r{ranks}")
    os.makedirs(case, exist_ok=True)
    scene = os.path.join(case, "scene.toml")
    with open(scene, "w") as f:
        f.write(scene_text(n, args.steps))
    log = os.path.join(case, "log_view.txt")
    env = dict(os.environ, OMP_NUM_THREADS="1", PETSC_OPTIONS=f"-log_view :{log}",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_mpi_yield_when_idle="1")  # (waiting ranks yield the core)
    # Each rank under /usr/bin/time: its own peak resident set size [kB] into rss.RANK.
    rank_cmd = (f'exec /usr/bin/time -f %M -o {case}/rss.$OMPI_COMM_WORLD_RANK '
                f'{args.contact_sim} {scene} --distributed --quiet --json '
                f'--output {case}/out')
    cmd = [args.mpiexec, "-n", str(ranks), "--oversubscribe", "sh", "-c", rank_cmd]
    load_before = os.getloadavg()[0]
    start = time.time()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.time() - start
    load_after = os.getloadavg()[0]
    if done.returncode != 0:
        sys.stderr.write(done.stdout + done.stderr)
        raise SystemExit(f"mpi_scaling: n = {n}, {ranks} ranks failed ({done.returncode})")
    import json
    summary = json.loads(done.stdout)
    with open(os.path.join(case, "out", "steps.csv")) as f:
        seconds = [float(row["seconds"]) for row in csv.DictReader(f)]
    rss = []
    for r in range(ranks):
        with open(os.path.join(case, f"rss.{r}")) as f:
            rss.append(int(f.read().split()[-1]) / 1024.0)  # MiB
    kx, count = matmult_seconds(log)
    step = statistics.median(seconds[1:] if len(seconds) > 2 else seconds)
    return {
        "cells": n * n * max(1, n // 2), "dofs": summary["dofs"],
        "free_dofs": summary["free_dofs"], "contact_nodes": summary["contact_nodes"],
        "ranks": ranks, "steps": len(seconds), "status": summary["status"],
        "time_per_step_s": step, "matmult_s": kx, "matmult_calls": count,
        "step_over_matmult": step / kx if kx > 0 else float("nan"),
        "peak_rss_rank0_MiB": rss[0],
        "peak_rss_other_ranks_MiB": max(rss[1:]) if ranks > 1 else float("nan"),
        "wall_s": wall, "load_before": load_before, "load_after": load_after,
    }


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for ranks, marker in ((1, "o"), (2, "s")):
        r = [x for x in rows if x["ranks"] == ranks]
        a.loglog([x["dofs"] for x in r], [x["time_per_step_s"] for x in r], marker + "-",
                 label=f"{ranks} rank{'s' if ranks > 1 else ''}: step")
        a.loglog([x["dofs"] for x in r], [x["matmult_s"] for x in r], marker + ":",
                 label=f"{ranks} rank{'s' if ranks > 1 else ''}: one K x")
    a.set_xlabel("dofs")
    a.set_ylabel("seconds")
    a.legend()
    a.grid(True, which="both", alpha=0.3)
    eff = [x for x in rows if x["ranks"] == 2 and x.get("efficiency") == x.get("efficiency")]
    b.semilogx([x["dofs"] for x in eff], [x["efficiency"] for x in eff], "s-")
    b.axhline(0.8, color="gray", ls="--", label="goal 0.8 (idle machine)")
    b.set_ylim(0, 1.4)
    b.set_xlabel("dofs")
    b.set_ylabel("strong-scaling efficiency t1 / (2 t2)")
    load = max(max(x["load_before"], x["load_after"]) for x in rows)
    b.set_title(f"2 shared cores, load average up to {load:.1f}")
    b.legend()
    b.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--contact-sim", required=True)
    p.add_argument("--mpiexec", default="mpiexec")
    p.add_argument("--cells", type=int, nargs="+", default=[24, 46, 80],
                   help="cells along x (and y; z has half)")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--steps", type=int, default=30)
    p.add_argument("--out", required=True, help="directory of the CSV and the plot")
    p.add_argument("--workdir", default="/tmp/mpi_scaling")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for n in args.cells:
        for ranks in args.ranks:
            row = run_case(args, n, ranks, args.workdir)
            one = [x for x in rows if x["dofs"] == row["dofs"] and x["ranks"] == 1]
            row["efficiency"] = (one[0]["time_per_step_s"] / (ranks * row["time_per_step_s"])
                                 if one else float("nan"))
            rows.append(row)
            print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                            for k, v in row.items()), flush=True)
            with open(os.path.join(args.out, "mpi_scaling.csv"), "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
                w.writeheader()
                w.writerows(rows)
            plot(rows, os.path.join(args.out, "mpi_scaling.png"))  # (after every case)


if __name__ == "__main__":
    main()
