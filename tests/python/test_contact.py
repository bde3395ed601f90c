"""The contact package against the contact-sim command line on the same scenes (same
numbers to the 10 digits of its CSV files), per-node results checked against the per-step
sums, scenes from dicts, progress, and the error paths."""
import csv
import os
import subprocess
import tomllib

import numpy as np
import pytest

import contact

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")
SCENES = {"flat": os.path.join(EXAMPLES, "thesis", "friction_2d_flat.toml"),
          "drop": os.path.join(EXAMPLES, "scenes", "block_drop_2d.toml")}


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


@pytest.fixture(scope="module")
def runs(tmp_path_factory, bin_dir):
    """Each scene run by Python and by contact-sim (CSV output into a temporary directory)."""
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built (NCP_BIN_DIR)")
    out = {}
    for key, path in SCENES.items():
        d = tmp_path_factory.mktemp(key)
        subprocess.run([exe, path, "--quiet", "--output", str(d)], check=True, capture_output=True)
        out[key] = (contact.run(path), d)
    return out


@pytest.mark.parametrize("key", sorted(SCENES))
def test_records_match_contact_sim(runs, key):
    result, d = runs[key]
    steps = read_csv(d / "steps.csv")
    assert result.completed and result.summary["steps"] == steps["step"].size
    # auto: the method of least predicted cost (docs/contact-steps.md)
    assert result.summary["step_method"] in ("condensed", "sparse", "explicit")
    np.testing.assert_allclose(result.times, steps["time"], rtol=1e-9)
    # One vocabulary: every column of steps.csv is a record of the same name and value
    # (seconds are wall-clock times of two different runs).
    assert set(steps) <= set(contact.STEP_FIELDS), set(steps) - set(contact.STEP_FIELDS)
    for name in set(steps) - {"seconds"}:
        scale = np.abs(steps[name]).max() + 1e-300
        np.testing.assert_allclose(result.records[name], steps[name], rtol=1e-9, atol=1e-9 * scale,
                                   err_msg=name)
    for name in ("newton_iterations", "active_nodes"):
        np.testing.assert_array_equal(result.records[name], steps[name].astype(int))


@pytest.mark.parametrize("key", sorted(SCENES))
def test_snapshots_match_contact_sim(runs, key):
    result, d = runs[key]
    stress = read_csv(d / "contact_stress.csv")
    times = np.unique(stress["time"])
    np.testing.assert_allclose(result.output_times, times, rtol=1e-9)
    T, C = result.normal_force.shape
    assert stress["time"].size == T * C
    np.testing.assert_array_equal(stress["node"].reshape(T, C)[0], result.contact_node)
    for py, name in [(result.normal_stress, "normal_stress"), (result.friction_stress[:, :, 0], "friction_stress"),
                     (result.gap, "gap"), (result.normal_force, "normal_force")]:
        ref = stress[name].reshape(T, C)
        np.testing.assert_allclose(py, ref, rtol=1e-8, atol=1e-9 * np.abs(ref).max(), err_msg=name)
    disp = read_csv(d / "displacement.csv")
    N = result.nodes.shape[0]
    ref = np.stack([disp["ux"].reshape(T, N), disp["uy"].reshape(T, N)], axis=2)
    np.testing.assert_allclose(result.displacement, ref, rtol=1e-8, atol=1e-9 * np.abs(ref).max())
    nodes = read_csv(d / "mesh_nodes.csv")
    np.testing.assert_allclose(result.nodes, np.stack([nodes["x"], nodes["y"]], axis=1))
    with open(d / "mesh_elements.csv") as f:
        rows = list(csv.DictReader(f))
    assert {r["type"] for r in rows} == {result.element_type}
    np.testing.assert_array_equal(result.elements, [[int(r[f"n{a}"]) for a in range(4)] for r in rows])


def test_contact_arrays_agree_with_the_step_sums(runs):
    """Per-node forces summed here = the record's sum; Signorini holds node by node."""
    result, _ = runs["flat"]
    step_of = np.searchsorted(result.times, result.output_times - 1e-12)
    np.testing.assert_allclose(result.normal_force.sum(axis=1), result.records["normal_force_sum"][step_of],
                               rtol=1e-12)
    np.testing.assert_allclose(np.abs(result.friction_force[:, :, 0]).sum(axis=1),
                               result.records["friction_force_sum"][step_of], rtol=1e-12)
    f_max = result.normal_force.max()
    assert f_max > 1e4  # the wall pushes back [N]
    assert result.normal_force.min() >= -1e-6 * f_max
    assert -result.gap.min() <= result.summary["max_penetration"] + 1e-15
    # Complementarity lambda_c gap_c = 0 per node, in [N m] relative to the largest force
    # times the largest gap.
    assert np.abs(result.normal_force * result.gap).max() <= 1e-6 * f_max * np.abs(result.gap).max()
    assert result.summary["energy_balance_error"] < 1e-6


def test_contact_history_and_the_marked_node(runs):
    result, d = runs["flat"]
    steps = result.times.size
    assert result.history_normal_force.shape == (steps, result.contact_node.size)
    assert result.history_friction_force.shape == (steps, result.contact_node.size, 1)
    step_of = np.searchsorted(result.times, result.output_times - 1e-12)
    np.testing.assert_array_equal(result.history_normal_force[step_of], result.normal_force)
    np.testing.assert_array_equal(result.history_gap[step_of], result.gap)
    # contact-sim's node_history.csv: the contact node nearest to output.marked_point (5, 0)
    c = result.nearest_contact_node([5.0, 0.0])
    np.testing.assert_allclose(result.contact_coordinates[c], [5.0, 0.0])
    history = read_csv(d / "node_history.csv")
    area = result.contact_area[c]
    np.testing.assert_allclose(result.history_normal_force[:, c] / area, history["normal_stress"], rtol=1e-8,
                               atol=1e-9 * np.abs(history["normal_stress"]).max())
    np.testing.assert_allclose(result.history_friction_force[:, c, 0] / area, history["friction_stress"], rtol=1e-8,
                               atol=1e-9 * np.abs(history["friction_stress"]).max())
    with pytest.raises(ValueError, match="2 coordinates"):
        result.nearest_contact_node([1.0, 2.0, 3.0])
    lean = contact.run(SCENES["flat"], contact_history=False)
    assert not hasattr(lean, "history_normal_force")


def test_scene_from_dict_runs_like_the_file():
    with open(SCENES["flat"], "rb") as f:
        d = tomllib.load(f)
    d["time"]["end_time"] = 0.025
    a = contact.run(d, base_dir=os.path.dirname(SCENES["flat"]))
    scene = contact.load_scene(SCENES["flat"])
    scene.end_time = 0.025
    b = contact.run(scene)
    assert a.summary["steps"] == b.summary["steps"] == 10
    for name in contact.STEP_FIELDS:
        if "seconds" not in name:
            np.testing.assert_array_equal(a.records[name], b.records[name], err_msg=name)
    np.testing.assert_array_equal(a.displacement, b.displacement)


def test_step_method_and_friction_formulation_from_python():
    """A scene given as a dict chooses the step and the friction formulation; the sparse step
    follows the condensed one, and the summary says which step ran."""
    with open(SCENES["flat"], "rb") as f:
        d = tomllib.load(f)
    d["time"]["end_time"] = 0.025
    d["solver"]["friction"] = "coulomb-fc"
    base = os.path.dirname(SCENES["flat"])
    runs = {}
    for step in ("condensed", "sparse"):
        d["solver"]["step"] = step
        runs[step] = contact.run(d, base_dir=base)
        assert runs[step].completed and runs[step].summary["step_method"] == step
    scale = np.abs(runs["condensed"].displacement).max()
    assert scale > 0
    np.testing.assert_allclose(runs["sparse"].displacement, runs["condensed"].displacement, rtol=0,
                               atol=1e-9 * scale)
    scene = contact.load_scene(SCENES["flat"])
    assert scene.step == "auto" and scene.friction_formulation == "lagged-bound"  # pinned by the file


def test_every_and_progress():
    scene = contact.load_scene(SCENES["flat"])
    scene.end_time = 0.025
    scene.stress_times = []
    calls = []
    r = contact.run(scene, every=3, progress=lambda step, t, end: calls.append((step, t, end)))
    assert [c[0] for c in calls] == list(range(1, 11))
    assert calls[-1][1] == pytest.approx(0.025) and calls[-1][2] == 0.025
    np.testing.assert_allclose(r.output_times, [0.0075, 0.015, 0.0225, 0.025])
    assert r.displacement.shape == (4, r.nodes.shape[0], 2)
    assert "completed" in repr(r)


def test_progress_bar_on_stderr(capsys):
    scene = contact.load_scene(SCENES["flat"])
    scene.end_time = 0.01
    contact.run(scene, progress=True)
    err = capsys.readouterr().err
    assert "step 4" in err and "#" * 30 in err and "100.0 %" in err


@pytest.mark.parametrize("fraction,elapsed,text", [
    (0.0, 0.0, "  0.0 %, 0 s elapsed, ETA --"),
    (0.25, 10.0, " 25.0 %, 10 s elapsed, ETA 30 s"),      # 10 s (1 - 1/4) / (1/4)
    (0.5, 125.0, " 50.0 %, 2 min 05 s elapsed, ETA 2 min 05 s"),
    (0.1, 400.0, " 10.0 %, 6 min 40 s elapsed, ETA 1 h 00 min"),  # 3600 s left
    (1.0, 42.0, "100.0 %, 42 s elapsed"),
])
def test_progress_text_extrapolates_the_mean_rate(fraction, elapsed, text):
    assert contact.progress_text(fraction, elapsed) == text


def test_records_have_the_csv_names_and_old_names_say_so(runs):
    result, _ = runs["flat"]
    assert "kinetic_energy" in result.records and "kinetic" not in result.records
    with pytest.raises(KeyError, match="renamed 'kinetic_energy'"):
        result.records["kinetic"]
    with pytest.raises(AttributeError, match="renamed friction_stress"):
        result.tangent_stress


def test_overrides_are_checked_like_the_file(tmp_path):
    r = contact.run(SCENES["flat"], end_time=0.005, contact_history=False)
    assert r.summary["steps"] == 2 and r.times[-1] == pytest.approx(0.005)
    with pytest.raises(ValueError, match="time.end_time"):
        contact.run(SCENES["flat"], end_time=-1.0)
    with pytest.raises(ValueError, match="unknown override 'end'"):
        contact.run(SCENES["flat"], end=1.0)


def test_example_path_works_from_any_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = contact.example_path("thesis/friction_2d_flat.toml")
    assert os.path.isabs(path) and contact.load_scene(path).name == "thesis-6.2-friction-2d-flat"
    with pytest.raises(ValueError, match="working directory"):
        contact.load_scene("examples/thesis/friction_2d_flat.toml")
    with pytest.raises(FileNotFoundError, match="no example"):
        contact.example_path("scenes/nothing.toml")


# ---- error paths ---------------------------------------------------------------------

def test_missing_file_and_bad_scenes_raise_value_error(tmp_path):
    with pytest.raises(ValueError, match="cannot read scene file"):
        contact.load_scene(str(tmp_path / "missing.toml"))
    with open(SCENES["flat"], "rb") as f:
        d = tomllib.load(f)
    bad = dict(d, material=dict(d["material"], young_modulus=-1.0))
    with pytest.raises(contact.SceneError, match="young_modulus"):
        contact.run(bad)
    with pytest.raises(ValueError, match="<scene dict>"):
        contact.scene_from_dict({"name": "no geometry"})
    import glob
    import tempfile
    temporary = set(glob.glob(os.path.join(tempfile.gettempdir(), "scene-*.toml")))
    with pytest.raises(ValueError, match="type NoneType"):
        contact.scene_from_dict(dict(d, name=None))
    with pytest.raises(ValueError, match="<scene dict>"):
        contact.scene_from_dict(dict(d, bogus_key=1.0))
    assert set(glob.glob(os.path.join(tempfile.gettempdir(), "scene-*.toml"))) == temporary
    with pytest.raises(ValueError, match="every must be >= 0"):
        contact.run(SCENES["flat"], every=-1)
    with pytest.raises(ValueError, match="Scene, a path or a dict"):
        contact.run(42)


def test_exception_in_progress_reaches_the_caller():
    def stop(step, t, end):
        raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        contact.run(SCENES["flat"], progress=stop)


def test_contact_sim_json_uses_the_python_summary_names(bin_dir, tmp_path):
    """One vocabulary: contact-sim --json has a key for every field of result.summary (the
    Ipopt difference only when Ipopt compared), with the same integer counts."""
    exe = os.path.join(bin_dir, "contact-sim")
    if not os.path.exists(exe):
        pytest.skip(f"{exe} not built (NCP_BIN_DIR)")
    import json
    out = subprocess.run([exe, SCENES["drop"], "--json", "--quiet", "--no-output", "--end-time", "0.002"],
                         check=True, capture_output=True, text=True).stdout
    j = json.loads(out)
    r = contact.run(SCENES["drop"], end_time=0.002, contact_history=False)
    missing = set(contact.SUMMARY_FIELDS) - {"max_ipopt_relative_difference"} - set(j)
    assert not missing, f"contact-sim --json lacks {sorted(missing)}"
    for name in ("steps", "newton_iterations", "jacobian_evaluations", "residual_evaluations",
                 "inaccurate_steps", "status", "step_method"):
        assert j[name] == r.summary[name], name
    assert j["critical_time_step"] == pytest.approx(r.summary["critical_time_step"], rel=1e-12)
