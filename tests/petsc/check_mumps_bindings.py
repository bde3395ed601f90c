#!/usr/bin/python3
"""contact-sim with Ipopt's sequential MUMPS and PETSc's parallel MUMPS in one executable
(docs/petsc-contact.md, "Ipopt beside PETSc's parallel MUMPS"), by the dynamic linker's
own account (LD_DEBUG=bindings, one file per process):

* one process, solver.step = "ipopt" on a frictionless Tet4 box drop: the run completes,
  and libipopt's dmumps_c is bound to libdmumps_seq - never to the parallel libdmumps;
* 2 MPI ranks, the condensed step with friction and the consistent mass: on every rank
  PETSc's dmumps_c is bound to the parallel libdmumps and no MPI_* symbol to the
  sequential MUMPS's one-process stubs, the log
  says the solves with M are MUMPS's Cholesky factor ("preonly + cholesky (mumps)"), and
  the trajectory is the one-process contact-sim's: steps.csv's contact force sums and the
  final displacement.csv to 1e-9 of their largest value (the files print 10 digits; the
  1e-9 comparison without rounding is test_distributed_condensed's).

--asan (an AddressSanitizer build, whose dlopen refuses RTLD_DEEPBIND): the one-process
Ipopt run must instead stop with exit code 1 and say why, naming AddressSanitizer.
"""
import argparse
import glob
import json
import os
import subprocess
import sys

import numpy as np

SCENE = """
name = "box-drop-mumps"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [0.2, 0.2, 0.1]
cells = [4, 3, 2]
element = "tet4"
contact = ["zmin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
mass = "consistent"
[loads]
body_force = [30000.0, 8000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = -0.001
normal_source = "obstacle"
{friction}
[time]
dt = 5e-5
end_time = {end_time}
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[solver]
step = "{step}"
"""
SAME = 1e-9  # relative to the largest value: the CSV files print 10 significant digits
# Ipopt's QP solution against the condensed step's (both to the step's accuracy, ~1e-10 of
# the forces), relative to the largest value.
SAME_QP = 1e-8


def write_scene(workdir, name, step, friction, end_time):
    path = os.path.join(workdir, name)
    with open(path, "w") as f:
        f.write(SCENE.format(step=step, friction=friction, end_time=end_time))
    return path


def all_bindings(prefix):
    """(file, caller, callee, symbol) of every binding in the LD_DEBUG_OUTPUT files
    prefix.PID (one per process; libraries by file name)."""
    for path in glob.glob(prefix + ".*"):
        with open(path, errors="replace") as f:
            for line in f:
                if "binding file" not in line or "symbol `" not in line:
                    continue
                words = line.split()
                caller = os.path.basename(words[words.index("file") + 1])
                callee = os.path.basename(words[words.index("to") + 1])
                yield path, caller, callee, line.rsplit("`", 1)[1].rstrip("'\n")


def bindings(prefix, symbol):
    """{(file, caller): callee} of `symbol` (see all_bindings)."""
    return {(path, caller): callee
            for path, caller, callee, name in all_bindings(prefix) if name == symbol}


def traced(workdir, name):
    prefix = os.path.join(workdir, name)
    for old in glob.glob(prefix + ".*"):
        os.remove(old)
    return prefix, dict(os.environ, LD_DEBUG="bindings", LD_DEBUG_OUTPUT=prefix)


def load(directory, name):
    return np.loadtxt(os.path.join(directory, name), delimiter=",", skiprows=1, ndmin=2)


def columns_of(directory, name, columns=None):
    """The CSV file's columns (names; None: all) as an array."""
    values = load(directory, name)
    if columns is None:
        return values
    with open(os.path.join(directory, name)) as f:
        header = f.readline().strip().split(",")
    return values[:, [header.index(c) for c in columns]]


def largest_difference(dir_a, dir_b, name, columns=None):
    """max |a - b| / max |b| over the columns (names; None: all) of the CSV file name."""
    a, b = columns_of(dir_a, name, columns), columns_of(dir_b, name, columns)
    assert a.shape == b.shape and len(a) > 1, (name, a.shape, b.shape)
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return (np.abs(a - b) / scale).max()


FORCE_SUMS = ("normal_force_sum", "friction_force_sum")


def check_ipopt_serial(a):
    # 50 steps: the box lands at 2 ms. (Later, at a contact switch, Ipopt's interior
    # point misses the step's contact accuracy: accuracy-not-reached, as before.)
    scene = write_scene(a.workdir, "ipopt.toml", "ipopt", "", 0.0025)
    ipopt_dir = os.path.join(a.workdir, "ipopt")
    prefix, env = traced(a.workdir, "ld_ipopt")
    run = subprocess.run([a.contact_sim, scene, "--json", "--output", ipopt_dir], env=env,
                         capture_output=True, text=True, timeout=300)
    if a.asan:
        assert run.returncode == 1, (run.returncode, run.stderr)
        assert "AddressSanitizer" in run.stderr, run.stderr
        return "Ipopt refused under AddressSanitizer, with the reason"
    assert run.returncode == 0, (run.returncode, run.stderr)
    summary = json.loads(run.stdout)
    assert summary["status"] == "completed" and summary["step_method"] == "ipopt", summary
    calls = bindings(prefix, "dmumps_c")
    ipopt = {k: v for k, v in calls.items() if k[1].startswith("libipopt")}
    assert ipopt and all(v.startswith("libdmumps_seq") for v in ipopt.values()), calls
    # The same steps by the condensed step (CHOLMOD and ncp): Ipopt's answers.
    condensed_dir = os.path.join(a.workdir, "ipopt_condensed")
    subprocess.run([a.contact_sim, scene, "--quiet", "--step", "condensed", "--output",
                    condensed_dir], check=True, timeout=300)
    u = largest_difference(ipopt_dir, condensed_dir, "displacement.csv")
    forces = largest_difference(ipopt_dir, condensed_dir, "steps.csv", FORCE_SUMS[:1])
    landed = columns_of(condensed_dir, "steps.csv", FORCE_SUMS[:1]).max()
    assert landed > 0, landed
    assert u <= SAME_QP and forces <= SAME_QP, (u, forces)
    return (f"Ipopt step: {summary['steps']} steps, libipopt -> {sorted(set(ipopt.values()))}"
            f", u within {u:.2g} and normal force sums within {forces:.2g} of the "
            "condensed step's")


def check_condensed_ranks(a):
    scene = write_scene(a.workdir, "condensed.toml", "condensed",
                        "[friction]\ncoefficient = 0.3", 0.005)
    serial_dir = os.path.join(a.workdir, "serial")
    mpi_dir = os.path.join(a.workdir, "mpi2")
    subprocess.run([a.contact_sim, scene, "--quiet", "--output", serial_dir], check=True,
                   timeout=300)
    prefix, env = traced(a.workdir, "ld_mpi2")
    run = subprocess.run([a.mpiexec, "-n", "2", "--oversubscribe", "-x", "LD_DEBUG",
                          "-x", "LD_DEBUG_OUTPUT", a.contact_sim, scene, "--json", "--output",
                          mpi_dir], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, (run.returncode, run.stderr)
    summary = json.loads(run.stdout)
    assert summary["ranks"] == 2 and summary["status"] == "completed", summary
    assert summary["step_method"] == "condensed", summary
    lines = [l for l in run.stderr.splitlines() if "solves with M by" in l]
    assert len(lines) == 1 and "preonly + cholesky (mumps)" in lines[0], run.stderr

    # Every rank's PETSc: the parallel MUMPS and the real MPI_Init.
    mumps = {k: v for k, v in bindings(prefix, "dmumps_c").items()
             if k[1].startswith("libpetsc")}
    ranks = {k[0] for k in mumps}
    assert len(ranks) == 2, mumps
    assert all(v.startswith("libdmumps-") for v in mumps.values()), mumps
    # No MPI call of a rank reaches the one-process stubs of the sequential MUMPS.
    stubs = [b for b in all_bindings(prefix)
             if b[0] in ranks and b[3].startswith("MPI_") and "_seq" in b[2]]
    assert not stubs, stubs[:5]

    # The trajectory of one process.
    worst = max(largest_difference(mpi_dir, serial_dir, "steps.csv", FORCE_SUMS),
                largest_difference(mpi_dir, serial_dir, "displacement.csv"))
    assert worst <= SAME, worst
    return (f"2 ranks: PETSc -> {sorted(set(mumps.values()))}, M by "
            f"{lines[0].split('solves with M by')[1].split(';')[0].strip()}, "
            f"trajectory within {worst:.2g} of one process's")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--contact-sim", required=True)
    p.add_argument("--workdir", required=True)
    p.add_argument("--asan", action="store_true")
    a = p.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    print("ok:", check_ipopt_serial(a) + ";", check_condensed_ranks(a))
    return 0


if __name__ == "__main__":
    sys.exit(main())
