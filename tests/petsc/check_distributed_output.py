#!/usr/bin/python3
"""contact-sim on 2 MPI ranks against the serial contact-sim on the same scene, through the
files a user opens: solution.pvd lists one .pvtu per snapshot, VTK's own parallel reader
(vtkXMLPUnstructuredGridReader) reads the last one - its cells are the mesh's, its points
(the pieces share their partition-boundary vertices) the mesh's nodes once merged, its
displacement the serial displacement.csv to its 10 printed digits, and every snapshot's
arrays (displacement, velocity, gap, contact forces, slip, contact state and normal,
stress, von Mises) those of the serial .vtu - steps.csv has the
serial rows' contact force sums (the 1e-12 comparison of the trajectories themselves is
test_distributed_scene.cpp's, in one process without the files' rounding), and
contact_stress.csv, node_history.csv (output.marked_point) and displacement.csv (at
output.stress_times and the end) have the serial rows; --json reports ranks = 2; a scene
whose step is not explicit or condensed (here the full step) is refused once, with exit
code 1, naming the step; the condensed step (a Tet4 box with the consistent mass and
friction: SCENE's box as Tet4 cells) on 2 ranks writes the serial steps.csv's accuracy, energy and active_nodes
columns and ends with the serial status and summary maxima; and SIGINT
to mpiexec ends a run after a finished step with the "interrupted" summary and steps.csv
complete up to that step (OpenMPI 4.1's mpiexec passes SIGINT on as SIGTERM and exits
nonzero)."""
import argparse
import csv
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
import vtk

SCENE = """
name = "box-drop-output"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [0.2, 0.2, 0.1]
cells = [6, 5, 3]
element = "hex8"
contact = ["zmin"]
fixed = ["xmin"]
fixed_components = [0]
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
offset = -0.001
normal_source = "obstacle"
[friction]
coefficient = 0.3
[time]
dt = 2e-5
end_time = 0.004
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[solver]
step = "explicit"
[output]
snapshot_every = 50
stress_times = [0.001, 0.002]
marked_point = [0.1, 0.1, 0.0]
"""
SAME = 1e-9  # relative: the CSV files print 10 significant digits

# The box of SCENE as Tet4 cells with the consistent mass under the condensed step (as
# tests/petsc/test_distributed_condensed.cpp's): it lands, slides and rings.
CONDENSED_SCENE = (SCENE.replace("cells = [6, 5, 3]", "cells = [4, 3, 2]")
                   .replace('element = "hex8"', 'element = "tet4"')
                   .replace('mass = "lumped"', 'mass = "consistent"')
                   .replace('step = "explicit"', 'step = "condensed"'))
ENERGY_COLUMNS = ("kinetic_energy", "strain_energy", "external_work", "normal_contact_work",
                  "friction_dissipation", "energy_balance_error")
RESIDUAL_COLUMNS = ("equilibrium_residual", "complementarity_residual", "friction_residual")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def arrays(data):
    """name -> (n, components) array of a vtkPointData or vtkCellData."""
    from vtk.util.numpy_support import vtk_to_numpy
    out = {}
    for i in range(data.GetNumberOfArrays()):
        values = vtk_to_numpy(data.GetArray(i))
        out[data.GetArrayName(i)] = values.reshape(len(values), -1)
    return out


def cell_centres(grid):
    """(cells, 3): the mean of each cell's points."""
    return np.array([np.mean([grid.GetPoint(cell.GetPointId(j))
                              for j in range(cell.GetNumberOfPoints())], axis=0)
                     for cell in (grid.GetCell(c) for c in range(grid.GetNumberOfCells()))])


def check_snapshot_fields(serial_dir, mpi_dir, serial_files, files):
    """Every snapshot: the arrays of the .pvtu (VTK's parallel reader, 2 pieces) against
    the serial .vtu's, point by point (a partition-boundary point in both pieces, each
    compared) and cell by cell (matched by their coordinates and centres): the same
    names and components, NaN where one process has NaN (gap off the contact surface,
    forces and contact_state at the start), the values within SAME of the array's
    largest magnitude (gap and slip: or of the displacement's); the contact arrays are not zero in every snapshot."""
    worst, seen = 0.0, {}
    for serial_name, mpi_name in zip(serial_files, files):
        serial = vtk.vtkXMLUnstructuredGridReader()
        serial.SetFileName(os.path.join(serial_dir, serial_name))
        serial.Update()
        reader = vtk.vtkXMLPUnstructuredGridReader()
        reader.SetFileName(os.path.join(mpi_dir, mpi_name))
        reader.Update()
        s_grid, m_grid = serial.GetOutput(), reader.GetOutput()
        s_points = np.array([s_grid.GetPoint(i) for i in range(s_grid.GetNumberOfPoints())])
        m_points = np.array([m_grid.GetPoint(i) for i in range(m_grid.GetNumberOfPoints())])
        point_of = {tuple(np.round(x, 12)): i for i, x in enumerate(s_points)}
        points = [point_of[tuple(np.round(x, 12))] for x in m_points]
        cell_of = {tuple(np.round(x, 12)): i for i, x in enumerate(cell_centres(s_grid))}
        cells = [cell_of[tuple(np.round(x, 12))] for x in cell_centres(m_grid)]
        assert sorted(cells) == list(range(s_grid.GetNumberOfCells())), mpi_name
        for kind, order in (("point", points), ("cell", cells)):
            get = (lambda g: g.GetPointData()) if kind == "point" else (lambda g: g.GetCellData())
            s_arrays, m_arrays = arrays(get(s_grid)), arrays(get(m_grid))
            assert set(m_arrays) == set(s_arrays) | ({"rank"} if kind == "cell" else set()), \
                (mpi_name, sorted(m_arrays), sorted(s_arrays))
            for name, s_values in s_arrays.items():
                expected, got = s_values[order], m_arrays[name]
                assert got.shape == expected.shape, (mpi_name, name, got.shape, expected.shape)
                assert (np.isnan(got) == np.isnan(expected)).all(), (mpi_name, name, "NaN")
                known = ~np.isnan(expected)
                scale = max(np.abs(expected[known]).max(initial=0.0), 1e-300)
                if name in ("gap", "slip"):  # (a closed gap is round-off of u's size)
                    scale = max(scale, np.abs(s_arrays["displacement"]).max())
                error = np.abs(got[known] - expected[known]).max(initial=0.0) / scale
                assert error <= SAME, (mpi_name, name, error)
                worst = max(worst, error)
                if name in ("normal_force", "friction_force", "slip", "contact_state",
                            "velocity", "von_mises"):
                    seen[name] = max(seen.get(name, 0.0), np.nanmax(np.abs(got)))
    assert all(v > 0 for v in seen.values()) and len(seen) == 6, seen  # (contact: state > 0)
    return f"{len(files)} snapshots' arrays as one process's within {worst:.2g} (relative)"


def check_interrupt(a, mpi, scene):
    """SIGINT to mpiexec once steps.csv has rows: the run stops after a finished step."""
    with open(scene) as f:
        text = f.read().replace("end_time = 0.004", "end_time = 4.0")
    long_scene = os.path.join(a.workdir, "box_drop_long.toml")
    with open(long_scene, "w") as f:
        f.write(text)
    out = os.path.join(a.workdir, "interrupted")
    steps = os.path.join(out, "steps.csv")
    if os.path.exists(steps):
        os.remove(steps)
    run = subprocess.Popen(mpi + [long_scene, "--quiet", "--output", out],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 90
    while time.time() < deadline and run.poll() is None:
        if os.path.exists(steps) and len(read_csv(steps)) >= 5:
            break
        time.sleep(0.2)
    assert run.poll() is None, "the long run ended before the signal"
    run.send_signal(signal.SIGINT)
    stdout, stderr = run.communicate(timeout=90)
    assert run.returncode != 0, run.returncode
    lines = [l for l in stderr.splitlines() if "interrupted at step" in l]
    assert len(lines) == 1, stderr
    step = int(lines[0].split("interrupted at step")[1].split()[0])
    rows = read_csv(steps)
    assert len(rows) == step and int(rows[-1]["step"]) == step, (len(rows), step)
    return f"stopped after step {step} (mpiexec exit code {run.returncode})"


def check_condensed(a):
    """The condensed step on 2 ranks against one process: steps.csv's energy columns within
    SAME of the run's largest energy, the residuals within SAME of the step's force scale
    F = force_accuracy / tolerance (their own size is what the contact solver left), the
    penetration within SAME of D = displacement_accuracy / tolerance, both accuracies within
    SAME relative, active_nodes equal; --json's status, inaccurate_steps and maxima alike."""
    scene = os.path.join(a.workdir, "tet_box_condensed.toml")
    assert CONDENSED_SCENE.count("tet4") == CONDENSED_SCENE.count("condensed") == 1
    with open(scene, "w") as f:
        f.write(CONDENSED_SCENE)
    tolerance = 1e-10  # (solver.tolerance's default)
    runs = {}
    for name, command in (("serial", [a.contact_sim]),
                          ("mpi2", [a.mpiexec, "-n", "2", "--oversubscribe", a.contact_sim])):
        out = os.path.join(a.workdir, "condensed_" + name)
        run = subprocess.run(command + [scene, "--quiet", "--json", "--output", out],
                             check=True, capture_output=True, text=True)
        runs[name] = (json.loads(run.stdout), read_csv(os.path.join(out, "steps.csv")))
    (js, serial), (jm, mpi) = runs["serial"], runs["mpi2"]
    assert jm["ranks"] == 2 and jm["step_method"] == "condensed", jm
    for key in ("status", "inaccurate_steps", "steps"):
        assert jm[key] == js[key], (key, jm[key], js[key])
    assert js["status"] == "completed", js
    assert len(serial) == len(mpi) == 200, (len(serial), len(mpi))
    column = lambda rows, c: np.array([float(r[c]) for r in rows])
    energy_scale = max(np.abs(column(serial, c)).max() for c in ENERGY_COLUMNS[:-1])
    worst = {}
    worst["energy"] = max(np.abs(column(mpi, c) - column(serial, c)).max()
                          for c in ENERGY_COLUMNS) / energy_scale
    F = column(serial, "force_accuracy") / tolerance
    D = column(serial, "displacement_accuracy") / tolerance
    worst["residuals"] = max((np.abs(column(mpi, c) - column(serial, c)) / F).max()
                             for c in RESIDUAL_COLUMNS)
    worst["penetration"] = (np.abs(column(mpi, "max_penetration") -
                                   column(serial, "max_penetration")) / D).max()
    worst["accuracies"] = max((np.abs(column(mpi, c) / column(serial, c) - 1)).max()
                              for c in ("force_accuracy", "displacement_accuracy"))
    assert all(v <= SAME for v in worst.values()), worst
    active_s, active_m = column(serial, "active_nodes"), column(mpi, "active_nodes")
    assert active_s.max() > 0 and (active_s == active_m).all(), "active_nodes"
    for key in ("max_equilibrium_residual", "max_complementarity_residual",
                "max_friction_residual"):
        assert np.isfinite(jm[key]) and abs(jm[key] - js[key]) <= SAME * F.max(), key
    assert abs(jm["energy_balance_error"] - js["energy_balance_error"]) <= SAME * energy_scale
    series = [[d.get("file") for d in
               ET.parse(os.path.join(a.workdir, "condensed_" + name, "solution.pvd")).getroot()
               .iter("DataSet")] for name in ("serial", "mpi2")]
    fields = check_snapshot_fields(os.path.join(a.workdir, "condensed_serial"),
                                   os.path.join(a.workdir, "condensed_mpi2"), *series)
    return ("condensed on 2 ranks: " + fields + "; " +
            ", ".join(f"{k} {v:.2g}" for k, v in worst.items()) +
            f" (energy scale {energy_scale:.3g} J); active_nodes up to {int(active_s.max())}")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--contact-sim", required=True)
    p.add_argument("--workdir", required=True)
    a = p.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    scene = os.path.join(a.workdir, "box_drop_output.toml")
    with open(scene, "w") as f:
        f.write(SCENE)
    serial_dir, mpi_dir = os.path.join(a.workdir, "serial"), os.path.join(a.workdir, "mpi2")
    mpi = [a.mpiexec, "-n", "2", "--oversubscribe", a.contact_sim]
    subprocess.run([a.contact_sim, scene, "--quiet", "--output", serial_dir], check=True)
    run = subprocess.run(mpi + [scene, "--quiet", "--json", "--output", mpi_dir], check=True,
                         capture_output=True, text=True)
    summary = json.loads(run.stdout)
    assert summary["ranks"] == 2 and summary["status"] == "completed", summary
    assert summary["step_method"] == "explicit", summary

    # The mesh of the serial run: nodes with coordinates, elements.
    nodes = read_csv(os.path.join(serial_dir, "mesh_nodes.csv"))
    num_elements = len(read_csv(os.path.join(serial_dir, "mesh_elements.csv")))
    xyz = np.array([[float(n["x"]), float(n["y"]), float(n["z"])] for n in nodes])
    u_serial = np.array([[float(r["ux"]), float(r["uy"]), float(r["uz"])]
                         for r in read_csv(os.path.join(serial_dir, "displacement.csv"))
                         if abs(float(r["time"]) - 0.004) < 1e-9])
    assert u_serial.shape == xyz.shape, (u_serial.shape, xyz.shape)

    # solution.pvd -> the last .pvtu, read by VTK's parallel reader.
    series = ET.parse(os.path.join(mpi_dir, "solution.pvd")).getroot()
    files = [d.get("file") for d in series.iter("DataSet")]
    assert len(files) == 1 + 200 // 50, files  # step 0, every 50th step (the last among them)
    # The snapshots are named as in one process: step 200 is snapshot_00200 in both.
    serial_files = [d.get("file") for d in
                    ET.parse(os.path.join(serial_dir, "solution.pvd")).getroot().iter("DataSet")]
    assert [f.replace(".pvtu", "") for f in files] == [f.replace(".vtu", "") for f in serial_files], \
        (files, serial_files)
    assert os.path.exists(os.path.join(mpi_dir, "snapshot_00200_rank_1.vtu")), os.listdir(mpi_dir)
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(os.path.join(mpi_dir, files[-1]))
    reader.Update()
    grid = reader.GetOutput()
    assert reader.GetNumberOfPieces() == 2, reader.GetNumberOfPieces()
    assert grid.GetNumberOfCells() == num_elements, (grid.GetNumberOfCells(), num_elements)
    points = np.array([grid.GetPoint(i) for i in range(grid.GetNumberOfPoints())])
    u_piece = np.array([grid.GetPointData().GetArray("displacement").GetTuple3(i)
                        for i in range(grid.GetNumberOfPoints())])
    index = {tuple(np.round(x, 8)): i for i, x in enumerate(xyz)}  # (mesh_nodes.csv: 10 digits)
    matched = [index[tuple(np.round(x, 8))] for x in points]
    assert len(set(matched)) == len(nodes), (len(set(matched)), len(nodes))
    u_max = np.abs(u_serial).max()
    difference = np.abs(u_piece - u_serial[matched]).max()
    assert u_max > 1e-4 and difference <= SAME * u_max, (difference, u_max)
    fields = check_snapshot_fields(serial_dir, mpi_dir, serial_files, files)

    # steps.csv: the same rows' contact force sums.
    rows_serial = read_csv(os.path.join(serial_dir, "steps.csv"))
    rows_mpi = read_csv(os.path.join(mpi_dir, "steps.csv"))
    assert len(rows_mpi) == len(rows_serial) == 200, (len(rows_mpi), len(rows_serial))
    for column in ("normal_force_sum", "friction_force_sum"):
        s = np.array([float(r[column]) for r in rows_serial])
        m = np.array([float(r[column]) for r in rows_mpi])
        assert s.max() > 0 and np.abs(m - s).max() <= SAME * np.abs(s).max(), column

    # The other CSVs of one process: the same rows (the stress times, the marked node).
    for name in ("contact_stress.csv", "node_history.csv", "displacement.csv"):
        s = np.loadtxt(os.path.join(serial_dir, name), delimiter=",", skiprows=1, ndmin=2)
        m = np.loadtxt(os.path.join(mpi_dir, name), delimiter=",", skiprows=1, ndmin=2)
        assert s.shape == m.shape and len(s) > 1, (name, s.shape, m.shape)
        scale = np.maximum(np.abs(s).max(axis=0), 1e-300)
        assert (np.abs(m - s) / scale).max() <= SAME, (name, (np.abs(m - s) / scale).max())

    interrupted = check_interrupt(a, mpi, scene)
    condensed = check_condensed(a)

    # Another step on 2 ranks: refused, once, naming the step and what is supported.
    refused = subprocess.run(mpi + [scene, "--step", "full", "--no-output"], capture_output=True, text=True)
    assert refused.returncode == 1, refused
    lines = [l for l in refused.stderr.splitlines() if "full" in l]
    assert len(lines) == 1 and "explicit" in lines[0], refused.stderr
    print(f"ok: {len(files)} snapshots, {grid.GetNumberOfPoints()} piece points = {len(nodes)} nodes merged, "
          f"{num_elements} cells; |u_mpi - u_serial| = {difference:.3g} m of {u_max:.3g} m; "
          f"{fields}; SIGINT: {interrupted}; {condensed}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
