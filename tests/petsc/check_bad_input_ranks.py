#!/usr/bin/python3
"""Bad input to `mpiexec -n 2 contact-sim SCENE.toml`, as a user meets it from the command
line ("bad partitions work or fail with a clear message; never a hang").

Each refused case must end on every rank within TIMEOUT seconds (never a hang) with a
non-zero exit code, a message on stderr that names the key or option, the value and what
is accepted, and no `completed` anywhere (no report; --json prints nothing or the
summary of a run that did not complete). The cases:
  * an unknown scene key, a value of the wrong type, a missing mesh file (refused by
    LoadScene on every rank: the message once, from rank 0);
  * dt above dt_crit with the lumped mass (dt_crit by Lanczos on the ranks) and with the
    consistent mass (dt_crit on rank 0);
  * steps contact-sim does not run on ranks: solver.step = "ipopt", the lagged-bound
    friction, compare_with_ipopt, --resume (solver.step = "full" is
    check_distributed_output.py's);
  * PETSC_OPTIONS: a KSP type that does not exist, preonly with a preconditioner that is
    not M^-1, a partitioner this PETSc lacks; and an option the run does not use (the
    explicit step has no solves with M) is a warning, the run completes.
And what must work:
  * more ranks than cells: one Hex8 cell on 2 ranks (rank 1 has no cell and no contact
    node), the explicit and the condensed step: completed, the serial run's force sums,
    two VTK pieces of which one is empty, read by VTK's parallel reader;
  * a rank with cells but no contact node: a column of 6 Hex8 cells split by the simple
    partitioner (rank 1 holds the upper cells: its piece has no point on the contact
    plane z = 0), the sparse step: completed, the serial run's force sums."""
import argparse
import concurrent.futures
import csv
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk

TIMEOUT = 120  # [s] per run: a hang fails the case
SAME = 1e-9  # relative: steps.csv prints 10 significant digits

BOX = """
name = "bad-input-box"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [0.2, 0.2, 0.1]
cells = [3, 3, 2]
element = "hex8"
contact = ["zmin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
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
dt = 2e-5
end_time = 2e-4
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[solver]
step = "explicit"
"""
CONSISTENT = BOX.replace('mass = "lumped"', 'mass = "consistent"').replace(
    'step = "explicit"', 'step = "condensed"')


def write(workdir, name, text):
    path = os.path.join(workdir, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(a, scene, *args, ranks=2, petsc_options=None):
    env = dict(os.environ)
    env.pop("PETSC_OPTIONS", None)
    if petsc_options:
        env["PETSC_OPTIONS"] = petsc_options
    command = [a.mpiexec, "-n", str(ranks), "--oversubscribe", a.contact_sim, scene,
               *args]
    try:
        return subprocess.run(command, capture_output=True, text=True, env=env,
                              timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        raise AssertionError(f"hangs: {' '.join(command)} did not end in {TIMEOUT} s")


def refused(a, name, scene, expected, *args, petsc_options=None, once=True):
    """The run ends non-zero with a message holding every string of `expected`, on one
    contact-sim line (once: printed by rank 0 only), and nothing says completed."""
    r = run(a, scene, "--no-output", "--json", *args, petsc_options=petsc_options)
    out = r.stdout + r.stderr
    assert r.returncode != 0, (name, r.returncode, out)
    assert "completed" not in out, (name, out)
    if r.stdout.strip():  # --json: a summary with the status (refused-unstable-time-step)
        assert json.loads(r.stdout)["status"] != "completed", (name, r.stdout)
    lines = [l for l in r.stderr.splitlines()
             if l.startswith("contact-sim:") and all(e in l for e in expected)]
    assert lines, (name, expected, r.stderr)
    if once:
        assert len(lines) == 1, (name, lines)
    assert "PETSC ERROR" not in out, (name, out)  # one line, not PETSc's traceback
    return f"{name}: exit {r.returncode}: {lines[0]}"


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def same_as_serial(a, name, scene, ranks_args=(), petsc_options=None):
    """The scene on 2 ranks completes with the serial run's per-step force sums; returns
    the output directory of the ranks' run."""
    serial, mpi = (os.path.join(a.workdir, name + s) for s in ("_serial", "_mpi2"))
    subprocess.run([a.contact_sim, scene, "--quiet", "--output", serial], check=True,
                   timeout=TIMEOUT, capture_output=True)
    r = run(a, scene, "--quiet", "--json", "--output", mpi, *ranks_args,
            petsc_options=petsc_options)
    assert r.returncode == 0, (name, r.returncode, r.stdout + r.stderr)
    summary = json.loads(r.stdout)
    assert summary["ranks"] == 2 and summary["status"] == "completed", summary
    rows_s, rows_m = (read_csv(os.path.join(d, "steps.csv")) for d in (serial, mpi))
    assert len(rows_s) == len(rows_m) > 0, (name, len(rows_s), len(rows_m))
    for column in ("normal_force_sum", "friction_force_sum"):
        s = np.array([float(row[column]) for row in rows_s])
        m = np.array([float(row[column]) for row in rows_m])
        assert s.max() > 0 and np.abs(m - s).max() <= SAME * s.max(), (name, column)
    return mpi, summary


def pieces(directory):
    """The last snapshot's .vtu pieces of solution.pvd, each read alone, and the whole."""
    series = ET.parse(os.path.join(directory, "solution.pvd")).getroot()
    last = [d.get("file") for d in series.iter("DataSet")][-1]
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(os.path.join(directory, last))
    reader.Update()
    grids = []
    for piece in ET.parse(os.path.join(directory, last)).getroot().iter("Piece"):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(directory, piece.get("Source")))
        r.Update()
        grids.append(r.GetOutput())
    return reader.GetOutput(), grids


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--contact-sim", required=True)
    p.add_argument("--workdir", required=True)
    a = p.parse_args()
    os.makedirs(a.workdir, exist_ok=True)

    cases = []  # (name, scene, the strings of the message, contact-sim's options, env)

    def case(name, scene, expected, *args, petsc_options=None, once=True):
        cases.append(dict(name=name, scene=scene, expected=expected, args=args,
                          petsc_options=petsc_options, once=once))

    # Refused by the scene file's reader, on every rank alike.
    case("unknown key",
         write(a.workdir, "unknown_key", BOX.replace("young_modulus", "youngs_modulus")),
         ["material.young_modulus", "youngs_modulus"])
    case("wrong type", write(a.workdir, "wrong_type", BOX.replace("dt = 2e-5", 'dt = "2e-5"')),
         ["'time.dt'", "must be a number in the accepted range (0,", 'got a string "2e-5"'])
    missing = BOX.replace('type = "box"', 'type = "msh"\nfile = "no_such_mesh.msh"\n'
                          'dimension = 3').replace("cells = [3, 3, 2]\n", "")
    case("missing mesh", write(a.workdir, "missing_mesh", missing),
         ["'geometry.file'", "no_such_mesh.msh", "no such file",
          os.path.join(os.path.abspath(a.workdir), "no_such_mesh.msh")])

    # dt above dt_crit: dt_crit by Lanczos on the ranks (lumped) and on rank 0 (consistent).
    for name, text in (("dt above dt_crit, lumped", BOX),
                       ("dt above dt_crit, consistent", CONSISTENT)):
        case(name, write(a.workdir, "dt_" + name.split()[-1],
                         text.replace("dt = 2e-5", "dt = 4e-4")
                         .replace("end_time = 2e-4", "end_time = 2e-3")),
             ["dt = 0.0004 s", "dt_crit", "time.dt", "time.allow_unstable"])

    # Steps and settings not run on ranks: named, with what runs there.
    frictionless = BOX.replace("coefficient = 0.3", "coefficient = 0.0")
    case("step ipopt", write(a.workdir, "ipopt", frictionless), ["'ipopt'", "explicit"],
         "--step", "ipopt")
    case("lagged bound", write(a.workdir, "lagged", CONSISTENT),
         ["lagged bound", "coulomb-fc"], "--friction-formulation", "lagged-bound")
    compare = frictionless.replace('mass = "lumped"', 'mass = "consistent"').replace(
        'step = "explicit"', 'step = "condensed"\ncompare_with_ipopt = true')
    case("compare_with_ipopt", write(a.workdir, "compare", compare),
         ["compare_with_ipopt", "not available on MPI ranks"])
    case("resume", write(a.workdir, "resume", BOX), ["--resume", "MPI ranks"], "--resume")

    # PETSc options: PETSc's own message on one line, no traceback (every rank may print
    # it: the KSP's set-up is collective).
    condensed = write(a.workdir, "condensed", CONSISTENT)
    case("KSP type", condensed, ["KSP type nonsense"],
         petsc_options="-mass_ksp_type nonsense", once=False)
    case("preonly + jacobi", condensed, ["preonly + jacobi", "-mass_pc_type cholesky"],
         petsc_options="-mass_ksp_type preonly -mass_pc_type jacobi", once=False)
    case("partitioner", write(a.workdir, "explicit", BOX),
         ["DMPlexDistribute", "external package"],
         petsc_options="-petscpartitioner_type parmetis", once=False)
    # Two runs at a time: each is mostly mpiexec's start and the scene's set-up.
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        for line in pool.map(lambda c: refused(a, c["name"], c["scene"], c["expected"],
                                               *c["args"], petsc_options=c["petsc_options"],
                                               once=c["once"]), cases):
            print(line)

    r = run(a, write(a.workdir, "explicit", BOX), "--no-output",
            petsc_options="-mass_ksp_type cg")
    assert r.returncode == 0 and "completed" in r.stdout, r.stdout + r.stderr
    warnings = [l for l in r.stderr.splitlines() if "-mass_ksp_type cg was not used" in l]
    assert len(warnings) == 1, r.stderr
    print(f"unused option: exit 0: {warnings[0]}")

    # More ranks than cells: one cell on 2 ranks.
    one_cell = BOX.replace("cells = [3, 3, 2]", "cells = [1, 1, 1]") \
        .replace("end_time = 2e-4", "end_time = 4e-4") + "[output]\nsnapshot_every = 5\n"
    for step, text in (("explicit", one_cell),
                       ("condensed", one_cell.replace('mass = "lumped"', 'mass = "consistent"')
                        .replace('step = "explicit"', 'step = "condensed"'))):
        directory, _ = same_as_serial(a, "one_cell_" + step,
                                      write(a.workdir, "one_cell_" + step, text))
        whole, parts = pieces(directory)
        assert whole.GetNumberOfCells() == 1 and len(parts) == 2, whole.GetNumberOfCells()
        assert sorted(g.GetNumberOfCells() for g in parts) == [0, 1]
        print(f"one cell on 2 ranks, {step}: completed, pieces of "
              f"{[g.GetNumberOfCells() for g in parts]} cells")

    # A rank with cells but no contact node: the simple partitioner gives rank 1 the upper
    # cells of the column (cells are numbered x fastest, z slowest).
    column = CONSISTENT.replace("size = [0.2, 0.2, 0.1]", "size = [0.05, 0.05, 0.3]") \
        .replace("cells = [3, 3, 2]", "cells = [1, 1, 6]") \
        .replace('step = "condensed"', 'step = "sparse"') \
        .replace("end_time = 2e-4", "end_time = 3e-4") + "[output]\nsnapshot_every = 5\n"
    directory, summary = same_as_serial(a, "column", write(a.workdir, "column", column),
                                        petsc_options="-petscpartitioner_type simple")
    assert summary["step_method"] == "sparse", summary
    _, parts = pieces(directory)
    lowest = [min(g.GetPoint(i)[2] for i in range(g.GetNumberOfPoints())) for g in parts]
    assert lowest[0] == 0.0 and lowest[1] > 0.0, lowest
    print(f"column, sparse step: rank 1's cells start at z = {lowest[1]} m (no contact "
          f"node), completed with the serial force sums")
    return 0


if __name__ == "__main__":
    sys.exit(main())
