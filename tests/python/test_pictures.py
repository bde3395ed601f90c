"""Pictures of snapshots, checked for what they show, not only for being written: the 2D
plot draws the obstacle where the scene puts it (the plane y = offset, from the snapshot's
gap and contact_normal), the time, the displacement scale, a colour bar and legend that stay
off the body, and the body itself (non-background pixels inside its box); the 3D render
(VTK off screen), from Python and from examples/plot/render_snapshot.py, has the body in its
box; the moment chosen by default is one in contact; plot_scene.py picks it too."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("vtk")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

import contact.vtu  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")
OFFSET = -0.001  # [m] the floor: y <= OFFSET (2D), z <= OFFSET (3D)

SCENE_2D = f"""
name = "picture-2d"
[geometry]
type = "rectangle"
size = [1.0, 0.2]
cells = [10, 2]
contact = ["ymin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
[loads]
body_force = [20000.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 1.0]
offset = {OFFSET}
[friction]
coefficient = 0.3
[time]
dt = 5e-5
end_time = 0.012
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[output]
directory = "out"
snapshot_every = 20
stress_times = [0.001, 0.003, 0.005]
"""

SCENE_3D = f"""
name = "picture-3d"
[geometry]
type = "box"
origin = [0.0, 0.0, 0.0]
size = [0.2, 0.2, 0.1]
cells = [4, 4, 2]
element = "hex8"
contact = ["zmin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
[loads]
body_force = [0.0, 0.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 0.0, 1.0]
offset = {OFFSET}
[time]
dt = 1e-4
end_time = 0.004
initial_state = "velocity"
initial_velocity = [0.0, 0.0, -0.5]
[output]
directory = "out"
snapshot_every = 10
"""


def run_scene(directory, text, bin_dir):
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built")
    (directory / "scene.toml").write_text(text)
    subprocess.run([exe, "scene.toml", "--quiet"], cwd=directory, check=True, timeout=120)
    return directory / "out"


@pytest.fixture(scope="module")
def run_2d(tmp_path_factory, bin_dir):
    return run_scene(tmp_path_factory.mktemp("pictures2d"), SCENE_2D, bin_dir)


@pytest.fixture(scope="module")
def run_3d(tmp_path_factory, bin_dir):
    return run_scene(tmp_path_factory.mktemp("pictures3d"), SCENE_3D, bin_dir)


def painted_fraction(png, box):
    """The fraction of pixels in box (left, top, right, bottom) that are not the white
    background."""
    image = matplotlib.image.imread(png)[..., :3]
    left, top, right, bottom = (int(round(v)) for v in box)
    inside = image[max(top, 0):bottom, max(left, 0):right]
    assert inside.size > 0, (box, image.shape)
    return float(np.mean(np.any(inside < 0.95, axis=-1)))


def overlaps(a, b):
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_in_contact_picks_the_snapshot_with_the_largest_contact_force(run_2d):
    chosen = contact.vtu.in_contact(str(run_2d))
    forces = {path: np.nansum(np.linalg.norm(contact.vtu.read(path)["point_data"]["normal_force"], axis=1))
              for _, path in contact.vtu.series(str(run_2d))}
    assert forces[chosen] == max(forces.values()) > 0
    assert forces[contact.vtu.series(str(run_2d))[-1][1]] < forces[chosen]  # not the end


def test_plot_draws_obstacle_time_and_scale_and_keeps_bar_and_legend_off_the_body(run_2d, tmp_path):
    path = contact.vtu.in_contact(str(run_2d))
    snap = contact.vtu.read(path)
    png = tmp_path / "plot.png"
    fig = contact.vtu.plot(path, str(png), magnify=20)
    ax = fig.axes[0]
    # The obstacle: its surface line lies on y = OFFSET (the scene's plane), across the body.
    line = next(l for l in ax.get_lines() if l.get_label() == "obstacle")
    x, y = line.get_data()
    np.testing.assert_allclose(y, OFFSET, rtol=0, atol=1e-12)
    assert x.min() < snap["points"][:, 0].min() and x.max() > snap["points"][:, 0].max()
    # The time (from solution.pvd), the displacement scale, the largest displacement.
    title = fig._suptitle.get_text()
    assert f"t = {snap['time']:.6g} s" in title and "displacements drawn x 20" in title, title
    u_max = np.linalg.norm(snap["point_data"]["displacement"], axis=1).max()
    assert float(re.search(r"largest \|u\| = ([0-9.e+-]+) m", title).group(1)) == pytest.approx(u_max, rel=1e-2)
    # The colour bar and the legend stay off the body's box.
    fig.canvas.draw()
    mesh = ax.collections[0]
    body = mesh.get_datalim(ax.transData).transformed(ax.transData)
    colorbar = fig.axes[1].get_window_extent()
    legend = ax.get_legend().get_window_extent()
    assert not overlaps(body, colorbar) and not overlaps(body, legend), (body, colorbar, legend)
    # The body is in the picture: most pixels in its box are painted (rows from the top;
    # the PNG has its own dpi).
    scale = matplotlib.image.imread(str(png)).shape[0] / fig.bbox.height
    height = fig.bbox.height
    box = (scale * body.x0, scale * (height - body.y1), scale * body.x1, scale * (height - body.y0))
    assert painted_fraction(str(png), box) > 0.8


def test_render_draws_a_3d_snapshot_with_the_body_in_its_box(run_3d, tmp_path):
    path = contact.vtu.in_contact(str(run_3d))
    picture = contact.vtu.render(path, str(tmp_path / "box.png"), size=(600, 400))
    left, top, right, bottom = picture.body_box
    assert 0 <= left < right <= 600 * 0.88 and 0 <= top < bottom <= 400, picture.body_box
    assert painted_fraction(picture.path, picture.body_box) > 0.3
    # Outside the body's box and the bar's strip, the corners are background.
    image = matplotlib.image.imread(picture.path)[..., :3]
    assert image.shape[:2] == (400, 600)
    assert np.all(image[:5, :5] > 0.95)


def test_the_render_script_draws_the_moment_in_contact(run_3d, tmp_path):
    png = tmp_path / "script.png"
    env = dict(os.environ)
    done = subprocess.run([sys.executable, os.path.join(EXAMPLES, "plot", "render_snapshot.py"),
                           str(run_3d), str(png), "--size", "600", "400"], capture_output=True,
                          text=True, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    snapshot = re.search(r"snapshot (\S+)", done.stdout).group(1)
    assert snapshot == contact.vtu.in_contact(str(run_3d))
    box = [float(v) for v in done.stdout.strip().split()[-4:]]
    assert painted_fraction(str(png), box) > 0.3


def test_plot_scene_picks_a_written_time_in_contact(run_2d):
    sys.path.insert(0, os.path.join(EXAMPLES, "plot"))
    try:
        import plot_scene
    finally:
        sys.path.pop(0)
    run = plot_scene.Run(str(run_2d))
    t = run.contact_time()
    stress, steps = run.stress, run.steps
    pressed = {}
    for s in np.unique(stress["time"]):
        accuracy = steps["force_accuracy"][np.argmin(np.abs(steps["time"] - s))]
        force = stress["normal_force"][stress["time"] == s]
        pressed[s] = force[force > accuracy].sum()
    assert pressed[t] == max(pressed.values()) > 0 and t != run.times[-1], (t, pressed)
    assert run.displacement(t)[0] == t  # the mesh picture's time is a written one
