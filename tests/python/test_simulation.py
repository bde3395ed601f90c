"""contact.Simulation: stepping by hand gives run()'s numbers, a load changed between steps
gives the closed-form sliding distance of a block on a Coulomb floor, a moved obstacle
closes the gap by the translation, and bad input raises naming the value."""
import math
import os

import numpy as np
import pytest

import contact

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")
DROP = os.path.join(EXAMPLES, "scenes", "block_drop_2d.toml")
FLAT = os.path.join(EXAMPLES, "thesis", "friction_2d_flat.toml")

RHO, G, MU = 7800.0, 9.81, 0.3  # kg/m^3, m/s^2, friction coefficient


def block(body_force, offset=0.0, end_time=0.05, dt=5e-5, friction=MU, initial="static",
          young_modulus=2e8):
    """A steel-density block 0.1 m x 0.05 m (plane strain, lumped mass, E [Pa]) on the floor
    y = offset (offset < 0: a gap of -offset below it); dt [s], end_time [s]."""
    time = {"dt": dt, "end_time": end_time}
    if initial == "velocity":
        time.update(initial_state="velocity", initial_velocity=[0.0, 0.0])
    return {
        "geometry": {"type": "rectangle", "origin": [0.0, 0.0], "size": [0.1, 0.05],
                     "cells": [4, 2], "element": "quad4", "contact": ["ymin"]},
        "material": {"young_modulus": young_modulus, "poisson_ratio": 0.3, "density": RHO,
                     "plane": "strain", "thickness": 1.0, "mass": "lumped"},
        "loads": {"body_force": list(body_force)},
        "obstacle": {"type": "plane", "normal": [0.0, 1.0], "offset": offset,
                     "normal_source": "obstacle"},
        "friction": {"coefficient": friction},
        "time": time,
    }


@pytest.mark.parametrize("path", [DROP, FLAT])
def test_stepping_by_hand_equals_run(path):
    """Steps in uneven chunks give run()'s records and displacement bit for bit."""
    ran = contact.run(path, end_time=4e-3 if path == DROP else None)
    sim = contact.Simulation(path, end_time=4e-3 if path == DROP else None)
    assert sim.state == "running" and sim.step_index == 0 and sim.time == pytest.approx(ran.times[0] - sim.dt)
    chunks = [1, 0, 7, 3, 50]
    while sim.step(chunks[sim.step_index % len(chunks)] or 1) == "running":
        pass
    assert sim.state == "finished" and sim.completed and ran.completed
    assert sim.step_index == sim.num_steps == len(ran.times)
    assert sim.time == ran.times[-1]
    for name in contact.STEP_FIELDS:
        if name not in ("seconds", "solve_seconds"):
            np.testing.assert_array_equal(sim.records[name], ran.records[name], err_msg=name)
    np.testing.assert_array_equal(sim.displacement, ran.displacement[-1])
    np.testing.assert_array_equal(sim.contact["normal_force"], ran.normal_force[-1])
    np.testing.assert_array_equal(sim.contact["friction_force"], ran.friction_force[-1])
    np.testing.assert_array_equal(sim.contact["gap"], ran.gap[-1])
    for key in ("status", "steps", "newton_iterations", "max_penetration", "energy_balance_error"):
        assert sim.summary[key] == ran.summary[key], key
    assert sim.step(5) == "finished" and sim.step_index == sim.num_steps  # nothing past the end


def test_push_then_release_slides_the_closed_form_distance():
    """Pushed sideways by a body force b_x = 2 mu rho g for T, the block slides with a = mu g
    (push minus Coulomb friction mu rho g); released, it decelerates at mu g and stops at
    t = 2T, after x = 1/2 mu g T^2 + (mu g T)^2 / (2 mu g) = mu g T^2. Measured at the centre
    of mass (lumped quad4 masses: a quarter of each element per node); the body's vertical
    vibration (it starts at rest on the floor without its support force) makes the normal
    force, and so the friction, oscillate about rho g: 0.3 % on the velocity, 1.4 % on the
    deceleration, 0.2 % on the distance (measured)."""
    # At rest on the floor (the static start is frictionless: no equilibrium in x).
    sim = contact.Simulation(block([0.0, -RHO * G], initial="velocity", young_modulus=2e9, dt=1.5e-5))
    w = np.bincount(sim.result().elements.ravel()).astype(float)
    w /= w.sum()

    def centre(a):
        return w @ a[:, 0]

    sim.set_body_force([2 * MU * RHO * G, -RHO * G])
    steps = round(0.02 / sim.dt)
    T = steps * sim.dt  # [s]
    assert sim.step(steps) == "running" and sim.time == pytest.approx(T)
    v_push = centre(sim.velocity)
    assert v_push == pytest.approx(MU * G * T, rel=0.01)
    sim.set_body_force([0.0, -RHO * G])
    np.testing.assert_array_equal(sim.body_force, [0.0, -RHO * G])
    x_release = centre(sim.displacement)
    sim.step(steps // 2)  # halfway through the deceleration
    decel = (v_push - centre(sim.velocity)) / (sim.time - T)
    assert decel == pytest.approx(MU * G, rel=0.03)
    assert sim.step(10**6) == "finished" and sim.completed
    x = centre(sim.displacement)
    assert x == pytest.approx(MU * G * T**2, rel=0.01)
    assert x - x_release == pytest.approx(0.5 * MU * G * T**2, rel=0.01)
    assert abs(centre(sim.velocity)) < 2e-3 * MU * G * T  # at rest again
    assert np.all(sim.contact["state"] == 1)  # stuck to the floor
    assert np.all(sim.contact["normal_force"] > 0)


def test_moving_the_obstacle_up_closes_the_gap_by_the_translation():
    gap = 1e-3  # m, below a block at rest without loads
    sim = contact.Simulation(block([0.0, 0.0], offset=-gap, initial="velocity"))
    np.testing.assert_allclose(sim.contact_gaps, gap, rtol=1e-12)
    assert np.all(np.isnan(sim.contact["normal_force"]))  # a prescribed start: not known yet
    sim.step(2)
    np.testing.assert_allclose(sim.contact["gap"], gap, rtol=1e-12)
    sim.move_obstacle([0.0, 4e-4])
    np.testing.assert_array_equal(sim.obstacle_translation, [0.0, 4e-4])
    np.testing.assert_allclose(sim.contact_gaps, gap - 4e-4, rtol=1e-12)
    sim.step()
    np.testing.assert_allclose(sim.contact["gap"], gap - 4e-4, rtol=1e-12)
    assert np.all(sim.contact["state"] == 0) and np.all(sim.contact["normal_force"] == 0)
    # Sideways moves of a plane change nothing; the translation is absolute.
    sim.move_obstacle([0.3, 4e-4])
    np.testing.assert_allclose(sim.contact_gaps, gap - 4e-4, rtol=1e-12)
    # Past the body: the floor pushes it up, closing the gap to round-off.
    sim.move_obstacle([0.0, gap + 1e-4])
    sim.step()
    assert np.all(sim.contact["normal_force"] > 0)
    assert np.all(np.abs(sim.contact["gap"]) < 1e-9)
    bottom = sim.result().contact_node
    np.testing.assert_allclose(sim.displacement[bottom, 1], 1e-4, rtol=1e-6)


def test_contact_state_and_units():
    sim = contact.Simulation(DROP, end_time=2e-3)
    sim.step(10)
    c = sim.contact
    n = len(c["gap"])
    assert c["normal_force"].shape == (n,) and c["friction_force"].shape == (n, 1) and c["state"].shape == (n,)
    assert sim.displacement.shape == sim.velocity.shape == (33, 2)
    # velocity = (u^k - u^{k-1}) / dt: the block moves down at about 0.5 m/s before impact
    assert sim.velocity[:, 1].mean() == pytest.approx(-0.5, rel=0.01)
    assert sim.summary["status"] == "not-run" and sim.summary["steps"] == 10
    assert len(sim.records["time"]) == 10
    assert "running" in repr(sim)


def test_a_refused_run_fails_at_once():
    sim = contact.Simulation(DROP, dt=1e-2)
    assert sim.state == "failed" and sim.step(3) == "failed" and not sim.completed
    assert "allow_unstable" in sim.summary["message"] and sim.summary["status"] == "refused-unstable-time-step"
    with pytest.raises(RuntimeError, match="no state"):
        sim.displacement


@pytest.mark.parametrize("call, match", [
    (lambda s: s.step(-1), "n must be >= 0"),
    (lambda s: s.step(1.5), "n must be an int"),
    (lambda s: s.set_body_force([1.0, 2.0, 3.0]), "2 components"),
    (lambda s: s.set_body_force([math.nan, 0.0]), "finite"),
    (lambda s: s.set_body_force([[1.0, 2.0]]), "vector"),
    (lambda s: s.move_obstacle([0.0]), "2 components"),
    (lambda s: s.move_obstacle([math.inf, 0.0]), "finite"),
])
def test_bad_input_raises_with_a_message(call, match):
    sim = contact.Simulation(DROP, end_time=1e-3)
    with pytest.raises(ValueError, match=match):
        call(sim)
    assert sim.step_index == 0 and sim.step() == "running"  # nothing changed


def test_scene_dict_and_overrides():
    sim = contact.Simulation(block([0.0, -RHO * G], initial="velocity"), end_time=1e-3, dt=1e-4)
    assert sim.num_steps == 10 and sim.dt == 1e-4
    with pytest.raises(ValueError, match="unknown override"):
        contact.Simulation(DROP, tol=1e-3)
    with pytest.raises(ValueError, match="overrides need a path or a dict"):
        contact.Simulation(contact.load_scene(DROP), dt=1e-5)
