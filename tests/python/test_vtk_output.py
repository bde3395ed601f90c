"""contact-sim's ParaView output read back with VTK's own XML reader (Debian python3-vtk9):
the .pvd series lists every snapshot, and the fields of each .vtu agree with independent
recomputations - kinetic energy from the velocity field and the lumped masses, stress from
the displacement field by bilinear shape functions and Hooke's law, the Coulomb law node by
node - and with the CSV outputs of the same run; no node counts as in contact in flight."""
import csv
import os
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

E, NU, RHO, H = 2e8, 0.3, 7800.0, 1.0  # Pa, -, kg/m^3, m (thickness)
MU = 0.3                               # friction coefficient
SIZE, CELLS = (1.0, 0.2), (10, 2)      # m, Q4 cells
DT, END = 5e-5, 0.02                   # s

# A steel block thrown down onto a floor 1 mm below with a sideways push: it lands,
# slides with friction, bounces off and flies (lumped mass: the kinetic energy is
# 1/2 sum m_i |v_i|^2 with the element masses split equally among the 4 nodes).
SCENE = f"""
name = "vtk-output"
[geometry]
type = "rectangle"
size = [{SIZE[0]}, {SIZE[1]}]
cells = [{CELLS[0]}, {CELLS[1]}]
contact = ["ymin"]
[material]
young_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
mass = "lumped"
[loads]
body_force = [20000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 1.0]
offset = -0.001
normal_source = "obstacle"
[friction]
coefficient = {MU}
[time]
dt = {DT}
end_time = {END}
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[output]
directory = "out"
stress_times = [0.004, 0.01]
snapshot_every = 10
"""


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfPoints() > 0, f"VTK could not read {path}"
    point = {grid.GetPointData().GetArrayName(i): vtk_to_numpy(grid.GetPointData().GetArray(i))
             for i in range(grid.GetPointData().GetNumberOfArrays())}
    cell = {grid.GetCellData().GetArrayName(i): vtk_to_numpy(grid.GetCellData().GetArray(i))
            for i in range(grid.GetCellData().GetNumberOfArrays())}
    points = vtk_to_numpy(grid.GetPoints().GetData())
    cells = [[grid.GetCell(e).GetPointId(a) for a in range(grid.GetCell(e).GetNumberOfPoints())]
             for e in range(grid.GetNumberOfCells())]
    types = {grid.GetCellType(e) for e in range(grid.GetNumberOfCells())}
    return points, np.array(cells), types, point, cell


@pytest.fixture(scope="module")
def run(tmp_path_factory, bin_dir):
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built (NCP_BIN_DIR)")
    d = tmp_path_factory.mktemp("vtk")
    (d / "scene.toml").write_text(SCENE)
    subprocess.run([exe, str(d / "scene.toml"), "--quiet"], check=True, capture_output=True, cwd=d)
    series = ET.parse(d / "out" / "solution.pvd").getroot().find("Collection")
    snapshots = [(float(s.get("timestep")), d / "out" / s.get("file")) for s in series]
    return d / "out", snapshots, read_csv(d / "out" / "steps.csv")


def test_the_series_lists_every_snapshot_in_time_order(run):
    out, snapshots, steps = run
    times = [t for t, _ in snapshots]
    nsteps = int(round(END / DT))
    expected = [0.0] + [k * DT for k in range(10, nsteps + 1, 10)]
    np.testing.assert_allclose(times, expected, rtol=1e-12, atol=1e-15)
    assert sorted(p.name for p in out.glob("*.vtu")) == [p.name for _, p in snapshots]


def test_mesh_and_fields_as_paraview_reads_them(run):
    _, snapshots, _ = run
    points, cells, types, point, cell = read_vtu(snapshots[-1][1])
    nodes = (CELLS[0] + 1) * (CELLS[1] + 1)
    assert points.shape == (nodes, 3) and cells.shape == (CELLS[0] * CELLS[1], 4)
    assert types == {vtk.VTK_QUAD}
    assert points[:, 0].max() == pytest.approx(SIZE[0]) and points[:, 1].max() == pytest.approx(SIZE[1])
    for name, components in [("displacement", 3), ("velocity", 3), ("normal_force", 3),
                             ("friction_force", 3), ("slip", 3)]:
        assert point[name].shape == (nodes, components), name
    assert point["gap"].shape == point["contact_state"].shape == (nodes,)
    assert cell["stress"].shape == (len(cells), 9) and cell["von_mises"].shape == (len(cells),)


def lumped_masses(points, cells):
    """m_i [kg]: each Q4 element's mass rho h |A_e| split equally among its nodes (the row
    sums of the consistent mass matrix of a parallelogram)."""
    m = np.zeros(len(points))
    for c in cells:
        x, y = points[c, 0], points[c, 1]
        area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))  # shoelace
        m[c] += RHO * H * area / 4
    return m


def test_velocity_gives_the_kinetic_energy_of_steps_csv(run):
    _, snapshots, steps = run
    for t, path in snapshots[1:]:
        points, cells, _, point, _ = read_vtu(path)
        k = int(np.argmin(np.abs(steps["time"] - t)))
        kinetic = 0.5 * np.sum(lumped_masses(points, cells) * np.sum(point["velocity"] ** 2, axis=1))
        assert kinetic == pytest.approx(steps["kinetic_energy"][k], rel=1e-8), t
    # The initial snapshot shows the prescribed velocity and no force yet (unknown: NaN).
    _, _, _, point, _ = read_vtu(snapshots[0][1])
    np.testing.assert_allclose(point["velocity"][:, :2], np.tile([0.0, -0.5], (len(point["gap"]), 1)),
                               atol=1e-14)
    assert np.isnan(point["contact_state"][point["gap"] == point["gap"]]).all()


def q4_stress(points, cells, u):
    """Cell-averaged plane-strain stress over the 2x2 Gauss points [Pa], recomputed from
    the bilinear shape functions: sigma = lambda tr(eps) I + 2 mu eps, sigma_zz = lambda tr."""
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    g = 1 / np.sqrt(3)
    out = []
    for c in cells:
        X, U = points[c, :2], u[c, :2]
        sigma = np.zeros((3, 3))
        for xi, eta in [(-g, -g), (g, -g), (g, g), (-g, g)]:
            dN = 0.25 * np.array([[-(1 - eta), -(1 - xi)], [(1 - eta), -(1 + xi)],
                                  [(1 + eta), (1 + xi)], [-(1 + eta), (1 - xi)]])
            J = X.T @ dN
            grad = U.T @ dN @ np.linalg.inv(J)
            eps = np.zeros((3, 3))
            eps[:2, :2] = 0.5 * (grad + grad.T)
            sigma += (lam * np.trace(eps) * np.eye(3) + 2 * mu * eps) / 4
        out.append(sigma.reshape(9))
    return np.array(out)


def test_stress_is_hookes_law_of_the_displacement_field(run):
    _, snapshots, _ = run
    for _, path in snapshots[1::8]:
        points, cells, _, point, cell = read_vtu(path)
        ref = q4_stress(points, cells, point["displacement"])
        # Round-off floor: a strain of eps |u| / h (h = 0.1 m) in either computation [Pa].
        floor = 100 * E * np.finfo(float).eps * np.abs(point["displacement"]).max() / 0.1
        np.testing.assert_allclose(cell["stress"], ref, rtol=1e-9, atol=floor)
        s = ref.reshape(-1, 3, 3)
        dev = s - np.trace(s, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3
        np.testing.assert_allclose(cell["von_mises"], np.sqrt(1.5 * np.sum(dev ** 2, axis=(1, 2))),
                                   rtol=1e-9, atol=floor)
        assert np.abs(ref).max() > 1e3 * floor or path == snapshots[1][1]  # resolved stresses


def test_contact_fields_obey_signorini_and_coulomb_and_match_the_csv(run):
    out, snapshots, steps = run
    stress = read_csv(out / "contact_stress.csv")
    pressed = slipping = sticking = flying = 0
    for t, path in snapshots[1:]:
        points, _, _, point, _ = read_vtu(path)
        k = int(np.argmin(np.abs(steps["time"] - t)))
        force_accuracy = steps["force_accuracy"][k]
        on = point["contact_state"] >= 0
        assert on.sum() == CELLS[0] + 1  # the bottom edge
        assert np.isnan(point["gap"][~on]).all() and not np.isnan(point["gap"][on]).any()
        assert (point["normal_force"][~on] == 0).all() and (point["friction_force"][~on] == 0).all()
        lam = point["normal_force"][on, 1]   # the floor pushes up: lambda n with n = (0, -1)
        tau = np.linalg.norm(point["friction_force"][on], axis=1)
        slip = np.linalg.norm(point["slip"][on], axis=1)
        state = point["contact_state"][on]
        assert (lam >= -force_accuracy).all()
        assert (tau <= MU * lam + 10 * force_accuracy).all()                     # Coulomb disc
        assert (point["normal_force"][on, 0] == 0).all() and (point["slip"][on, 1] == 0).all()
        assert ((state > 0) == (lam > force_accuracy)).all()
        assert (state > 0).sum() == steps["active_nodes"][k], t               # the same count
        assert lam.sum() == pytest.approx(steps["normal_force_sum"][k], rel=1e-9, abs=1e-9 * force_accuracy)
        slipping_now = state == 2
        np.testing.assert_allclose(tau[slipping_now], MU * lam[slipping_now], rtol=1e-6)  # on the cone
        np.testing.assert_allclose(point["slip"][on][slipping_now, 0] * point["friction_force"][on][slipping_now, 0],
                                   -slip[slipping_now] * tau[slipping_now], rtol=1e-6)  # opposes the slip
        pressed += (state > 0).sum()
        slipping += slipping_now.sum()
        sticking += (state == 1).sum()
        flying += (steps["normal_force_sum"][k] < force_accuracy)
        at = np.isclose(stress["time"], t, rtol=1e-9)
        if at.any():  # the same gaps as contact_stress.csv at its times
            order = np.argsort(stress["node"][at])
            np.testing.assert_allclose(point["gap"][on], stress["gap"][at][order], rtol=1e-9, atol=1e-15)
    assert pressed > 0 and slipping > 0 and flying > 0  # the run lands, slides and flies


def test_no_contact_counted_in_flight(run):
    """After the bounce the contact forces are round-off (~1e-18 N and below), which neither
    steps.csv's active_nodes nor the snapshots count as contact."""
    _, _, steps = run
    flight = steps["normal_force_sum"] < steps["force_accuracy"]
    assert flight[len(flight) // 2:].any()
    assert (steps["active_nodes"][flight] == 0).all()


def test_pieces_joined_by_a_pvtu_read_by_vtks_parallel_reader(tmp_path, bin_dir):
    """The MPI layout: each rank writes its piece with WriteVtu, one .pvtu joins them
    (written by the hidden Catch2 case "[.vtu-pieces]": a 2 x 1 Q4 mesh split in halves)."""
    exe = os.path.join(bin_dir, "test_contact_fem")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built")
    subprocess.run([exe, "[.vtu-pieces]"], check=True, capture_output=True,
                   env=dict(os.environ, NCP_PVTU_DIR=str(tmp_path)))
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "joined.pvtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfCells() == 2 and grid.GetNumberOfPoints() == 8  # the shared edge twice
    x = vtk_to_numpy(grid.GetPointData().GetArray("x"))
    np.testing.assert_array_equal(x, vtk_to_numpy(grid.GetPoints().GetData())[:, 0])
    np.testing.assert_array_equal(vtk_to_numpy(grid.GetCellData().GetArray("rank")), [0, 1])


def test_the_package_reader_and_plot(run, tmp_path):
    """contact.vtu.read gives what VTK's reader gives here; plot draws a 2D snapshot with
    an arrow per pressed node and refuses a missing file by name."""
    import matplotlib
    matplotlib.use("Agg")
    import contact.vtu

    _, snapshots, steps = run
    pressed = [(t, p) for t, p in snapshots[1:]
               if steps["active_nodes"][int(np.argmin(np.abs(steps["time"] - t)))] > 0]
    t, path = pressed[0]
    points, cells, _, point, cell = read_vtu(path)
    snap = contact.vtu.read(str(path))
    np.testing.assert_array_equal(snap["points"], points)
    np.testing.assert_array_equal(snap["cells"], cells)
    for name in point:
        np.testing.assert_array_equal(snap["point_data"][name], point[name])
    for name in cell:
        np.testing.assert_array_equal(snap["cell_data"][name], cell[name])
    fig = contact.vtu.plot(str(path), str(tmp_path / "snapshot.png"))
    arrows = [c for c in fig.axes[0].collections if c.__class__.__name__ == "Quiver"]
    assert len(arrows) == 1 and arrows[0].N == (point["contact_state"] > 0).sum() > 0
    assert (tmp_path / "snapshot.png").stat().st_size > 0
    with pytest.raises(FileNotFoundError, match="no file"):
        contact.vtu.read(str(tmp_path / "missing.vtu"))
