"""contact.Simulation.save / contact.Simulation.load: a Simulation saved
after k steps, loaded and stepped to the end gives the uninterrupted run's trajectory bit for
bit - displacement, velocity, contact forces and every step record but the timings - with the
body force and the obstacle moved through the API before the save; a checkpoint of another
scene, a truncated or a corrupt one raise contact.CheckpointError naming what is wrong."""
import os

import numpy as np
import pytest

import contact

pytestmark = pytest.mark.filterwarnings("ignore:.*stress_times:UserWarning")  # short end_times

HERE = os.path.dirname(os.path.abspath(__file__))
FLAT = os.path.join(HERE, "..", "..", "examples", "thesis", "friction_2d_flat.toml")
DROP = os.path.join(HERE, "..", "..", "examples", "scenes", "block_drop_2d.toml")
TIMINGS = {"seconds", "solve_seconds"}


def state(sim):
    """Everything a step leaves that the comparison covers (timings excluded)."""
    records = {k: v for k, v in sim.records.items() if k not in TIMINGS}
    summary = {k: v for k, v in sim.summary.items() if not k.endswith("seconds")}
    return sim.displacement, sim.velocity, sim.contact, records, summary


def assert_same(a, b):
    ua, va, ca, ra, sa = state(a)
    ub, vb, cb, rb, sb = state(b)
    np.testing.assert_array_equal(ua, ub)
    np.testing.assert_array_equal(va, vb)
    for key in ca:
        np.testing.assert_array_equal(ca[key], cb[key], err_msg=key)
    assert ra.keys() == rb.keys()
    for key in ra:
        np.testing.assert_array_equal(ra[key], rb[key], err_msg=key)
    assert sa == sb


@pytest.mark.parametrize("scene,overrides,k", [
    (FLAT, {"end_time": 0.1}, 17),                        # condensed, lagged-bound friction
    (DROP, {"end_time": 0.005}, 33),                      # auto step, prescribed start
])
def test_resumed_equals_uninterrupted(tmp_path, scene, overrides, k):
    whole = contact.Simulation(scene, **overrides)
    whole.step(k)
    whole.set_body_force(np.array(whole.body_force) * 0.5)  # changed through the API: saved
    whole.move_obstacle(np.full(whole.dim, 1e-6))
    path = tmp_path / "state.ckpt"
    whole.save(path)
    assert path.exists() and not (tmp_path / "state.ckpt.partial").exists()
    whole.step(10**6)
    assert whole.state == "finished"

    resumed = contact.Simulation.load(path, scene, **overrides)
    assert resumed.step_index == k and resumed.state == "running"
    np.testing.assert_array_equal(resumed.body_force, np.array(contact.Simulation(scene, **overrides).body_force) * 0.5)
    np.testing.assert_array_equal(resumed.obstacle_translation, np.full(whole.dim, 1e-6))
    resumed.step(10**6)
    assert_same(whole, resumed)
    # The snapshots after the load: those of the uninterrupted run after step k (stress
    # times reached before the checkpoint are not collected again), with the same numbers.
    times_k = whole.records["time"][k - 1]
    after = [i for i, t in enumerate(whole.result().output_times) if t > times_k]
    np.testing.assert_array_equal(resumed.result().output_times, whole.result().output_times[after])
    np.testing.assert_array_equal(resumed.result().displacement, whole.result().displacement[after])


def test_refusals(tmp_path):
    sim = contact.Simulation(DROP, end_time=0.002)
    sim.step(5)
    path = tmp_path / "state.ckpt"
    sim.save(path)
    with pytest.raises(contact.CheckpointError, match=r"the scene changed.*0x[0-9a-f]{16}.*0x[0-9a-f]{16}.*time.end_time"):
        contact.Simulation.load(path, DROP, end_time=0.003)
    data = path.read_bytes()
    (tmp_path / "cut.ckpt").write_bytes(data[: len(data) // 2])
    with pytest.raises(contact.CheckpointError, match="truncated"):
        contact.Simulation.load(tmp_path / "cut.ckpt", DROP, end_time=0.002)
    (tmp_path / "bad.ckpt").write_bytes(data[:-9] + bytes([data[-9] ^ 0x10]) + data[-8:])
    with pytest.raises(contact.CheckpointError, match="checksum"):
        contact.Simulation.load(tmp_path / "bad.ckpt", DROP, end_time=0.002)
    with pytest.raises(contact.CheckpointError, match="cannot read checkpoint"):
        contact.Simulation.load(tmp_path / "missing.ckpt", DROP, end_time=0.002)
    assert issubclass(contact.CheckpointError, ValueError)
