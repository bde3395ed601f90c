"""What a new user runs into, each checked against what it must be: one version in every
CLI and both packages; a scene's relative output directory taken from the working
directory (the shipped scenes write output/<scene>); a refused run writes nothing; a plane
normal off unit length is refused by name; the summary line in words; warnings that point
at the user's own line and speak of what run() does."""
import math
import os
import re
import subprocess
import tomllib
import warnings

import pytest

import contact
import ncp

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")
DROP = os.path.join(EXAMPLES, "scenes", "block_drop_2d.toml")

# A steel block 1 mm above a floor, thrown down at 0.5 m/s: it lands after 2 ms.
SCENE = """
name = "trap"
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
body_force = [0.0, -76518.0]
[obstacle]
type = "plane"
normal = NORMAL
offset = -0.001
[time]
dt = 5e-5
end_time = 0.004
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[output]
directory = "out"
"""


def scene_file(directory, normal="[0.0, 1.0]", extra=""):
    os.makedirs(directory, exist_ok=True)
    path = os.path.join(directory, "scene.toml")
    with open(path, "w") as f:
        f.write(SCENE.replace("NORMAL", normal) + extra)
    return path


def executable(bin_dir, name):
    path = os.path.join(bin_dir, name)
    if not os.path.exists(path):
        pytest.skip(f"{path} not built")
    return path


# ---- versions ---------------------------------------------------------------------------

def test_one_version_in_both_packages_and_every_cli(bin_dir):
    assert re.fullmatch(r"\d+\.\d+\.\d+", ncp.__version__), ncp.__version__
    assert contact.__version__ == ncp.__version__
    for name in ("contact-sim", "fc-solve"):
        done = subprocess.run([executable(bin_dir, name), "--version"], capture_output=True,
                              text=True, timeout=30)
        assert done.returncode == 0 and done.stdout == f"{name} {ncp.__version__}\n", done


def test_petsc_example_answers_help_and_version_without_running(bin_dir):
    exe = executable(bin_dir, "ncp-petsc-obstacle")
    for option in ("--help", "-h"):
        done = subprocess.run([exe, option], capture_output=True, text=True, timeout=30)
        assert done.returncode == 0 and "usage:" in done.stdout and "-m N" in done.stdout, done
        assert "unknowns" not in done.stdout, done.stdout  # (the run's first line)
    done = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30)
    assert done.stdout == f"ncp-petsc-obstacle {ncp.__version__}\n", done


# ---- where the output goes, and when nothing is written ----------------------------------

def test_relative_output_directory_is_taken_from_the_working_directory(tmp_path, bin_dir):
    scene = scene_file(tmp_path / "scenes")
    work = tmp_path / "work"
    work.mkdir()
    done = subprocess.run([executable(bin_dir, "contact-sim"), scene, "--quiet"], cwd=work,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert (work / "out" / "steps.csv").is_file()
    assert not (tmp_path / "scenes" / "out").exists()


@pytest.mark.parametrize("folder", ["scenes", "thesis", "validation"])
def test_shipped_scenes_write_output_slash_their_name(folder):
    files = sorted(f for f in os.listdir(os.path.join(EXAMPLES, folder)) if f.endswith(".toml"))
    assert files
    for name in files:
        with open(os.path.join(EXAMPLES, folder, name), "rb") as f:
            directory = tomllib.load(f)["output"]["directory"]
        assert directory == "output/" + name[:-len(".toml")], (name, directory)


def test_a_refused_time_step_writes_nothing(tmp_path, bin_dir):
    out = tmp_path / "refused"
    done = subprocess.run([executable(bin_dir, "contact-sim"), DROP, "--dt", "1e-3", "--output",
                           str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1 and "time.dt" in done.stderr, done
    assert not out.exists(), sorted(os.listdir(out))


# ---- refusals and words ------------------------------------------------------------------

@pytest.mark.parametrize("normal, length", [("[0.0, 2.0]", 2.0), ("[0.6, 0.6]", math.hypot(0.6, 0.6)),
                                            ("[0.0, 0.998]", 0.998)])
def test_a_plane_normal_off_unit_length_is_refused_by_name(tmp_path, normal, length):
    with pytest.raises(contact.SceneError) as e:
        contact.load_scene(scene_file(tmp_path, normal))
    message = str(e.value)
    assert "'obstacle.normal' must be a unit vector" in message, message
    assert math.isclose(float(re.search(r"got \|n\| = ([0-9.e+-]+)", message).group(1)), length,
                        rel_tol=1e-5), message


def test_a_plane_normal_within_its_slack_is_accepted(tmp_path):
    assert contact.load_scene(scene_file(tmp_path, "[0.0, 1.0009]")).name == "trap"


def test_the_summary_says_in_words_what_completed_means(tmp_path, bin_dir):
    result = contact.run(scene_file(tmp_path))
    steps = result.summary["steps"]
    assert steps == 80 and result.summary["status"] == "completed"
    assert result.summary["message"] == f"all {steps} time steps solved to their accuracy"
    done = subprocess.run([executable(bin_dir, "contact-sim"), scene_file(tmp_path), "--no-output"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"trap: completed (all {steps} time steps solved to their accuracy)\n" in done.stdout
    header = next(line for line in done.stdout.splitlines() if "dt [s]" in line)
    assert header.split() == ["dt", "[s]", "friction", "time", "steps", "Jacobians", "residuals",
                              "time", "[s]"], header
    assert "k_sim" not in done.stdout and "N_Jac" not in done.stdout


def test_warnings_point_at_the_callers_line_and_speak_of_what_run_does(tmp_path):
    path = scene_file(tmp_path, extra="stress_times = [0.5]\n")
    for call in (lambda: contact.run(path), lambda: contact.Simulation(path)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            call()
        assert len(caught) == 1, [str(w.message) for w in caught]
        w = caught[0]
        assert w.filename == __file__, w.filename  # this file, not the package's
        assert "output.stress_times" in str(w.message) and "nothing is recorded" in str(w.message)
        assert "written" not in str(w.message), w.message  # run() writes no stress files
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        contact.run(path)
    assert str(caught[0].message).startswith("contact.run: "), caught[0].message
