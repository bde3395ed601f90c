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

--mode sparse: the sparse frictional step (consistent mass, W = H S^-1 H' applied, never
formed) on the slab series of contact-scaling-bench --series face (scaling_bench.cpp): a
steel slab (E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3) of 5 m x 5 m, n x n x 8 Hex8 cells,
(n + 1)^2 contact nodes on its bottom face, resting on the floor z >= 0 (gap 0) and thrown
at it with v = (1, 0, -1) m/s, f_c = 0.3 (implicit Coulomb), dt = 0.3 h / c_p, tolerance
1e-10; `steps` steps. Per size three runs: contact-sim in one process (the serial sparse
step, CHOLMOD; `run` = serial), and `mpiexec -n R contact-sim --distributed` for each R of
--ranks (the PETSc step, MUMPS's Cholesky of M by default; `run` = distributed). Besides
the times, each distributed row has PETSc -log_view's factorization and solve counts and
times (max over ranks) and the largest difference of its final displacement
(displacement.csv, 10 digits) to the serial run's. Writes sparse_scaling.csv and
sparse_scaling.png:

    /usr/bin/python3 benchmarks/contact/mpi_scaling.py --mode sparse \\
        --contact-sim build/bin/contact-sim --cells 24 46 69 99 --steps 4 \\
        --out benchmarks/results/contact/scaling/mpi
"""
import argparse
import csv
import json
import math
import os
import re
import signal
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


SLAB_E, SLAB_RHO = 2.1e11, 7850.0  # the face series' steel [Pa], [kg/m^3]
SLAB_SIZE, SLAB_LAYERS = 5.0, 8  # slab edge [m], cells through its thickness


def slab_scene_text(n, steps):
    """The face series' slab (scaling_bench.cpp) as a scene file, sparse step."""
    h = SLAB_SIZE / n
    c_p = math.sqrt(SLAB_E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / SLAB_RHO)  # [m/s]
    dt = 0.3 * h / c_p
    return f"""
name = "mpi-slab-{n}"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [{SLAB_SIZE}, {SLAB_SIZE}, {h * SLAB_LAYERS!r}]
cells = [{n}, {n}, {SLAB_LAYERS}]
element = "hex8"
contact = ["zmin"]
[material]
young_modulus = {SLAB_E}
poisson_ratio = {NU}
density = {SLAB_RHO}
mass = "consistent"
[loads]
body_force = [0.0, 0.0, 0.0]
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = 0.0
[friction]
coefficient = 0.3
[time]
dt = {dt!r}
end_time = {steps * dt!r}
initial_state = "velocity"
initial_velocity = [1.0, 0.0, -1.0]
[solver]
step = "sparse"
friction = "coulomb-fc"
tolerance = 1e-10
[output]
snapshot_every = 0
"""


def log_view_event(log_path, name):
    """(count, seconds) of one event of PETSc -log_view: its count and its time, the
    maximum over ranks; (0, nan) when the event is not in the log."""
    with open(log_path) as f:
        for line in f:
            fields = line.split()
            if fields and fields[0] == name:
                return int(fields[1]), float(fields[3])
    return 0, float("nan")


def matmult_seconds(log_path):
    """One MatMult [s]: PETSc -log_view's MatMult time (max over ranks) / its count."""
    count, seconds = log_view_event(log_path, "MatMult")
    return (seconds / count if count else float("nan")), count


def descendants(pid):
    """The ids of pid's child processes and theirs (Linux /proc)."""
    out = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as f:
                out += [int(c) for c in f.read().split()]
    except OSError:
        return []
    return out + [d for c in out for d in descendants(c)]


def stop(proc):
    """Ends a case over --time-limit: SIGTERM to mpiexec or contact-sim (contact-sim stops
    after the step in progress; mpiexec passes the signal on to its ranks), then, after a
    grace of 30 s, SIGKILL to it and to every process it started (by their ids)."""
    family = descendants(proc.pid)
    proc.terminate()
    try:
        proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        pass
    for pid in [proc.pid] + family:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


def launch(args, case, ranks, log=None, quiet=True):
    """contact-sim on case/scene.toml: under mpiexec on `ranks` ranks (--distributed), or
    in one process without MPI (ranks = 0). Each process under /usr/bin/time (its peak
    resident set size [kB] and CPU time [s] into rss.RANK). Returns the --json summary,
    stderr, the seconds of steps.csv, the peak memory [MiB] and the CPU time per rank,
    the wall time and the load average before and after; over args.time_limit seconds the case is stopped and only
    {"time_limit": True}, the wall time and the load come back."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_mpi_yield_when_idle="1")  # (waiting ranks yield the core)
    if log:
        env["PETSC_OPTIONS"] = f"-log_view :{log}"
    rank = "$OMPI_COMM_WORLD_RANK" if ranks > 0 else "0"
    rank_cmd = (f'exec /usr/bin/time -f "%M %U %S" -o {case}/rss.{rank} '
                f'{args.contact_sim} {case}/scene.toml {"--distributed " if ranks else ""}'
                f'{"--quiet " if quiet else ""}--json --output {case}/out')
    cmd = ["sh", "-c", rank_cmd]
    if ranks > 0:
        cmd = [args.mpiexec, "-n", str(ranks), "--oversubscribe"] + cmd
    load_before = os.getloadavg()[0]
    start = time.time()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        stdout, stderr = proc.communicate(timeout=args.time_limit)
    except subprocess.TimeoutExpired:
        stop(proc)
        return {"time_limit": True, "wall": time.time() - start,
                "load_before": load_before, "load_after": os.getloadavg()[0]}
    wall = time.time() - start
    load_after = os.getloadavg()[0]
    with open(os.path.join(case, "stderr.txt"), "w") as f:
        f.write(stderr)
    if proc.returncode != 0:
        sys.stderr.write(stdout + stderr)
        raise SystemExit(f"mpi_scaling: {case} failed ({proc.returncode})")
    with open(os.path.join(case, "out", "steps.csv")) as f:
        seconds = [float(row["seconds"]) for row in csv.DictReader(f)]
    rss, cpu = [], []
    for r in range(max(1, ranks)):
        with open(os.path.join(case, f"rss.{r}")) as f:
            kib, user, system = f.read().split()[-3:]
        rss.append(int(kib) / 1024.0)  # MiB
        cpu.append(float(user) + float(system))  # [s]
    return {"summary": json.loads(stdout), "stderr": stderr, "seconds": seconds,
            "rss": rss, "cpu": cpu, "wall": wall, "load_before": load_before,
            "load_after": load_after}


def run_case(args, n, ranks, workdir):
    case = os.path.join(workdir, f"n{n}_r{ranks}")
    os.makedirs(case, exist_ok=True)
    with open(os.path.join(case, "scene.toml"), "w") as f:
        f.write(scene_text(n, args.steps))
    log = os.path.join(case, "log_view.txt")
    run = launch(args, case, ranks, log)
    if run.get("time_limit"):
        raise SystemExit(f"mpi_scaling: {case} over --time-limit {args.time_limit} s")
    summary, seconds, rss = run["summary"], run["seconds"], run["rss"]
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
        "wall_s": run["wall"], "load_before": run["load_before"],
        "load_after": run["load_after"],
    }


def read_displacement(path):
    """The last time's rows of displacement.csv: {node: (ux, uy, uz)} [m]."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]["time"]
    return {int(r["node"]): tuple(float(r[k]) for k in ("ux", "uy", "uz"))
            for r in rows if r["time"] == last}


def stderr_number(text, pattern):
    """The first number the regular expression's group catches in text, or nan."""
    m = re.search(pattern, text)
    return float(m.group(1)) if m else float("nan")


def run_sparse_case(args, n, ranks, workdir, serial):
    """One slab case: ranks = 0 the serial step, else the PETSc step on `ranks` ranks;
    serial: the serial row of this size (None for the serial run itself)."""
    case = os.path.join(workdir, f"slab{n}_{'serial' if ranks == 0 else f'r{ranks}'}")
    os.makedirs(case, exist_ok=True)
    with open(os.path.join(case, "scene.toml"), "w") as f:
        f.write(slab_scene_text(n, args.steps))
    log = os.path.join(case, "log_view.txt") if ranks else None
    run = launch(args, case, ranks, log, quiet=False)
    if run.get("time_limit"):
        return {"cells": n * n * SLAB_LAYERS, "dofs": 3 * (n + 1) ** 2 * (SLAB_LAYERS + 1),
                "contact_nodes": (n + 1) ** 2,
                "run": "serial" if ranks == 0 else "distributed", "ranks": max(1, ranks),
                "steps": 0, "status": f"stopped: over --time-limit {args.time_limit:g} s",
                "wall_s": run["wall"], "load_before": run["load_before"],
                "load_after": run["load_after"]}
    s, seconds, rss, err = run["summary"], run["seconds"], run["rss"], run["stderr"]
    steps = max(1, s["steps"])
    step = statistics.median(seconds[1:] if len(seconds) > 2 else seconds)
    u = read_displacement(os.path.join(case, "out", "displacement.csv"))
    u_max = max(abs(x) for v in u.values() for x in v)
    row = {
        "cells": n * n * SLAB_LAYERS, "dofs": s["dofs"], "contact_nodes": s["contact_nodes"],
        "run": "serial" if ranks == 0 else "distributed", "ranks": max(1, ranks),
        "steps": s["steps"], "status": s["status"], "time_per_step_s": step,
        "first_step_s": seconds[0] if seconds else float("nan"),
        "setup_s": run["wall"] - sum(seconds),
        "newton_steps": s["newton_iterations"],
        "newton_per_step": s["newton_iterations"] / steps,
        "gmres_per_step": s["krylov_iterations"] / steps,
    }
    if ranks == 0:
        # The serial sparse step solves with M twice per step besides its products.
        row["w_products_per_step"] = s["mass_solves"] / steps - 2
        row["mass_solver"] = "cholmod"
        row["factor_s"] = float("nan")
    else:
        products = stderr_number(err, r"sparse step on ranks: (\d+) products with W")
        row["w_products_per_step"] = products / steps
        m = re.search(r"solves with M by (.*?); factor ([0-9.e+-]+) s", err)
        row["mass_solver"] = m.group(1) if m else "?"
        row["factor_s"] = float(m.group(2)) if m else float("nan")
    # PETSc's events (max over ranks): the numeric factorization, the solves with the
    # factor, and the scatters (the contact gathers and scatters, MatMult's and MUMPS's
    # own right-hand side and solution moves).
    for key, event in (("chol_numeric", "MatCholFctrNum"), ("mat_solve", "MatSolve"),
                       ("scatter_end", "VecScatterEnd"), ("ksp_solve", "KSPSolve")):
        count, sec = log_view_event(log, event) if log else (0, float("nan"))
        row[f"{key}_count"], row[f"{key}_s"] = count, sec
    row["peak_rss_rank0_MiB"] = rss[0]
    row["peak_rss_other_ranks_MiB"] = max(rss[1:]) if len(rss) > 1 else float("nan")
    # Rank 0's peak after its serial set-up (the model with K and M, dt_crit, the start),
    # before the distribution.
    row["rank0_setup_peak_MiB"] = stderr_number(
        err, r"rank 0's peak memory: ([0-9.]+) MiB after its set-up")
    # CPU time of the whole run per rank (set-up included; waiting ranks poll, so on
    # ranks it also counts the waits): on a loaded machine wall times count the time
    # other processes held the cores.
    row["cpu_s_rank0"] = run["cpu"][0]
    row["cpu_s_other_ranks"] = max(run["cpu"][1:]) if len(rss) > 1 else float("nan")
    row["u_max_m"] = u_max
    if serial is None:
        row["u_diff_to_serial_m"] = 0.0
        row["time_over_serial"] = 1.0
        row["_u"] = u
    else:
        ref = serial.get("_u")  # (None: the serial run was stopped by --time-limit)
        row["u_diff_to_serial_m"] = max(
            abs(a - b) for node, v in u.items()
            for a, b in zip(v, ref[node])) if ref else float("nan")
        row["time_over_serial"] = step / serial.get("time_per_step_s", float("nan"))
    row["u_diff_relative"] = row["u_diff_to_serial_m"] / u_max if u_max > 0 else 0.0
    row.update(wall_s=run["wall"], load_before=run["load_before"],
               load_after=run["load_after"])
    return row


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


def plot_sparse(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    runs = [("serial", 1, "^", "one process (CHOLMOD)")] + [
        ("distributed", r, m, f"{r} rank{'s' if r > 1 else ''} (PETSc)")
        for r, m in ((1, "o"), (2, "s"), (3, "D"), (4, "v"))]
    for run, ranks, marker, label in runs:
        r = [x for x in rows
             if x["run"] == run and x["ranks"] == ranks and "time_per_step_s" in x]
        if not r:
            continue
        nodes = [x["contact_nodes"] for x in r]
        a.loglog(nodes, [x["time_per_step_s"] for x in r], marker + "-", label=label)
        b.loglog(nodes, [x["peak_rss_rank0_MiB"] for x in r], marker + "-",
                 label=label + (": rank 0" if ranks > 1 else ""))
        if ranks > 1:
            b.loglog(nodes, [x["peak_rss_other_ranks_MiB"] for x in r], marker + ":",
                     label=label + ": other ranks")
    load = max(max(x["load_before"], x["load_after"]) for x in rows)
    a.set_title(f"sparse step, slab series; load average up to {load:.1f}")
    a.set_xlabel("contact nodes")
    a.set_ylabel("time per step [s]")
    b.set_xlabel("contact nodes")
    b.set_ylabel("peak resident memory per rank [MiB]")
    for ax in (a, b):
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def write_results(rows, out, name, plot_rows):
    """The CSV (columns of the first row; keys starting with _ are not written) and the
    plot, after every case (a stopped run keeps its finished cases)."""
    widest = max(rows, key=len)  # (a case stopped by --time-limit has fewer columns)
    fields = [k for k in widest if not k.startswith("_")]
    with open(os.path.join(out, name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore", restval="nan")
        w.writeheader()
        w.writerows(rows)
    plot_rows(rows, os.path.join(out, name + ".png"))


def print_row(row):
    print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                    for k, v in row.items() if not k.startswith("_")), flush=True)


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mode", choices=["explicit", "sparse"], default="explicit",
                   help="explicit: Hex8 boxes, lumped mass; sparse: the slab series")
    p.add_argument("--contact-sim", required=True)
    p.add_argument("--mpiexec", default="mpiexec")
    p.add_argument("--cells", type=int, nargs="+", default=None,
                   help="cells along x and y (explicit: 24 46 80, z has half; sparse: "
                        "24 46 69 99, z has 8)")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--steps", type=int, default=None,
                   help="steps per case (explicit: 30, sparse: 4)")
    p.add_argument("--time-limit", type=float, default=None,
                   help="seconds per case; a sparse case over it is stopped and its row "
                        "says so (the series goes on), an explicit one ends the run")
    p.add_argument("--out", required=True, help="directory of the CSV and the plot")
    p.add_argument("--workdir", default="/tmp/mpi_scaling")
    args = p.parse_args()
    sparse = args.mode == "sparse"
    if args.cells is None:
        args.cells = [24, 46, 69, 99] if sparse else [24, 46, 80]
    if args.steps is None:
        args.steps = 4 if sparse else 30
    if args.steps < 1 or min(args.cells) < 1 or min(args.ranks) < 1:
        p.error("--steps, --cells and --ranks must be positive")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for n in args.cells:
        if sparse:
            serial = run_sparse_case(args, n, 0, args.workdir, None)
            rows.append(serial)
            print_row(serial)
            write_results(rows, args.out, "sparse_scaling", plot_sparse)
        for ranks in args.ranks:
            if sparse:
                row = run_sparse_case(args, n, ranks, args.workdir, serial)
            else:
                row = run_case(args, n, ranks, args.workdir)
                one = [x for x in rows if x["dofs"] == row["dofs"] and x["ranks"] == 1]
                row["efficiency"] = (
                    one[0]["time_per_step_s"] / (ranks * row["time_per_step_s"])
                    if one else float("nan"))
            rows.append(row)
            print_row(row)
            if sparse:
                write_results(rows, args.out, "sparse_scaling", plot_sparse)
            else:
                write_results(rows, args.out, "mpi_scaling", plot)


if __name__ == "__main__":
    main()
