"""Dynamic contact of an elastic body with a rigid obstacle, from Python.

    result = contact.run(contact.example_path("thesis/friction_2d_flat.toml"), progress=True)
    result.times, result.records["kinetic_energy"], result.normal_force[-1], result.nodes

    sim = contact.Simulation(contact.example_path("scenes/block_drop_2d.toml"))
    while sim.step(10) == "running":  # look at sim.contact, change the loads, move the obstacle
        sim.set_body_force([20000.0 if sim.time < 0.01 else 0.0, -76518.0])  # [N/m^3]

A scene is a TOML file (keys and units: examples/scenes/README.md) or the same content as a
nested dict (``scene_from_dict``).  ``run`` writes no files: it returns NumPy arrays.
Units: s, m, N, Pa, J.  A bad scene raises ValueError (contact.SceneError) naming the key.
The record names are the columns of contact-sim's steps.csv.
"""
import math
import os
import sys
import tempfile
import time as _time
import warnings as _warnings

import numpy as np

from ._contact import STEP_FIELDS, SUMMARY_FIELDS, CheckpointError, Scene, SceneError
from . import _contact
from ncp import _did_you_mean  # one suggestion rule for both packages
from ncp import __version__  # one version for both packages and the CLIs

__all__ = ["load_scene", "scene_from_dict", "run", "Simulation", "example_path", "Result", "Scene",
           "SceneError", "CheckpointError", "STEP_FIELDS", "SUMMARY_FIELDS", "OVERRIDES"]

#: Keyword overrides of ``load_scene`` and ``run`` -> scene keys (contact-sim's --dt, ...).
OVERRIDES = {"dt": "time.dt", "end_time": "time.end_time", "friction": "friction.coefficient",
             "tolerance": "solver.tolerance", "solver": "solver.method", "step": "solver.step",
             "friction_formulation": "solver.friction"}

#: Record names before they were made equal to the columns of steps.csv.
_RENAMED_RECORDS = {"kinetic": "kinetic_energy", "strain": "strain_energy",
                    "tangent_force_sum": "friction_force_sum"}


#: Result arrays before they were named like contact_stress.csv's columns.
_RENAMED_ARRAYS = {"tangent_force": "friction_force", "tangent_stress": "friction_stress",
                   "history_tangent_force": "history_friction_force"}


def _examples_dirs():
    """Where the example scenes may be: $NCP_EXAMPLES_DIR, the installed
    <prefix>/share/ncp/examples (this package is <prefix>/lib/pythonX.Y/dist-packages/contact),
    and the source tree's examples/ when run from a build tree."""
    here = os.path.dirname(os.path.abspath(__file__))
    dirs = [os.environ.get("NCP_EXAMPLES_DIR", ""),
            os.path.normpath(os.path.join(here, "..", "..", "..", "..", "share", "ncp", "examples"))]
    try:
        from ._build_paths import SOURCE_EXAMPLES_DIR
        dirs.append(SOURCE_EXAMPLES_DIR)
    except ImportError:
        pass
    return [d for d in dirs if d and os.path.isdir(d)]


def example_path(name):
    """Absolute path of a shipped example, e.g. example_path("scenes/block_drop_2d.toml") or
    example_path("thesis/friction_3d.toml"), wherever the package is used from."""
    dirs = _examples_dirs()
    for d in dirs:
        path = os.path.join(d, name)
        if os.path.exists(path):
            return path
    raise FileNotFoundError(f"contact: no example {name!r} in {dirs or 'any examples directory'} "
                            "(set NCP_EXAMPLES_DIR to the repository's examples/)")


def _override_list(overrides):
    """[(scene key, TOML literal)] from run's / load_scene's keyword overrides."""
    out = []
    for name, value in overrides.items():
        if name not in OVERRIDES:
            raise ValueError(f"contact: unknown override {name!r}{_did_you_mean(name, OVERRIDES)}; "
                             f"overrides are {', '.join(OVERRIDES)}")
        if value is not None:
            out.append((OVERRIDES[name], _toml_value(value, OVERRIDES[name])))
    return out


def load_scene(path, **overrides):
    """Reads and validates a scene file.  A relative path is relative to the working
    directory; the shipped scenes are at example_path(...).  Keyword overrides
    (OVERRIDES: dt, end_time, friction, tolerance, solver, step, friction_formulation)
    pass the same checks as the file's values."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise SceneError(f"cannot read scene file '{path}': no such file (relative paths are "
                         f"relative to the working directory {os.getcwd()}; the shipped examples: "
                         "contact.example_path(\"scenes/block_drop_2d.toml\"))")
    return _contact.load_scene(path, _override_list(overrides))


def _toml_value(value, key):
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(float(value))
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    raise ValueError(f"contact: scene key {key!r} has a value of type {type(value).__name__}")


def _toml(d, prefix=""):
    """TOML text of a nested dict: scalars and arrays first, then one [table] per sub-dict."""
    lines, tables = [], []
    for key, value in d.items():
        if isinstance(value, dict):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {_toml_value(value, prefix + key)}")
    for key, value in tables:
        lines.append(f"\n[{prefix}{key}]")
        lines.append(_toml(value, f"{prefix}{key}."))
    return "\n".join(lines)


def scene_from_dict(scene, base_dir=".", **overrides):
    """A Scene from a nested dict with the keys of a scene file, checked exactly like a
    file.  Relative paths in it (geometry.file, output.directory) are relative to base_dir;
    the scene's name defaults to "scene-dict"."""
    if not isinstance(scene, dict):
        raise ValueError(f"contact: scene_from_dict needs a dict, got {type(scene).__name__}")
    scene = {k: dict(v) if isinstance(v, dict) else v for k, v in scene.items()}
    scene.setdefault("name", "scene-dict")
    for table, key in (("geometry", "file"), ("output", "directory")):
        value = scene.get(table, {}).get(key) if isinstance(scene.get(table), dict) else None
        if isinstance(value, str):
            scene[table][key] = os.path.join(os.path.abspath(base_dir), value)
    text = _toml(scene) + "\n"  # before any file exists: a bad value raises here
    with tempfile.NamedTemporaryFile("w", suffix=".toml", prefix="scene-", delete=False) as f:
        f.write(text)
        path = f.name
    try:
        return load_scene(path, **overrides)
    except SceneError as e:  # name the dict, not the temporary file
        raise SceneError(str(e).replace(path, "<scene dict>")) from None
    finally:
        os.unlink(path)


class Result:
    """What a run returned.  Arrays (units in brackets):

    times (steps,) [s]                   records: {name: (steps,)}, the names of steps.csv's
                                         columns (STEP_FIELDS)
    summary: dict (status, message, steps, newton_iterations, max_penetration [m], ...)
    output_times (T,) [s]                displacement (T, nodes, dim) [m]
    normal_force (T, C) [N]              friction_force (T, C, dim-1) [N] along t1 (, t2)
    normal_stress (T, C) [Pa]            friction_stress (T, C, dim-1) [Pa]
    gap (T, C) [m] (< 0: penetration)    contact_node (C,), contact_coordinates (C, dim) [m],
    contact_area (C,) [m^2]              nodes (N, dim) [m], elements (E, k), element_type
    with contact_history (every step):   history_normal_force (steps, C) [N],
    history_friction_force (steps, C, dim-1) [N], history_gap (steps, C) [m]
    (the names of contact_stress.csv's columns and of the .vtu fields)
    """

    def __init__(self, raw):
        self.__dict__.update(raw)
        self.records = _Records(self.records)
        self.times = self.records["time"]
        self.normal_stress = self.normal_force / self.contact_area
        self.friction_stress = self.friction_force / self.contact_area[None, :, None]

    def __getattr__(self, name):  # only for names not set in __init__
        if name in _RENAMED_ARRAYS:
            raise AttributeError(f"contact.Result.{name} was renamed {_RENAMED_ARRAYS[name]}")
        raise AttributeError(f"contact.Result has no {name!r}")

    def nearest_contact_node(self, point):
        """Index c (into the contact arrays) of the contact node nearest to point [m]."""
        point = np.asarray(point, dtype=float)
        if point.shape != (self.contact_coordinates.shape[1],):
            raise ValueError(f"contact: point must have {self.contact_coordinates.shape[1]} coordinates")
        return int(np.argmin(np.linalg.norm(self.contact_coordinates - point, axis=1)))

    @property
    def completed(self):
        return self.summary["status"] == "completed"

    def __repr__(self):
        s = self.summary
        return (f"<contact.Result {s['status']}: {s['steps']} steps, {s['newton_iterations']} Newton "
                f"iterations, max penetration {s['max_penetration']:.3g} m, "
                f"{len(self.output_times)} output times, {len(self.contact_node)} contact nodes>")


class _Records(dict):
    """{name: array}; a name used before the records were named like steps.csv's columns
    raises KeyError naming the new one."""

    def __missing__(self, key):
        if key in _RENAMED_RECORDS:
            raise KeyError(f"record {key!r} was renamed {_RENAMED_RECORDS[key]!r} (the steps.csv column)")
        raise KeyError(key)


def _duration(seconds):
    """'42 s', '3 min 05 s', '1 h 02 min'."""
    s = int(round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s // 3600} h {(s % 3600) // 60:02d} min"


def progress_text(fraction, elapsed_s):
    """'37.5 %, 12 s elapsed, ETA 20 s': the remaining time extrapolated at the mean rate so
    far, elapsed * (1 - fraction) / fraction (no ETA before any progress)."""
    text = f"{100 * fraction:5.1f} %, {_duration(elapsed_s)} elapsed"
    if fraction >= 1:
        return text
    if fraction > 0:
        return text + f", ETA {_duration(elapsed_s * (1 - fraction) / fraction)}"
    return text + ", ETA --"


def _progress_bar(stream=None, width=30, interval_s=0.2, start_time=0.0):
    """A text progress bar with percent, elapsed time and ETA on `stream` (None: sys.stderr
    at the time of drawing), redrawn at most every interval_s seconds."""
    last = [-math.inf]
    started = _time.monotonic()

    def draw(step, t, end_time):
        out = stream or sys.stderr
        now = _time.monotonic()
        done = t >= end_time - 1e-12 * max(abs(end_time), 1.0)
        if now - last[0] < interval_s and not done:
            return
        last[0] = now
        span = end_time - start_time
        fraction = min(max((t - start_time) / span, 0.0), 1.0) if span > 0 else 1.0
        filled = int(round(width * fraction))
        out.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {progress_text(fraction, now - started)}"
                  f"  step {step}, t = {t:.4g} s ")
        if done:
            out.write("\n")
        out.flush()
    return draw


def _scene_of(scene, base_dir, overrides, who):
    """A Scene from a Scene, a path or a dict (with the keyword overrides); its warnings
    (Scene.warnings: a stress time after the end, end_time < dt) as UserWarnings."""
    if isinstance(scene, dict):
        scene = scene_from_dict(scene, base_dir, **overrides)
    elif isinstance(scene, (str, os.PathLike)):
        scene = load_scene(scene, **overrides)
    elif not isinstance(scene, Scene):
        raise ValueError(f"{who}: scene must be a Scene, a path or a dict, got {type(scene).__name__}")
    elif overrides:
        raise ValueError(f"{who}: overrides need a path or a dict; set a Scene's dt, end_time "
                         "or tolerance directly")
    for message in scene.warnings:
        _warn(f"{who}: {message}")
    return scene


def _warn(message):
    """A UserWarning attributed to the user's line: the first frame outside this package
    (the line that called contact.run, contact.Simulation, ...), not a line of the library."""
    package = os.path.dirname(os.path.abspath(__file__))
    frame, level = sys._getframe(1), 2  # stacklevel 2: the caller of _warn
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == package:
        frame, level = frame.f_back, level + 1
    _warnings.warn(message, stacklevel=level)


class Simulation:
    """A scene integrated one step at a time (the C++ contact::Simulation): step, look at
    the state, change the body force or move the obstacle, step again.  ``contact.run`` is
    this loop to the end, so the numbers are the same.

        sim = contact.Simulation(contact.example_path("scenes/block_drop_2d.toml"))
        sim.step(100)                     # "running", "finished" or "failed"
        sim.time, sim.displacement, sim.contact["normal_force"]
        sim.set_body_force([0.0, 0.0])    # [N/m^3], from the next step on
        sim.move_obstacle([0.0, 1e-3])    # [m] from the scene's position (absolute)

    scene: a Scene, a path or a dict, with the overrides of ``run`` (dt, end_time, ...).
    Units: s, m, N, N/m^3.  Properties (NumPy arrays, new on every access):

    time [s], step_index, num_steps, dt [s], end_time [s], state, completed
    displacement (nodes, dim) [m]: u^k of every node
    velocity (nodes, dim) [m/s]: (u^k - u^{k-1}) / dt, the last step's mean velocity
    contact: {"normal_force" (C,) [N], "friction_force" (C, dim-1) [N] along t1 (, t2),
              "gap" (C,) [m], "state" (C,) 0 open, 1 stick, 2 slip} - after the last
              step; before the first, the initial state (NaN forces for a prescribed start)
    contact_gaps (C,) [m]: s_c, the gaps at u = 0 for the obstacle where it is now
    summary: dict as Result.summary (status "not-run" until the end), records: {name: (steps,)}
    body_force (dim,) [N/m^3], obstacle_translation (dim,) [m]

    Checkpoints: ``sim.save(path)`` writes the state; ``contact.Simulation.load(path, scene)``
    continues from it (same scene and overrides, else contact.CheckpointError) and steps on
    exactly as the Simulation that was saved.
    """

    def __init__(self, scene, base_dir=".", **overrides):
        self._start(_scene_of(scene, base_dir, overrides, "contact.Simulation"))

    def _start(self, scene):
        self._scene = scene
        self._core = _contact.Simulation(scene)

    def step(self, n=1, progress=None):
        """Takes up to n steps (an int >= 0), stopping at end_time or on a failure.  Returns
        the state: "running", "finished" (summary["status"] says completed or
        accuracy-not-reached) or "failed" (summary["message"] says why).  progress: a
        callable(step, time, end_time) called after every step."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
            raise ValueError(f"contact.Simulation.step: n must be an int >= 0, got {n!r}")
        if n < 0:
            raise ValueError(f"contact.Simulation.step: n must be >= 0, got {n}")
        return self._core.step(int(n), progress)

    def set_body_force(self, body_force):
        """The body force density [N/m^3] (dim components, finite; gravity: rho g) from the
        next step on, with the scene's traction and load history."""
        self._core.set_body_force(_finite_vector(body_force, "body force"))

    def move_obstacle(self, translation):
        """Moves the obstacle rigidly to `translation` [m] (dim components) from its position
        in the scene - absolute, not an increment.  The gaps s_c are recomputed from the moved
        obstacle; the contact frames (normals) are kept (small displacements)."""
        self._core.move_obstacle(_finite_vector(translation, "obstacle translation"))

    def save(self, path):
        """Writes the state after the current step to `path` (binary, atomically: path.partial
        renamed when complete): everything the next steps read, the summary with every step's
        record, the body force and obstacle translation, and the scene's text and hash.
        Raises RuntimeError naming the file and the reason if it cannot be written."""
        self._core.save(os.fspath(path))

    @classmethod
    def load(cls, path, scene, base_dir=".", **overrides):
        """The Simulation of `scene` (a Scene, a path or a dict, with the overrides of
        ``run``) continued from the checkpoint at `path`: its steps from there are those of
        the Simulation that was saved, bit for bit.  Raises contact.CheckpointError (a
        ValueError) when the file is missing, truncated or corrupt or of another scene (the
        message names both hashes and the first line that differs).  ``result()`` holds the
        snapshots of the steps after the load (as the uninterrupted run's after the checkpoint's
        step); ``records`` and ``summary`` all steps."""
        sim = cls(scene, base_dir, **overrides)
        sim._core.load_checkpoint(os.fspath(path))
        return sim

    @property
    def completed(self):
        """True once end_time is reached with every step accurate (summary status completed)."""
        return self._core.summary["status"] == "completed"

    def result(self):
        """The steps so far as a contact.Result (snapshots only at the stress times and the end
        when stepped by hand; ``run`` sets what it collects)."""
        return Result(self._core.result())

    def __getattr__(self, name):  # the core's read-only properties
        if name in ("time", "step_index", "num_steps", "dt", "end_time", "dim", "state",
                    "displacement", "velocity", "contact", "contact_gaps", "summary",
                    "body_force", "obstacle_translation"):
            return getattr(self._core, name)
        if name == "records":
            return _Records(self._core.records)
        raise AttributeError(f"contact.Simulation has no {name!r}")

    def __repr__(self):
        return (f"<contact.Simulation '{self._scene.name}' {self.state}: step {self.step_index} of "
                f"{self.num_steps}, t = {self.time:.6g} s>")


def _finite_vector(value, what):
    """A float64 vector from value, refused (ValueError naming what) if it has a NaN or inf."""
    a = np.asarray(value, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"contact.Simulation: the {what} must be a vector, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"contact.Simulation: the {what} must be finite, got {a.tolist()}")
    return a


def run(scene, every=0, contact_history=True, progress=None, base_dir=".", **overrides):
    """Runs a scene (a Scene, a path to a scene file, or a dict) and returns a Result.

    Snapshots (displacements, contact forces, gaps) are taken at the scene's stress_times,
    at every `every`-th step (0: none) and at the last step.  contact_history keeps the
    contact forces and gaps of every step (steps x contact nodes x (dim + 1) floats).
    progress: True for a text bar on stderr (percent, elapsed time, ETA), or a
    callable(step, time, end_time) called after every step.  overrides (with a path or a
    dict): dt, end_time, friction, tolerance, solver, step, friction_formulation, checked
    like the scene file's values.  result.records holds the columns of steps.csv.
    The loop of a Simulation to the end: contact.Simulation steps the same integrator."""
    scene = _scene_of(scene, base_dir, overrides, "contact.run")
    if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 0:
        raise ValueError(f"contact.run: every must be >= 0 (an int), got {every!r}")
    if progress is True:
        progress = _progress_bar(start_time=scene.start_time)
    elif progress is False:
        progress = None
    sim = Simulation.__new__(Simulation)  # (the scene's warnings were given above, once)
    sim._start(scene)
    sim._core.record(int(every), bool(contact_history))
    sim._core.step(sys.maxsize, progress)
    return sim.result()
