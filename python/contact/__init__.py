"""Dynamic contact of an elastic body with a rigid obstacle, from Python.

    scene = contact.load_scene("examples/thesis/friction_2d_flat.toml")
    result = contact.run(scene, progress=True)
    result.times, result.records["kinetic"], result.normal_force[-1], result.nodes

A scene is a TOML file (keys and units: examples/scenes/README.md) or the same content as a
nested dict (``scene_from_dict``).  ``run`` writes no files: it returns NumPy arrays.
Units: s, m, N, Pa, J.  A bad scene raises ValueError (contact.SceneError) naming the key.
"""
import math
import os
import sys
import tempfile
import time as _time

import numpy as np

from ._contact import STEP_FIELDS, SUMMARY_FIELDS, Scene, SceneError, load_scene
from . import _contact

__all__ = ["load_scene", "scene_from_dict", "run", "Result", "Scene", "SceneError", "STEP_FIELDS",
           "SUMMARY_FIELDS"]


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


def scene_from_dict(scene, base_dir="."):
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
        return load_scene(path)
    except SceneError as e:  # name the dict, not the temporary file
        raise SceneError(str(e).replace(path, "<scene dict>")) from None
    finally:
        os.unlink(path)


class Result:
    """What a run returned.  Arrays (units in brackets):

    times (steps,) [s]                   records: {field: (steps,)} per StepRecord field
    summary: dict (status, message, steps, newton_iterations, max_penetration [m], ...)
    output_times (T,) [s]                displacement (T, nodes, dim) [m]
    normal_force (T, C) [N]              tangent_force (T, C, dim-1) [N]
    normal_stress (T, C) [Pa]            tangent_stress (T, C, dim-1) [Pa]
    gap (T, C) [m] (< 0: penetration)    contact_node (C,), contact_coordinates (C, dim) [m],
    contact_area (C,) [m^2]              nodes (N, dim) [m], elements (E, k), element_type
    with contact_history (every step):   history_normal_force (steps, C) [N],
    history_tangent_force (steps, C, dim-1) [N], history_gap (steps, C) [m]
    """

    def __init__(self, raw):
        self.__dict__.update(raw)
        self.times = self.records["time"]
        self.normal_stress = self.normal_force / self.contact_area
        self.tangent_stress = self.tangent_force / self.contact_area[None, :, None]

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


def _progress_bar(stream=None, width=40, interval_s=0.2):
    """A text progress bar on `stream` (None: sys.stderr at the time of drawing), redrawn at
    most every interval_s seconds."""
    last = [0.0]

    def draw(step, t, end_time):
        out = stream or sys.stderr
        now = _time.monotonic()
        done = t >= end_time * (1 - 1e-12)
        if now - last[0] < interval_s and not done:
            return
        last[0] = now
        fraction = min(t / end_time, 1.0) if end_time > 0 else 1.0
        filled = int(round(width * fraction))
        out.write(f"\r[{'#' * filled}{'.' * (width - filled)}] step {step}  t = {t:.4g} s")
        if done:
            out.write("\n")
        out.flush()
    return draw


def run(scene, every=0, contact_history=True, progress=None, base_dir="."):
    """Runs a scene (a Scene, a path to a scene file, or a dict) and returns a Result.

    Snapshots (displacements, contact forces, gaps) are taken at the scene's stress_times,
    at every `every`-th step (0: none) and at the last step.  contact_history keeps the
    contact forces and gaps of every step (steps x contact nodes x (dim + 1) floats).
    progress: True for a text bar on stderr, or a callable(step, time, end_time) called
    after every step."""
    if isinstance(scene, dict):
        scene = scene_from_dict(scene, base_dir)
    elif isinstance(scene, (str, os.PathLike)):
        scene = load_scene(os.fspath(scene))
    elif not isinstance(scene, Scene):
        raise ValueError(f"contact.run: scene must be a Scene, a path or a dict, got {type(scene).__name__}")
    if progress is True:
        progress = _progress_bar()
    elif progress is False:
        progress = None
    return Result(_contact.run(scene, int(every), bool(contact_history), progress))
