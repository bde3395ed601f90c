"""Every message names what to change: each key or option a message
suggests is fed back and must be accepted; paths in messages are resolved; no C++ function
names reach a scene user; warnings for what a user probably did not mean; Python setters
validate at once; contact-sim --quiet prints a refusal once and nothing else."""
import math
import os
import re
import subprocess

import pytest

import contact
import ncp
from contact import _contact

HERE = os.path.dirname(os.path.abspath(__file__))
DROP = os.path.join(HERE, "..", "..", "examples", "scenes", "block_drop_2d.toml")


def scene_text(**replace):
    """block_drop_2d.toml with lines replaced: {"old line start": "new line"}."""
    with open(DROP) as f:
        lines = f.read().splitlines()
    for old, new in replace.items():
        hits = [i for i, line in enumerate(lines) if line.startswith(old)]
        assert len(hits) == 1, old
        lines[hits[0]] = new
    return "\n".join(lines) + "\n"


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(re.sub(r'(?m)^directory = .*$', 'directory = "out"', text))
    return str(path)


def load_error(path, overrides=()):
    with pytest.raises(contact.SceneError) as e:
        _contact.load_scene(path, list(overrides))
    return str(e.value)


def test_unstable_time_step_names_the_scene_key_it_suggests(tmp_path):
    path = write(tmp_path, scene_text())
    big_dt = [("time.dt", "1e-3"), ("time.end_time", "3e-3")]
    r = contact.run(_contact.load_scene(path, big_dt))
    assert r.summary["status"].startswith("refused-unstable"), r.summary
    message = r.summary["message"]
    keys = re.findall(r"set (time\.\w+) = (\w+) in the scene", message)
    assert keys == [("time.allow_unstable", "true")], message
    # The suggested key, fed back, is accepted and runs the steps.
    r = contact.run(_contact.load_scene(path, big_dt + keys))
    assert r.summary["steps"] == 3 and not r.summary["status"].startswith("refused"), r.summary
    # The dt it suggests is stable.
    dt_max = float(re.search(r"choose dt <= ([0-9.e+-]+) s \(scene key time.dt\)", message).group(1))
    r = contact.run(_contact.load_scene(path, [("time.dt", repr(0.99 * dt_max)), ("time.end_time", "2e-3")]))
    assert r.completed, r.summary


def test_misspelt_table_and_key_get_a_suggestion_that_loads(tmp_path):
    message = load_error(write(tmp_path, scene_text(**{"[material]": "[materail]"})))
    assert "'materail'" in message and "typo" in message, message
    message = load_error(write(tmp_path, scene_text(**{"[solver]": "[solvr]"})))
    guess = re.search(r"did you mean '(\w+)'", message)
    assert "unknown table [solvr]" in message and guess and guess.group(1) == "solver", message
    message = load_error(write(tmp_path, scene_text(**{"young_modulus": "young_modulos = 2e8"})))
    assert "'material.young_modulos'" in message and "material.young_modulus" in message, message
    message = load_error(write(tmp_path, scene_text(**{"snapshot_every": "snapshot_evry = 100"})))
    guess = re.search(r"did you mean '([\w.]+)'", message).group(1)
    table, key = guess.split(".")
    assert table == "output", message
    fixed = scene_text(**{"snapshot_every": f"{key} = 100"})
    assert _contact.load_scene(write(tmp_path, fixed), []).dim == 2


def test_missing_mesh_shows_the_resolved_path(tmp_path):
    text = scene_text(**{"type = \"rectangle\"": "type = \"msh\"\nfile = \"../meshes/none.msh\"\ndimension = 2"})
    text = re.sub(r"(?m)^(origin|size|cells|element|contact) = .*\n", "", text)
    os.makedirs(tmp_path / "scenes")
    message = load_error(write(tmp_path / "scenes", text))
    resolved = os.path.normpath(str(tmp_path / "meshes" / "none.msh"))
    assert resolved in message and "geometry.file" in message, message


def test_body_inside_the_obstacle_gets_a_fix_and_no_function_name(tmp_path):
    path = write(tmp_path, scene_text(**{"offset = -0.001": "offset = 0.01"}))
    with pytest.raises(contact.SceneError) as e:
        contact.run(path, end_time=1e-4)
    message = str(e.value)
    assert "starts inside the obstacle" in message and "move the obstacle" in message, message
    assert not re.search(r"\b[A-Z]\w*(::\w+)*: ", message.split(": ", 1)[1]), message
    depth = float(re.search(r"by ([0-9.e+-]+) m", message).group(1))
    assert math.isclose(depth, 0.01, rel_tol=1e-9), message


def test_warnings_for_stress_times_past_the_end_and_end_time_below_dt(tmp_path):
    scene = _contact.load_scene(write(tmp_path, scene_text(**{"stress_times": "stress_times = [0.005, 0.5]"})), [])
    assert len(scene.warnings) == 1 and "output.stress_times" in scene.warnings[0] and "0.5" in scene.warnings[0]
    scene = _contact.load_scene(DROP, [("time.end_time", "1e-5")])
    assert any("time.end_time" in w and "time.dt" in w for w in scene.warnings), scene.warnings
    assert _contact.load_scene(DROP, []).warnings == []
    with pytest.warns(UserWarning, match="stress_times"):
        contact.run(write(tmp_path, scene_text(**{"stress_times": "stress_times = [0.5]"})), end_time=1e-4)


@pytest.mark.parametrize("name, value", [("dt", -1.0), ("dt", float("nan")), ("end_time", 0.0),
                                         ("tolerance", 2.0), ("stress_times", [0.1, float("inf")])])
def test_python_setters_validate_at_once(name, value):
    scene = contact.load_scene(DROP)
    before = getattr(scene, name)
    with pytest.raises(contact.SceneError, match=rf"contact.Scene.{name} = .* accepted range"):
        setattr(scene, name, value)
    assert getattr(scene, name) == before or (isinstance(before, float) and math.isnan(before))


def test_python_options_suggest_the_name():
    with pytest.raises(ValueError, match="did you mean 'tolerance'"):
        ncp.make_options(tol=1e-8)
    with pytest.raises(ValueError, match="did you mean 'end_time'"):
        contact.load_scene(DROP, end_tme=1.0)


def test_quiet_prints_a_refusal_once_and_nothing_else(bin_dir):
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built")
    p = subprocess.run([exe, DROP, "--quiet", "--no-output", "--dt", "1e-3"], capture_output=True, text=True)
    assert p.returncode == 1 and p.stdout == "", (p.stdout, p.stderr)
    assert p.stderr.count("exceeds the critical step") == 1 and len(p.stderr.strip().splitlines()) == 1, p.stderr
    p = subprocess.run([exe, DROP, "--no-output", "--dt", "1e-3"], capture_output=True, text=True)
    assert (p.stdout + p.stderr).count("exceeds the critical step") == 1, (p.stdout, p.stderr)
