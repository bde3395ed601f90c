"""Reading contact-sim's ParaView snapshots (.vtu) back, and pictures of them without
ParaView: a 2D snapshot drawn with matplotlib, a 2D or 3D one rendered with VTK.

    snap = contact.vtu.read("drop-out/snapshot_00030.vtu")
    snap["time"], snap["points"], snap["cells"], snap["point_data"]["normal_force"]
    contact.vtu.plot("drop-out/snapshot_00030.vtu", "drop.png")      # 2D, matplotlib
    contact.vtu.render("out/snapshot_00100.vtu", "box.png")          # 3D, VTK off screen
    contact.vtu.in_contact("drop-out")   # the snapshot with the largest contact force

Reading needs VTK's Python bindings (Debian: python3-vtk9), plotting matplotlib. VTK
draws through an X display: ``render`` uses $DISPLAY, or starts its own virtual display
(Xvfb, Debian: xvfb) for the life of the process when there is none.

The obstacle is drawn from the snapshot itself: at each contact node the obstacle's surface
lies at x + u + gap n_c (point data gap and contact_normal), so a plane obstacle is exact
and a curved one is drawn where it faces the body.
"""
import atexit
import collections
import os
import shutil
import subprocess
import time as _time
import xml.etree.ElementTree as _ElementTree

import numpy as np

#: What ``render`` returns: the PNG's path and the body's bounding box in it, (left, top,
#: right, bottom) in pixels from the top-left corner.
Picture = collections.namedtuple("Picture", ["path", "body_box"])


def read(path):
    """{'time' [s] (None when no solution.pvd beside the file lists it), 'points' (N, 3) [m],
    'cells' (E, k) node indices, 'point_data' {name: array}, 'cell_data' {name: array}}
    of a .vtu file, read by VTK's own XML reader."""
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
    times = {file: t for t, file in series(os.path.dirname(os.path.abspath(path)))}
    data["time"] = times.get(os.path.abspath(path))
    return data


def series(directory):
    """[(time [s], absolute path)] of the snapshots solution.pvd lists in `directory`
    ([] without one), in the file's order."""
    pvd = os.path.join(directory, "solution.pvd")
    if not os.path.isfile(pvd):
        return []
    root = _ElementTree.parse(pvd).getroot()
    return [(float(d.get("timestep")), os.path.abspath(os.path.join(directory, d.get("file"))))
            for d in root.iter("DataSet")]


def in_contact(directory):
    """The snapshot of `directory`'s series (solution.pvd) whose normal forces at pressed
    nodes (contact_state 1 stick or 2 slip: above the step's force accuracy, so round-off
    is not contact) sum to the most: a moment in contact; the last snapshot when none is in
    contact. Raises FileNotFoundError when the directory has no series."""
    snapshots = series(directory)
    if not snapshots:
        raise FileNotFoundError(f"contact.vtu.in_contact: no solution.pvd in {directory!r}")
    best, best_force = snapshots[-1][1], 0.0
    for _, path in snapshots:
        point = read(path)["point_data"]
        if "normal_force" not in point or "contact_state" not in point:
            continue
        pressed = np.nan_to_num(point["contact_state"], nan=-1.0) > 0
        force = float(np.linalg.norm(point["normal_force"][pressed], axis=1).sum())
        if force > best_force:
            best, best_force = path, force
    return best


def _obstacle_surface(snap):
    """Points on the obstacle's surface at the contact nodes, x + u + gap n_c [m] (dim
    columns), and the normals n_c there; None for a snapshot without contact_normal."""
    point = snap["point_data"]
    if "contact_normal" not in point or "gap" not in point:
        return None
    on = np.isfinite(point["gap"]) & (np.linalg.norm(point["contact_normal"], axis=1) > 0.5)
    if not on.any():
        return None
    x = snap["points"] + point["displacement"]  # the obstacle is where the body is, not magnified
    return x[on] + point["gap"][on, None] * point["contact_normal"][on], point["contact_normal"][on]


def _is_plane(normals):
    return bool(np.all(np.abs(normals - normals[0]).max(axis=0) < 1e-9))


def _caption(snap, magnify):
    u = np.linalg.norm(snap["point_data"]["displacement"], axis=1).max()
    when = "" if snap["time"] is None else f"t = {snap['time']:.6g} s, "
    scale = "true scale" if magnify == 1 else f"displacements drawn x {magnify:g}"
    return f"{when}{scale}, largest |u| = {u:.3g} m"


def plot(path, out=None, magnify=1.0, title=None):
    """Draws a 2D snapshot: the mesh at x + magnify u (true scale by default: a rigid motion
    magnified would misplace the body) colored by the von Mises stress [Pa], the obstacle
    (hatched, from the snapshot's gap and contact_normal), and the contact forces of the
    obstacle on the body (normal + friction) as arrows [N] at the nodes in contact
    (contact_state 1 stick, 2 slip). The caption gives the time (from solution.pvd beside
    the file), the displacement scale and the largest displacement; the colour bar sits
    below the axes and the legend above them, so neither covers the body. Saves to `out`
    if given; returns the matplotlib figure."""
    from matplotlib.collections import PolyCollection
    from matplotlib.ticker import MaxNLocator

    snap = read(path)
    points, cells = snap["points"][:, :2], snap["cells"]
    if np.ptp(snap["points"][:, 2]) > 0:
        raise ValueError("contact.vtu.plot draws 2D snapshots; contact.vtu.render draws 3D ones")
    u = snap["point_data"]["displacement"][:, :2]
    size = np.ptp(points, axis=0).max()
    x = points + magnify * u
    force = snap["point_data"]["normal_force"][:, :2] + snap["point_data"]["friction_force"][:, :2]
    pressed = snap["point_data"]["contact_state"] > 0
    fig, ax, cax = _figure_for(x, size)
    mesh = PolyCollection(x[cells], array=snap["cell_data"]["von_mises"], cmap="viridis",
                          edgecolors="k", linewidths=0.3, zorder=2)
    ax.add_collection(mesh)
    if pressed.any():
        f = force[pressed]
        scale = np.linalg.norm(f, axis=1).max() / (0.15 * size)  # [N per m of arrow]
        ax.quiver(x[pressed, 0], x[pressed, 1], f[:, 0], f[:, 1], angles="xy", scale_units="xy",
                  scale=scale, color="C3", width=0.004, zorder=3,
                  label=f"contact force (largest {np.linalg.norm(f, axis=1).max():.3g} N)")
    ax.set_aspect("equal", adjustable="datalim")  # the axes keep their place: limits grow
    ax.autoscale_view()
    ax.margins(0.15)
    limits = ax.get_xlim(), ax.get_ylim()  # the body's, with margins
    _draw_obstacle_2d(ax, snap, size)
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2, fontsize=8, frameon=False)
    bar = fig.colorbar(mesh, cax=cax, orientation="horizontal", label="von Mises stress [Pa]")
    bar.locator = MaxNLocator(5)
    bar.formatter.set_powerlimits((-3, 3))  # 2.5e5 as 2.5 with x1e5 beside the bar
    bar.update_ticks()
    fig.suptitle((title or os.path.basename(str(path))) + "\n" + _caption(snap, magnify), fontsize=10)
    if out is not None:
        fig.savefig(out, dpi=120)
    return fig


def _figure_for(x, size):
    """A figure 8 inches wide whose axes have about the body's aspect ratio (little empty
    space), with room above them for the caption and the legend and below for the axis label
    and the colour bar's own axes: (figure, axes, colour bar axes)."""
    import matplotlib.pyplot as plt

    span = np.maximum(np.ptp(x, axis=0), 1e-3 * size)
    axes_width = 6.4  # [in]
    axes_height = float(np.clip(axes_width * (span[1] + 0.3 * size) / (1.3 * span[0]), 1.2, 6.0))
    above, below = 1.0, 1.5  # [in]: caption and legend; x label and colour bar
    height = axes_height + above + below
    fig = plt.figure(figsize=(8.0, height))
    ax = fig.add_axes([0.12, below / height, axes_width / 8.0, axes_height / height])
    cax = fig.add_axes([0.25, 0.4 / height, 0.5, 0.16 / height])
    return fig, ax, cax


def _draw_obstacle_2d(ax, snap, size):
    """The obstacle's surface (a line) and a hatched band on its side, 0.1 body sizes deep."""
    from matplotlib.patches import Polygon

    surface = _obstacle_surface(snap)
    if surface is None:
        return
    p, n = surface[0][:, :2], surface[1][:, :2]
    tangent = np.column_stack([-n[:, 1], n[:, 0]])
    order = np.argsort(p @ tangent[0])
    p, n = p[order], n[order]
    if _is_plane(n):  # a plane: across the view and beyond (the view's limits stay)
        t = tangent[0]
        p, n = np.array([p[0] - 10 * size * t, p[-1] + 10 * size * t]), n[:2]
    band = np.vstack([p, (p + 0.1 * size * n)[::-1]])
    ax.add_patch(Polygon(band, closed=True, facecolor="0.9", edgecolor="0.6", linewidth=0.0,
                         hatch="///", zorder=1))
    ax.plot(p[:, 0], p[:, 1], color="0.3", linewidth=1.5, zorder=1, label="obstacle")


# ----------------------------------------------------------------------------------------
# 3D pictures with VTK

_display = {}


def _ensure_display():
    """$DISPLAY for VTK's window: the user's, else a virtual one (Xvfb) started here and
    stopped when the process exits. RuntimeError when there is neither."""
    if os.environ.get("DISPLAY"):
        return
    exe = shutil.which("Xvfb")
    if exe is None:
        raise RuntimeError("contact.vtu.render: VTK draws through an X display, and there is none "
                           "($DISPLAY is unset) and no Xvfb to start one: install xvfb (Debian) or "
                           "run where a display is")
    for number in range(99, 400):
        if os.path.exists(f"/tmp/.X{number}-lock") or os.path.exists(f"/tmp/.X11-unix/X{number}"):
            continue
        process = subprocess.Popen([exe, f":{number}", "-screen", "0", "1600x1200x24", "-nolisten",
                                    "tcp"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = _time.monotonic() + 10.0
        while process.poll() is None and _time.monotonic() < deadline:
            if os.path.exists(f"/tmp/.X11-unix/X{number}"):
                os.environ["DISPLAY"] = f":{number}"
                _display["process"] = process
                atexit.register(process.terminate)
                return
            _time.sleep(0.05)
        if process.poll() is None:
            process.terminate()
    raise RuntimeError("contact.vtu.render: Xvfb did not start a display (tried :99 to :399)")


def render(path, out, magnify=1.0, field="von_mises", size=(1200, 800), view=None, title=None):
    """Renders a snapshot (2D or 3D) to the PNG `out` with VTK off screen: the body's surface
    at x + magnify u coloured by `field` (cell data von_mises [Pa] by default, or any point
    or cell array of the snapshot: a vector by its length), its edges, the obstacle (a plane,
    or the surface through the points facing the body), a colour bar at the right edge and a
    caption with the time, the displacement scale and the largest displacement.
    view: the direction [x, y, z] the camera looks along (default in 3D: from above, in
    front and to the right, "up" away from the obstacle; in 2D straight on). Returns a
    Picture: the path and the body's bounding box in the picture [pixels]."""
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    snap = read(path)
    _ensure_display()
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    points = snap["points"] + magnify * snap["point_data"]["displacement"]
    grid.GetPoints().SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    on_cells = field in snap["cell_data"]
    if not on_cells and field not in snap["point_data"]:
        raise ValueError(f"contact.vtu.render: the snapshot has no field {field!r}; it has "
                         f"{sorted(snap['point_data']) + sorted(snap['cell_data'])}")
    values = (snap["cell_data"] if on_cells else snap["point_data"])[field]
    if values.ndim > 1:
        values = np.linalg.norm(values, axis=1)
    scalars = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
    scalars.SetName(field + "_shown")
    (grid.GetCellData() if on_cells else grid.GetPointData()).AddArray(scalars)
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(grid)
    mapper = vtk.vtkDataSetMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.SetScalarModeToUseCellFieldData() if on_cells else mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(field + "_shown")
    finite = values[np.isfinite(values)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    mapper.SetScalarRange(low, high if high > low else low + 1.0)
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (low) to red (high)
    lut.Build()
    mapper.SetLookupTable(lut)
    body = vtk.vtkActor()
    body.SetMapper(mapper)
    body.GetProperty().EdgeVisibilityOn()
    body.GetProperty().SetEdgeColor(0.15, 0.15, 0.15)

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.AddActor(body)
    obstacle = _obstacle_actor(snap, vtk)
    if obstacle is not None:
        renderer.AddActor(obstacle)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(field + (" [Pa]" if field in ("von_mises", "stress") else ""))
    bar.SetNumberOfLabels(5)
    bar.SetLabelFormat("%.3g")
    bar.GetPositionCoordinate().SetValue(0.88, 0.1)  # its own strip at the right edge
    bar.SetWidth(0.1)
    bar.SetHeight(0.8)
    for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        text.SetColor(0.0, 0.0, 0.0)
        text.ItalicOff()
        text.ShadowOff()
    renderer.AddActor2D(bar)
    caption = vtk.vtkTextActor()
    caption.SetInput((title or os.path.basename(str(path))) + "\n" + _caption(snap, magnify))
    caption.GetTextProperty().SetColor(0.0, 0.0, 0.0)
    caption.GetTextProperty().SetFontSize(max(12, size[1] // 45))
    caption.SetPosition(10, 10)
    renderer.AddActor2D(caption)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    window.AddRenderer(renderer)
    _place_camera(renderer, snap, points, view)
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.ReadFrontBufferOff()
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(str(out))
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()
    box = _pixel_box(renderer, points, size)
    window.Finalize()
    if not os.path.isfile(out) or os.path.getsize(out) == 0:
        raise RuntimeError(f"contact.vtu.render: VTK wrote no picture to {out!r}")
    return Picture(str(out), box)


def _pixel_box(renderer, points, size):
    """(left, top, right, bottom) in pixels of the picture (rows from the top) of the
    corners of the body's bounding box as the camera projects them."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    pixels = []
    for corner in np.array(np.meshgrid(*zip(lo, hi))).T.reshape(-1, 3):
        renderer.SetWorldPoint(*corner, 1.0)
        renderer.WorldToDisplay()
        x, y, _ = renderer.GetDisplayPoint()
        pixels.append((x, size[1] - y))
    pixels = np.array(pixels)
    return (float(pixels[:, 0].min()), float(pixels[:, 1].min()),
            float(pixels[:, 0].max()), float(pixels[:, 1].max()))


def _place_camera(renderer, snap, points, view):
    """Looks along `view` at the body's centre, the body filling the window left of the
    colour bar. 3D: "up" is away from the obstacle (-n_c; z without contact nodes) and the
    default view from above, in front and to the right; 2D: straight on, y up."""
    camera = renderer.GetActiveCamera()
    if np.ptp(snap["points"][:, 2]) > 0:
        surface = _obstacle_surface(snap)
        up = -surface[1].mean(axis=0) if surface is not None else np.array([0.0, 0.0, 1.0])
        up /= np.linalg.norm(up)
        h1 = np.cross(up, np.eye(3)[int(np.argmin(np.abs(up)))])
        h1 /= np.linalg.norm(h1)
        h2 = np.cross(up, h1)
        default = -0.6 * up - h1 - 0.6 * h2
    else:
        up, default = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, -1.0])
    direction = np.asarray(view if view is not None else default, dtype=float)
    direction /= np.linalg.norm(direction)
    if abs(np.dot(up, direction)) > 0.99:
        up = np.cross(direction, np.eye(3)[int(np.argmin(np.abs(direction)))])
    center = 0.5 * (points.min(axis=0) + points.max(axis=0))
    camera.SetFocalPoint(*center)
    camera.SetPosition(*(center - direction))
    camera.SetViewUp(*up)
    renderer.ResetCamera(*np.column_stack([points.min(axis=0), points.max(axis=0)]).ravel())
    camera.Zoom(0.85)


def _obstacle_actor(snap, vtk):
    """The obstacle as a grey surface: a square of the plane (3 body sizes wide) for a plane,
    else the surface through the obstacle's points facing the body; None without them."""
    surface = _obstacle_surface(snap)
    if surface is None:
        return None
    p, n = surface
    size = np.ptp(snap["points"], axis=0).max()
    if _is_plane(n) and np.ptp(snap["points"][:, 2]) > 0:
        normal = n[0]
        helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
        t1 = np.cross(normal, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(normal, t1)
        center = p.mean(axis=0)
        source = vtk.vtkPlaneSource()
        source.SetOrigin(*(center - 1.5 * size * (t1 + t2)))
        source.SetPoint1(*(center + 1.5 * size * (t1 - t2)))
        source.SetPoint2(*(center + 1.5 * size * (t2 - t1)))
        output = source
    elif np.ptp(snap["points"][:, 2]) > 0:
        cloud = vtk.vtkPolyData()
        vtk_points = vtk.vtkPoints()
        for q in p:
            vtk_points.InsertNextPoint(*q)
        cloud.SetPoints(vtk_points)
        output = vtk.vtkDelaunay2D()
        output.SetInputData(cloud)
        output.SetProjectionPlaneMode(vtk.VTK_BEST_FITTING_PLANE)
    else:  # 2D: the obstacle's line under the body (a plane: a body size beyond each side)
        t = np.column_stack([-n[:, 1], n[:, 0], np.zeros(len(n))])
        p = p[np.argsort(p @ t[0])]
        if _is_plane(n):
            p = np.array([p[0] - size * t[0], p[-1] + size * t[0]])
        vtk_points = vtk.vtkPoints()
        for q in p:
            vtk_points.InsertNextPoint(*q)
        output = vtk.vtkLineSource()
        output.SetPoints(vtk_points)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(output.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.75, 0.75, 0.72)
    actor.GetProperty().SetOpacity(0.5)
    actor.GetProperty().SetLineWidth(4)
    return actor
