#!/usr/bin/python3
"""Figures of a contact-sim run, of the kinds the thesis shows (figs. 5-6, 8-16, 18-22).

Reads the CSV files contact-sim writes into its output directory (mesh_nodes.csv,
mesh_elements.csv, displacement.csv, contact_stress.csv, node_history.csv, steps.csv)
and the scene file for the obstacle and the boundary parts. Run with Debian's
matplotlib: /usr/bin/python3.

  plot_scene.py run RUN_DIR --scene SCENE.toml --prefix OUT/name [--title T] [--arrows]
                   [--time T]
      OUT/name_mesh.png            initial configuration | deformed mesh coloured by |u| at
                                   time T (default: the written time with the largest
                                   contact stresses, a moment in contact)
      OUT/name_contact_stress.png  normal and friction stress along Gamma_c at every
                                   written time, darker = later (fig. 16; 3D: fig. 6)
      OUT/name_history.png         contact and friction stress of the marked node
                                   (figs. 19, 21, 22)
  plot_scene.py compare --scene SCENE.toml --out OUT.png [--time T] RUN_DIR=LABEL ...
      normal and friction stress along Gamma_c at one time for several runs (figs. 11, 15);
      default time: the first run's moment in contact

Conventions (examples/scenes/README.md): normal stress compressive-positive; in 2D the
friction stress is the tangential traction on the body along t1 = (-n_y, n_x), in 3D its
magnitude.
"""
import argparse
import os
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import cm, colors  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

# Local faces of a Hex8 (gmsh order) and edges of a Quad4.
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


# ---------------------------------------------------------------------------- reading
def read_csv(path):
    """A CSV with a header as a dict of numpy columns (strings kept for non-numbers)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    out = {}
    for j, name in enumerate(header):
        column = [r[j] for r in rows]
        try:
            out[name] = np.array([float(v) for v in column])
        except ValueError:
            out[name] = np.array(column)
    return out


class Run:
    """The files of one contact-sim output directory."""

    def __init__(self, directory):
        self.dir = directory
        nodes = read_csv(os.path.join(directory, "mesh_nodes.csv"))
        self.dim = 3 if "z" in nodes else 2
        axes = ["x", "y", "z"][: self.dim]
        self.X = np.column_stack([nodes[a] for a in axes])
        self.fixed = nodes["fixed_components"].astype(int)
        self.contact = nodes["contact"].astype(int) == 1
        elements = read_csv(os.path.join(directory, "mesh_elements.csv"))
        cols = sorted((k for k in elements if k.startswith("n")), key=lambda k: int(k[1:]))
        self.elements = np.column_stack([elements[k] for k in cols]).astype(int)
        self.element_type = str(elements["type"][0])
        d = read_csv(os.path.join(directory, "displacement.csv"))
        self.times = np.unique(d["time"])
        comps = ["ux", "uy", "uz"][: self.dim]
        self.U = {}
        for t in self.times:
            sel = d["time"] == t
            U = np.zeros_like(self.X)
            U[d["node"][sel].astype(int)] = np.column_stack([d[c][sel] for c in comps])
            self.U[t] = U
        self.stress = read_csv(os.path.join(directory, "contact_stress.csv"))
        hist = os.path.join(directory, "node_history.csv")
        self.history = read_csv(hist) if os.path.exists(hist) and os.path.getsize(hist) > 40 else None
        self.steps = read_csv(os.path.join(directory, "steps.csv"))
        # contact-sim --json output, if the runner kept it: the friction coefficient.
        self.friction = None
        summary = os.path.join(directory, "run.json")
        if os.path.exists(summary):
            import json
            with open(summary) as f:
                self.friction = json.load(f).get("friction_coefficient")

    def displacement(self, time=None):
        t = self.times[-1] if time is None else self.times[np.argmin(abs(self.times - time))]
        return t, self.U[t]

    def contact_time(self):
        """A moment in contact: of the written times (contact_stress.csv) the one whose normal
        forces above their step's force accuracy (steps.csv: round-off is not contact) sum to
        the most; the last written time, with a note on stderr naming when the body is in
        contact, when none is."""
        s, steps = self.stress, self.steps
        pressed = {}
        for t in np.unique(s["time"]):
            accuracy = steps["force_accuracy"][np.argmin(abs(steps["time"] - t))]
            force = s["normal_force"][s["time"] == t]
            pressed[t] = force[force > accuracy].sum()
        if pressed and max(pressed.values()) > 0:
            return max(pressed, key=pressed.get)
        touching = steps["time"][steps["active_nodes"] > 0]
        when = (f"it is between t = {touching.min():g} s and {touching.max():g} s: add such a time to "
                "output.stress_times" if len(touching) else "it never touches the obstacle")
        print(f"plot_scene.py: no written time is in contact ({when}); drawing the last one",
              file=sys.stderr)
        return self.times[-1]

    def stress_at(self, time):
        """Contact stress rows at the written time nearest to `time`."""
        ts = np.unique(self.stress["time"])
        t = ts[np.argmin(abs(ts - time))]
        sel = self.stress["time"] == t
        return t, {k: v[sel] for k, v in self.stress.items()}


# ---------------------------------------------------------------------------- helpers
def stress_unit(values):
    m = np.nanmax(np.abs(values)) if len(values) else 0.0
    if m >= 1e6:
        return 1e6, "MPa"
    if m >= 1e3:
        return 1e3, "kPa"
    return 1.0, "Pa"


def length_unit(m):
    if m >= 1e-2:
        return 1e-3, "mm"
    if m >= 1e-5:
        return 1e-6, "µm"
    return 1e-9, "nm"


def along_axes(points, count):
    """The `count` coordinates along which the contact nodes spread most."""
    spread = points.max(axis=0) - points.min(axis=0)
    return sorted(np.argsort(-spread)[:count])


def friction_columns(stress):
    return [k for k in stress if k.startswith("friction_stress")]


def friction_value(rows):
    cols = friction_columns(rows)
    if len(cols) == 1:
        return rows[cols[0]]
    return np.sqrt(sum(rows[c] ** 2 for c in cols))


def obstacle_curve_2d(scene, xlim, ylim):
    """Points of the obstacle boundary inside the box (2D), or None."""
    o = scene["obstacle"]
    if o["type"] == "parabola":
        y = np.linspace(ylim[0], ylim[1], 200)
        return o["vertex"] + o["coefficient"] * y**2, y, +1
    if o["type"] == "plane":
        n = np.array(o["normal"], float)
        n /= np.linalg.norm(n)
        c = o["offset"]
        t = np.array([-n[1], n[0]])
        p0 = c * n
        s = np.linspace(-1e3, 1e3, 2)
        pts = p0[None, :] + s[:, None] * t[None, :]
        return pts[:, 0], pts[:, 1], n
    if o["type"] == "sphere":
        a = np.linspace(0, 2 * np.pi, 200)
        return o["center"][0] + o["radius"] * np.cos(a), o["center"][1] + o["radius"] * np.sin(a), None
    return None


def magnified_scene(scene, X, scale):
    """The obstacle as it appears beside a deformation magnified `scale` times: the gaps
    are magnified too, so that a node in contact is drawn on the obstacle (parabola:
    coefficient x scale; plane: the gap of the nearest node x scale)."""
    o = dict(scene["obstacle"])
    if o["type"] == "parabola":
        o["coefficient"] = o["coefficient"] * scale
    elif o["type"] == "plane":
        n = np.array(o["normal"], float)
        n /= np.linalg.norm(n)
        nearest = (X @ n).min()
        o["normal"] = list(n)
        o["offset"] = nearest - scale * (nearest - o["offset"])
    return dict(scene, obstacle=o)


def draw_obstacle_2d(ax, scene, X):
    lo, hi = X.min(axis=0), X.max(axis=0)
    pad = 0.15 * (hi - lo).max()
    xlim, ylim = (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)
    curve = obstacle_curve_2d(scene, xlim, ylim)
    if curve is None:
        return
    x, y, side = curve
    ax.plot(x, y, color="0.2", lw=2, label="rigid obstacle")
    o = scene["obstacle"]
    if o["type"] == "parabola":
        ax.fill_betweenx(y, x, xlim[1] + 10 * pad, color="0.85", zorder=0)
    elif o["type"] == "plane":
        n = side
        # Shade the obstacle side {n . y <= offset}.
        shift = -n * 3 * pad
        poly = np.array([[x[0], y[0]], [x[1], y[1]], [x[1] + shift[0], y[1] + shift[1]],
                         [x[0] + shift[0], y[0] + shift[1]]])
        ax.fill(poly[:, 0], poly[:, 1], color="0.85", zorder=0)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)


def boundary_edges_2d(run):
    """Element edges that belong to one element only (the body's boundary)."""
    count = {}
    for e in run.elements:
        n = len(e)
        for a in range(n):
            key = tuple(sorted((e[a], e[(a + 1) % n])))
            count[key] = count.get(key, 0) + 1
    return [k for k, c in count.items() if c == 1]


def side_edges(run, scene, key):
    """Boundary edges on the sides listed under geometry.<key> (rectangle scenes)."""
    g = scene.get("geometry", {})
    sides = g.get(key, [])
    if not sides:
        return []
    lo, hi = run.X.min(axis=0), run.X.max(axis=0)
    tol = 1e-9 * (hi - lo).max()
    out = []
    for a, b in boundary_edges_2d(run):
        for s in sides:
            axis = "xyz".index(s[0])
            level = lo[axis] if s.endswith("min") else hi[axis]
            if abs(run.X[a, axis] - level) < tol and abs(run.X[b, axis] - level) < tol:
                out.append((a, b))
    return out


def triangles(elements):
    if elements.shape[1] == 3:
        return elements
    return np.vstack([elements[:, [0, 1, 2]], elements[:, [0, 2, 3]]])


# ---------------------------------------------------------------------------- figures
def plot_mesh_2d(run, scene, title, path, time=None):
    t, U = run.displacement(time)
    mag = np.linalg.norm(U, axis=1)
    size = (run.X.max(axis=0) - run.X.min(axis=0)).max()
    scale = 0.08 * size / mag.max() if mag.max() > 0 else 1.0
    scale = float(f"{scale:.1g}")
    lu, lname = length_unit(mag.max())
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 5.2), sharex=True, sharey=True)
    # Left: the initial configuration with the boundary parts.
    ax = axes[0]
    draw_obstacle_2d(ax, scene, run.X)
    polys = [run.X[e] for e in run.elements]
    ax.add_collection(PolyCollection(polys, facecolor="white", edgecolor="0.5", lw=0.7))
    for key, colour, label in (("fixed", "tab:red", "Dirichlet (fixed)"),
                               ("load", "tab:green", "edge load"),
                               ("contact", "tab:blue", r"$\Gamma_c$")):
        edges = side_edges(run, scene, key)
        if edges:
            ax.add_collection(LineCollection([run.X[list(e)] for e in edges], colors=colour, lw=4,
                                             label=label))
    ax.set_title(f"initial configuration")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=8)
    # Right: deformed mesh (scaled) coloured by |u|.
    ax = axes[1]
    draw_obstacle_2d(ax, magnified_scene(scene, run.X, scale), run.X)
    Y = run.X + scale * U
    tri = triangles(run.elements)
    pc = ax.tripcolor(Y[:, 0], Y[:, 1], tri, mag / lu, shading="gouraud", cmap="viridis")
    ax.add_collection(PolyCollection([Y[e] for e in run.elements], facecolor="none",
                                     edgecolor="k", lw=0.5))
    ax.add_collection(PolyCollection(polys, facecolor="none", edgecolor="0.6", lw=0.5, ls=":"))
    fig.colorbar(pc, ax=ax, label=f"|u| [{lname}]", shrink=0.85)
    ax.set_title(f"displacement at t = {t:g} s\n(displacements and gaps magnified x{scale:g})")
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def boundary_faces_3d(run):
    count = {}
    for e in run.elements:
        for f in HEX_FACES:
            face = tuple(e[list(f)])
            key = tuple(sorted(face))
            count.setdefault(key, [0, face])[0] += 1
    return [face for c, face in count.values() if c == 1]


def plot_mesh_3d(run, scene, title, path, time=None, arrows=False):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    if run.element_type != "Hexahedron8":
        print(f"plot_scene: 3D mesh plot supports Hexahedron8 only, got {run.element_type}",
              file=sys.stderr)
        return
    t, U = run.displacement(time)
    mag = np.linalg.norm(U, axis=1)
    size = (run.X.max(axis=0) - run.X.min(axis=0)).max()
    scale = 0.08 * size / mag.max() if mag.max() > 0 else 1.0
    scale = float(f"{scale:.1g}")
    lu, lname = length_unit(mag.max())
    faces = boundary_faces_3d(run)
    Y = run.X + scale * U
    norm = colors.Normalize(vmin=0.0, vmax=mag.max() / lu)
    cmap = cm.viridis
    fig = plt.figure(figsize=(11, 5.4))
    for k, (pts, label) in enumerate(((run.X, "initial configuration"),
                                      (Y, f"displacement at t = {t:g} s\n(magnified x{scale:g})"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        if k == 0:
            fc = []
            for f in faces:
                if all(run.fixed[list(f)] > 0):
                    fc.append("tab:red")
                elif all(run.contact[list(f)]):
                    fc.append("tab:green")
                else:
                    fc.append("0.92")
            ax.add_collection3d(Poly3DCollection([pts[list(f)] for f in faces], facecolors=fc,
                                                 edgecolors="0.3", linewidths=0.5, alpha=0.55))
            if run.history is not None:
                marked = marked_node(run)
                if marked is not None:
                    ax.scatter(*run.X[marked], s=120, facecolors="none", edgecolors="tab:blue",
                               linewidths=2, label="marked node")
            from matplotlib.patches import Patch
            handles = [Patch(color="tab:red", label="Dirichlet (fixed)"),
                       Patch(color="tab:green", label=r"$\Gamma_c$ (wall at s = 0)")]
            if run.history is not None:
                handles.append(plt.Line2D([], [], marker="o", ls="", mfc="none", mec="tab:blue",
                                          label="marked node"))
            ax.legend(handles=handles, loc="upper left", fontsize=8)
        else:
            fc = [cmap(norm(mag[list(f)].mean() / lu)) for f in faces]
            ax.add_collection3d(Poly3DCollection([pts[list(f)] for f in faces], facecolors=fc,
                                                 edgecolors="k", linewidths=0.4))
            if arrows:
                d = U / np.maximum(mag[:, None], 1e-300)
                L = 0.15 * size
                ax.quiver(Y[:, 0], Y[:, 1], Y[:, 2], d[:, 0], d[:, 1], d[:, 2], length=L,
                          color="tab:red", linewidth=1.2, arrow_length_ratio=0.3)
            m = cm.ScalarMappable(norm=norm, cmap=cmap)
            fig.colorbar(m, ax=ax, label=f"|u| [{lname}]" + (" (arrows: direction of u)" if arrows else ""),
                         shrink=0.7, pad=0.22)
        both = np.vstack([run.X, Y])
        pad = 0.08 * size
        lo, hi = both.min(axis=0) - pad, both.max(axis=0) + pad
        if arrows:
            lo, hi = lo - 0.15 * size, hi + 0.15 * size
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(hi - lo)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(label, fontsize=10)
        ax.view_init(elev=22, azim=-60)
    fig.suptitle(title)
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)


def marked_node(run):
    """The contact node whose stresses match node_history.csv (the marked node)."""
    if run.history is None:
        return None
    h = run.history
    s = run.stress
    best, node = np.inf, None
    for n in np.unique(s["node"]):
        sel = s["node"] == n
        err = 0.0
        for t, p in zip(s["time"][sel], s["normal_stress"][sel]):
            k = np.argmin(abs(h["time"] - t))
            err += abs(h["normal_stress"][k] - p)
        if err < best:
            best, node = err, int(n)
    return node


def plot_contact_stress_2d(run, title, path):
    s = run.stress
    times = np.unique(s["time"])
    pts = np.column_stack([s[a] for a in ("x", "y")])
    axis = along_axes(pts, 1)[0]
    coord = "xy"[axis]
    fu, fname = stress_unit(np.concatenate([s["normal_stress"], friction_value(s)]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharex=True)
    cmap_n, cmap_f = cm.Blues, cm.Oranges
    for i, t in enumerate(times):
        sel = s["time"] == t
        order = np.argsort(pts[sel, axis])
        x = pts[sel, axis][order]
        shade = 0.3 + 0.7 * (i + 1) / len(times)
        axes[0].plot(x, friction_value({k: v[sel] for k, v in s.items()})[order] / fu, "-o", ms=3,
                     color=cmap_f(shade), label=f"t = {t:g} s")
        axes[1].plot(x, s["normal_stress"][sel][order] / fu, "-o", ms=3, color=cmap_n(shade),
                     label=f"t = {t:g} s")
    axes[0].set_ylabel(f"friction stress [{fname}]")
    axes[1].set_ylabel(f"normal contact stress [{fname}]")
    axes[0].set_title(r"friction stress along $\Gamma_c$")
    axes[1].set_title(r"normal contact stress along $\Gamma_c$")
    for ax in axes:
        ax.set_xlabel(f"{coord} on $\\Gamma_c$ [m]")
        ax.grid(alpha=0.3)
        ax.axhline(0, color="0.5", lw=0.6)
    axes[1].legend(fontsize=7, ncol=2, title="darker = later", title_fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_contact_stress_3d(run, title, path, times=None):
    s = run.stress
    written = np.unique(s["time"])
    if times:
        chosen = sorted({written[np.argmin(abs(written - t))] for t in times})
    else:
        chosen = list(written)
    pts = np.column_stack([s[a] for a in ("x", "y", "z")])
    a, b = along_axes(pts, 2)
    fu, fname = stress_unit(s["normal_stress"])
    # One colour scale for the whole run: at a time without contact the round-off stresses
    # stay at the bottom of it instead of being stretched into a peak.
    vmax = np.nanmax(s["normal_stress"]) / fu
    vmin = min(0.0, np.nanmin(s["normal_stress"]) / fu)
    fig, axes = plt.subplots(1, len(chosen), figsize=(4.2 * len(chosen) + 1, 4.0), squeeze=False,
                             sharey=True)
    axes = axes[0]
    for ax, t in zip(axes, chosen):
        sel = s["time"] == t
        p = s["normal_stress"][sel] / fu
        P = pts[sel]
        try:
            pc = ax.tripcolor(P[:, a], P[:, b], p, shading="gouraud", vmin=vmin, vmax=vmax,
                              cmap="viridis")
        except Exception:  # too few points for a triangulation
            pc = ax.scatter(P[:, a], P[:, b], c=p, vmin=vmin, vmax=vmax, cmap="viridis")
        ax.scatter(P[:, a], P[:, b], c="k", s=6)
        ax.set_aspect("equal")
        ax.set_xlabel(f"{'xyz'[a]} [m]")
        ax.set_title(f"t = {t:g} s")
    axes[0].set_ylabel(f"{'xyz'[b]} [m]")
    fig.colorbar(pc, ax=list(axes), label=f"normal contact stress [{fname}]", shrink=0.9)
    fig.suptitle(title + r": normal contact stress on $\Gamma_c$")
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_history(run, title, path):
    h = run.history
    if h is None:
        return False
    fu, fname = stress_unit(np.concatenate([h["normal_stress"], h["friction_stress"]]))
    node = marked_node(run)
    where = ""
    if node is not None:
        where = " at (" + ", ".join(f"{v:g}" for v in run.X[node]) + ") m"
    # Frictionless runs: the tangential "stress" is only the solver's residual; not drawn.
    has_friction = run.friction != 0 and np.any(np.abs(h["friction_stress"]) > 0)
    fig, axes = plt.subplots(1, 2 if has_friction else 1, figsize=(11 if has_friction else 6, 4),
                             squeeze=False)
    axes = axes[0]
    axes[0].plot(h["time"], h["normal_stress"] / fu, "-", color="tab:blue", lw=1.5)
    axes[0].set_ylabel(f"normal contact stress [{fname}]")
    axes[0].set_title("contact stress" + where, fontsize=10)
    if has_friction:
        label = "friction stress" if run.dim == 2 else "|friction stress|"
        axes[1].plot(h["time"], h["friction_stress"] / fu, "-", color="tab:orange", lw=1.5)
        axes[1].set_ylabel(f"{label} [{fname}]")
        axes[1].set_title(label + where, fontsize=10)
    for ax in axes:
        ax.set_xlabel("time [s]")
        ax.grid(alpha=0.3)
        ax.axhline(0, color="0.5", lw=0.6)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return True


def plot_compare(runs, labels, time, title, path):
    first = runs[0]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharex=True)
    rows_all = []
    time = time if time is not None else first.contact_time()
    for run in runs:
        t, rows = run.stress_at(time)
        rows_all.append((t, rows))
    fu, fname = stress_unit(np.concatenate([np.concatenate([r["normal_stress"], friction_value(r)])
                                            for _, r in rows_all]))
    pts0 = np.column_stack([rows_all[0][1][a] for a in ("x", "y")])
    axis = along_axes(pts0, 1)[0]
    styles = ["-o", "--s", ":^", "-.v"]
    for k, ((t, rows), label) in enumerate(zip(rows_all, labels)):
        x = rows["xy"[axis]]
        order = np.argsort(x)
        axes[0].plot(x[order], friction_value(rows)[order] / fu, styles[k % 4], ms=4, label=label)
        axes[1].plot(x[order], rows["normal_stress"][order] / fu, styles[k % 4], ms=4, label=label)
    t_shown = rows_all[0][0]
    axes[0].set_ylabel(f"friction stress [{fname}]")
    axes[1].set_ylabel(f"normal contact stress [{fname}]")
    axes[0].set_title(rf"friction stress along $\Gamma_c$, t = {t_shown:g} s")
    axes[1].set_title(rf"normal contact stress along $\Gamma_c$, t = {t_shown:g} s")
    for ax in axes:
        ax.set_xlabel(f"{'xy'[axis]} on $\\Gamma_c$ [m]")
        ax.grid(alpha=0.3)
        ax.axhline(0, color="0.5", lw=0.6)
        ax.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    del first


# ---------------------------------------------------------------------------- main
def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="figures of one run")
    p.add_argument("run_dir")
    p.add_argument("--scene", required=True)
    p.add_argument("--prefix", required=True, help="output path prefix, e.g. figs/curved_fc0.5")
    p.add_argument("--title", default=None)
    p.add_argument("--arrows", action="store_true", help="3D: arrows along u (figs. 18, 20)")
    p.add_argument("--time", type=float, default=None,
                   help="time of the mesh picture (default: the written time with the largest "
                        "contact stresses, a moment in contact)")
    p.add_argument("--stress-times", type=float, nargs="*", default=None,
                   help="3D: times of the contact-stress maps (default: all written)")
    c = sub.add_parser("compare", help="stresses along Gamma_c of several runs at one time")
    c.add_argument("runs", nargs="+", help="RUN_DIR=LABEL")
    c.add_argument("--scene", required=True)
    c.add_argument("--out", required=True)
    c.add_argument("--time", type=float, default=None)
    c.add_argument("--title", default=None)
    args = parser.parse_args()

    with open(args.scene, "rb") as f:
        scene = tomllib.load(f)
    if args.command == "run":
        run = Run(args.run_dir)
        title = args.title or scene.get("name", os.path.basename(args.run_dir))
        os.makedirs(os.path.dirname(os.path.abspath(args.prefix)), exist_ok=True)
        written = []
        time = args.time if args.time is not None else run.contact_time()
        if run.dim == 2:
            plot_mesh_2d(run, scene, title, args.prefix + "_mesh.png", time=time)
            plot_contact_stress_2d(run, title, args.prefix + "_contact_stress.png")
        else:
            plot_mesh_3d(run, scene, title, args.prefix + "_mesh.png", time=time, arrows=args.arrows)
            plot_contact_stress_3d(run, title, args.prefix + "_contact_stress.png", args.stress_times)
        written += [args.prefix + "_mesh.png", args.prefix + "_contact_stress.png"]
        if plot_history(run, title, args.prefix + "_history.png"):
            written.append(args.prefix + "_history.png")
        for w in written:
            print(w)
    else:
        runs, labels = [], []
        for spec in args.runs:
            d, _, label = spec.partition("=")
            runs.append(Run(d))
            labels.append(label or os.path.basename(d))
        plot_compare(runs, labels, args.time, args.title or scene.get("name", ""), args.out)
        print(args.out)


if __name__ == "__main__":
    main()
