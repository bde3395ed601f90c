"""Scene features from Python: Rayleigh damping's dissipation in the records and in
steps.csv (the energy balance closes with it), a punch moved by obstacle.motion, and the
refusals with their keys."""
import math
import os
import subprocess

import numpy as np
import pytest

import contact

# A block 1 m x 0.2 m on a clamped base (plane strain, nu = 0, lumped mass), a flat punch
# pressed 1 mm into its top by t = 0.02 s, then slid 10 mm by t = 0.06 s.
PUNCH = """
[geometry]
type = "rectangle"
size = [1.0, 0.2]
cells = [10, 2]
fixed = ["ymin"]
contact = ["ymax"]
[material]
young_modulus = 2e8
poisson_ratio = 0.0
density = 7800
mass = "lumped"
damping = {mass = 500.0}
[obstacle]
type = "plane"
normal = [0.0, -1.0]
offset = -0.2
normal_source = "obstacle"
motion = {time = [0.0, 0.02, 0.06], x = [0.0, 0.0, 0.01], y = [0.0, -1e-3, -1e-3]}
[friction]
coefficient = 0.3
[time]
dt = 5e-5
end_time = 0.06
[solver]
step = "explicit"
"""


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_punch_pressed_then_slid_pulls_mu_times_its_normal_force(tmp_path):
    result = contact.run(write(tmp_path, "punch.toml", PUNCH))
    assert result.completed, result.summary["message"]
    r = result.records
    # Uniaxial compression (nu = 0): N = E (delta / h) * 1 m * 1 m = 1e6 N once settled.
    assert r["normal_force_sum"][-1] == pytest.approx(1e6, rel=1e-3)
    assert r["friction_force_sum"][-1] == pytest.approx(0.3 * r["normal_force_sum"][-1], rel=1e-5)
    # The damper took energy, and the balance closes with it.
    assert r["damping_dissipation"][-1] > 0.0
    assert np.abs(r["energy_balance_error"]).max() < 1e-6 * r["strain_energy"][-1]


def test_steps_csv_has_the_damping_dissipation(tmp_path, bin_dir):
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built (NCP_BIN_DIR)")
    scene = write(tmp_path, "punch.toml", PUNCH.replace("end_time = 0.06", "end_time = 0.01"))
    out = tmp_path / "out"
    subprocess.run([exe, scene, "--quiet", "--output", str(out)], check=True, capture_output=True)
    steps = np.genfromtxt(out / "steps.csv", delimiter=",", names=True)
    assert "damping_dissipation" in steps.dtype.names
    assert steps["damping_dissipation"][-1] > 0.0
    assert np.all(np.diff(steps["damping_dissipation"]) > -1e-12 * steps["damping_dissipation"][-1])


@pytest.mark.parametrize("change,message", [
    (("step = \"explicit\"", "step = \"condensed\""), "needs solver.step = \"explicit\""),
    (("x = [0.0, 0.0, 0.01]", "x = [0.1, 0.0, 0.01]"), "'obstacle.motion' must start"),
    (("damping = {mass = 500.0}", "damping = {mass = -1.0}"), "'material.damping.mass'"),
    (("damping = {mass = 500.0}", "damping = {mas = 1.0}"), "did you mean 'material.damping.mass'"),
    (("time = [0.0, 0.02, 0.06]", "time = [0.0, 0.06, 0.02]"), "must increase strictly"),
    (("y = [0.0, -1e-3, -1e-3]", "y = [0.0, -1e-3]"), "'obstacle.motion.y'"),
])
def test_refusals_name_the_key(tmp_path, change, message):
    scene = write(tmp_path, "bad.toml", PUNCH.replace(*change))
    with pytest.raises(contact.SceneError, match=None) as e:
        contact.load_scene(scene)
    assert message in str(e.value), str(e.value)
