"""Reading contact-sim's ParaView snapshots (.vtu) back, and a quick 2D picture of one
without ParaView.

    snap = contact.vtu.read("drop-out/snapshot_00030.vtu")
    snap["points"], snap["cells"], snap["point_data"]["normal_force"], snap["cell_data"]["stress"]
    contact.vtu.plot("drop-out/snapshot_00030.vtu", "drop.png")

Reading needs VTK's Python bindings (Debian: python3-vtk9), plotting matplotlib.
"""
import numpy as np


def read(path):
    """{'time'?, 'points' (N, 3) [m], 'cells' (E, k) node indices, 'point_data' {name: array},
    'cell_data' {name: array}} of a .vtu file, read by VTK's own XML reader."""
    import os

    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    if not os.path.isfile(path):
        raise FileNotFoundError(f"contact.vtu: no file {path!r} (working directory {os.getcwd()})")

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        raise ValueError(f"contact.vtu: no points read from {path!r}")
    data = {}
    for key, block in (("point_data", grid.GetPointData()), ("cell_data", grid.GetCellData())):
        data[key] = {block.GetArrayName(i): vtk_to_numpy(block.GetArray(i))
                     for i in range(block.GetNumberOfArrays())}
    data["points"] = vtk_to_numpy(grid.GetPoints().GetData())
    data["cells"] = np.array([[grid.GetCell(e).GetPointId(a)
                               for a in range(grid.GetCell(e).GetNumberOfPoints())]
                              for e in range(grid.GetNumberOfCells())])
    return data


def plot(path, out=None, magnify=1.0, title=None):
    """Draws a 2D snapshot: the mesh at x + magnify u (true scale by default: a rigid motion
    magnified would misplace the body) colored by the von Mises stress [Pa], and the
    contact forces of the obstacle on the body (normal + friction) as arrows [N] at the
    nodes in contact (contact_state 1 stick, 2 slip).  Saves to `out` if given; returns
    the matplotlib figure."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    snap = read(path)
    points, cells = snap["points"][:, :2], snap["cells"]
    if np.ptp(snap["points"][:, 2]) > 0:
        raise ValueError("contact.vtu.plot draws 2D snapshots; open 3D ones in ParaView")
    u = snap["point_data"]["displacement"][:, :2]
    size = np.ptp(points, axis=0).max()
    x = points + magnify * u
    force = snap["point_data"]["normal_force"][:, :2] + snap["point_data"]["friction_force"][:, :2]
    pressed = snap["point_data"]["contact_state"] > 0
    fig, ax = plt.subplots(figsize=(8, 3))
    mesh = PolyCollection(x[cells], array=snap["cell_data"]["von_mises"], cmap="viridis",
                          edgecolors="k", linewidths=0.3)
    ax.add_collection(mesh)
    fig.colorbar(mesh, ax=ax, label="von Mises stress [Pa]", shrink=0.8)
    if pressed.any():
        f = force[pressed]
        scale = np.linalg.norm(f, axis=1).max() / (0.15 * size)  # [N per m of arrow]
        ax.quiver(x[pressed, 0], x[pressed, 1], f[:, 0], f[:, 1], angles="xy", scale_units="xy",
                  scale=scale, color="C3", width=0.004,
                  label=f"contact force (largest {np.linalg.norm(f, axis=1).max():.3g} N)")
        ax.legend(loc="lower right", fontsize=8)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.15)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title or (str(path) + ("" if magnify == 1 else f": displacements x {magnify:g}")))
    fig.tight_layout()
    if out is not None:
        fig.savefig(out, dpi=120)
    return fig
