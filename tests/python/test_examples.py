"""Every script of examples/python run as a user runs it (a subprocess of the same
interpreter, the packages from PYTHONPATH), with its printed results checked."""
import os
import re
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python")


def run_example(name, *args, cwd=None):
    """Runs EXAMPLES/name as a script; returns its stdout, failing on a nonzero exit."""
    # Absolute PYTHONPATH entries: the script may run in another directory.
    path = os.pathsep.join(os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=path)
    done = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_lcp_example():
    out = run_example("lcp.py")
    assert "converged" in out
    z = [float(v) for v in re.search(r"z = \[([^\]]*)\]", out).group(1).split()]
    assert z == pytest.approx([4 / 3, 7 / 9, 4 / 9, 2 / 9], rel=1e-8)


def test_nash_cournot_example():
    out = run_example("nash_cournot.py")
    q = [float(v) for v in re.search(r"outputs q = \[([^\]]*)\]", out).group(1).split()]
    assert q == pytest.approx([15.4293, 12.4986, 9.6635, 7.1651, 5.1326], abs=1e-4)  # Harker (1988)
    assert float(re.search(r"natural residual .* = (\S+)$", out, re.M).group(1)) <= 1e-10


@pytest.mark.parametrize("friction", [None, "5.0"])
def test_thesis_scene_example_draws_its_figure(tmp_path, friction):
    png = tmp_path / "fig.png"
    args = [str(png)] + (["--friction", friction] if friction else [])
    out = run_example("thesis_scene.py", *args, cwd=tmp_path)
    assert "completed: 100 steps" in out
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 20000  # two panels with curves, not an empty canvas


def test_callback_overhead_benchmark_runs(tmp_path):
    """benchmarks/python/callback_overhead.py once: it stops with an error if a Python
    solve takes other iterations than the C++ one."""
    out_csv = tmp_path / "overhead.csv"
    run_example(os.path.join("..", "..", "benchmarks", "python", "callback_overhead.py"), "--repeat", "1",
                "--csv", str(out_csv))
    with open(out_csv) as f:
        assert len(f.readlines()) == 1 + 6 * 3
