#!/usr/bin/python3
"""Checkpoint and resume of contact-sim (docs/reliability.md).

  check_resume.py --contact-sim build/bin/contact-sim --scene SCENE.toml --mode MODE
                  [--checkpoint-every K] [--tolerance REL] [-- OVERRIDES...]

A copy of SCENE (with output.checkpoint_every = K) is run to the end uninterrupted into A.
Then, by MODE:
  rerun      the same run into B ends with its last checkpoint at the last multiple of K
             before the end; `--resume` into B continues from it: the CSV rows after the
             checkpoint are cut off and written again.
  interrupt  a run into B gets SIGINT after its first checkpoint is written (exit 130,
             "interrupted at step N"); `--resume` into B goes on to the end.
  refuse     --resume is refused (exit 1, message on stderr) without a checkpoint, with a
             truncated and a corrupt one, with a changed scene text (naming both hashes
             and the line that differs) or override, and (tests/fuzz/square_msh.toml) a
             changed mesh file; B is left as it was.
The resumed B must equal A: every CSV, .vtu and .pvd byte for byte, except steps.csv's
`seconds` column (wall-clock time), or with --tolerance REL every number to REL relative
(|a - b| <= REL max(|a|, |b|)); the largest relative difference is printed.
"""
import argparse
import filecmp
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

FAILURES = []


def check(condition, what):
    if not condition:
        FAILURES.append(what)
        print("FAIL:", what)


def run(cmd, timeout=300):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def scene_copy(scene, directory, every):
    """SCENE with output.checkpoint_every = every, no output.directory, written into
    directory (relative paths inside made absolute: a generated mesh is assumed)."""
    with open(scene) as f:
        text = f.read()
    text = re.sub(r"(?m)^directory\s*=.*$", "", text)
    if "[output]" in text:
        text = text.replace("[output]", f"[output]\ncheckpoint_every = {every}", 1)
    else:
        text += f"\n[output]\ncheckpoint_every = {every}\n"
    path = os.path.join(directory, "scene.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def csv_numbers(path, skip_column=None):
    with open(path) as f:
        lines = f.read().split("\n")
    header = lines[0].split(",")
    skip = header.index(skip_column) if skip_column in header else -1
    rows = []
    for line in lines[1:]:
        if line:
            rows.append([v for i, v in enumerate(line.split(",")) if i != skip])
    return header, rows


def compare_csv(a, b, tolerance, name):
    """Largest relative difference (0 for equal text); a failure if not within tolerance."""
    ha, ra = csv_numbers(a, "seconds")
    hb, rb = csv_numbers(b, "seconds")
    check(ha == hb, f"{name}: headers differ")
    check(len(ra) == len(rb), f"{name}: {len(ra)} rows uninterrupted, {len(rb)} resumed")
    worst = 0.0
    for row_a, row_b in zip(ra, rb):
        for x, y in zip(row_a, row_b):
            if x == y:
                continue
            if tolerance is None:
                check(False, f"{name}: '{x}' uninterrupted, '{y}' resumed (bitwise expected)")
                return float("inf")
            fx, fy = float(x), float(y)
            worst = max(worst, abs(fx - fy) / max(abs(fx), abs(fy)))
    if tolerance is not None:
        check(worst <= tolerance, f"{name}: relative difference {worst:.3e} > {tolerance:g}")
    return worst


def compare_directories(a, b, tolerance):
    names_a = sorted(n for n in os.listdir(a) if n != "checkpoint.bin")
    names_b = sorted(n for n in os.listdir(b) if n != "checkpoint.bin")
    check(names_a == names_b, f"files differ: {sorted(set(names_a) ^ set(names_b))}")
    worst = 0.0
    for name in names_a:
        if name not in names_b:
            continue
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if name.endswith(".csv"):
            worst = max(worst, compare_csv(pa, pb, tolerance, name))
        elif tolerance is None or not name.endswith(".vtu"):
            check(filecmp.cmp(pa, pb, shallow=False), f"{name}: differs")
    return worst


def check_mesh_change(contact_sim, work):
    """tests/fuzz/square_msh.toml with its square.msh: a byte appended to the mesh file after
    the run makes --resume refuse, naming the mesh file and both hashes."""
    fuzz = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz")
    mesh_dir = os.path.join(work, "mesh")
    os.makedirs(mesh_dir)
    for name in ("square_msh.toml", "square.msh"):
        shutil.copy(os.path.join(fuzz, name), mesh_dir)
    scene = os.path.join(mesh_dir, "square_msh.toml")
    with open(scene, "a") as f:
        f.write("\n[output]\ncheckpoint_every = 30\n")
    out = os.path.join(mesh_dir, "out")
    r = run([contact_sim, scene, "--quiet", "--output", out])
    check(r.returncode == 0, f"mesh scene: exit {r.returncode}\n{r.stderr[-800:]}")
    with open(os.path.join(mesh_dir, "square.msh"), "a") as f:
        f.write("\n")
    r = run([contact_sim, scene, "--quiet", "--output", out, "--resume"])
    check(r.returncode == 1 and "the mesh file changed" in r.stderr and "square.msh" in r.stderr
          and r.stderr.count("0x") >= 2,
          f"--resume after the mesh file changed: exit {r.returncode}, stderr {r.stderr[-600:]!r}")


def steps_rows(directory):
    return len(csv_numbers(os.path.join(directory, "steps.csv"))[1])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--contact-sim", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--mode", choices=["rerun", "interrupt", "refuse"], required=True)
    parser.add_argument("--checkpoint-every", type=int, default=30)
    parser.add_argument("--tolerance", type=float, default=None)
    parser.add_argument("overrides", nargs="*")
    args = parser.parse_args()

    work = tempfile.mkdtemp(prefix="check-resume-")
    try:
        scene = scene_copy(args.scene, work, args.checkpoint_every)
        a, b = os.path.join(work, "A"), os.path.join(work, "B")
        base = [args.contact_sim, scene, "--quiet", *args.overrides]
        r = run(base + ["--output", a])
        check(r.returncode == 0, f"uninterrupted run: exit {r.returncode}\n{r.stderr[-800:]}")
        total = steps_rows(a)

        if args.mode == "rerun":
            r = run(base + ["--output", b])
            check(r.returncode == 0, f"run into B: exit {r.returncode}\n{r.stderr[-800:]}")
            r = run([args.contact_sim, scene, *args.overrides, "--output", b, "--resume"])
            check(r.returncode == 0, f"resumed run: exit {r.returncode}\n{r.stderr[-800:]}")
            last = (total - 1) // args.checkpoint_every * args.checkpoint_every
            check(f"resumed from the checkpoint of step {last}\n" in r.stderr,
                  f"no 'resumed from the checkpoint of step {last}' on stderr:\n{r.stderr[-800:]}")
        elif args.mode == "interrupt":
            cmd = [args.contact_sim, scene, *args.overrides, "--output", b]
            process = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            checkpoint = os.path.join(b, "checkpoint.bin")
            deadline = time.time() + 120
            while not os.path.exists(checkpoint) and process.poll() is None and time.time() < deadline:
                time.sleep(0.005)
            process.send_signal(signal.SIGINT)
            out, err = process.communicate(timeout=300)
            if process.returncode == 0:
                print("note: the run ended before the interrupt; nothing was interrupted")
                check(False, "the run finished before SIGINT: choose a longer scene")
            else:
                check(process.returncode == 130, f"interrupted run: exit {process.returncode}\n{err[-800:]}")
                match = re.search(r"interrupted at step (\d+)", err)
                check(match is not None, f"no 'interrupted at step N' on stderr:\n{err[-800:]}")
                if match:
                    n = int(match.group(1))
                    check(steps_rows(b) == n, f"steps.csv has {steps_rows(b)} rows after the interrupt at step {n}")
                    check(f"checkpoint of step {n} written into {b}" in err,
                          f"no 'checkpoint of step {n} written' on stderr:\n{err[-800:]}")
                    print(f"interrupted at step {n} of {total}")
            r = run(base + ["--output", b, "--resume"])
            check(r.returncode == 0, f"resumed run: exit {r.returncode}\n{r.stderr[-800:]}")
        else:
            os.makedirs(b)
            r = run(base + ["--output", b, "--resume"])
            check(r.returncode == 1 and "no checkpoint" in r.stderr,
                  f"--resume without a checkpoint: exit {r.returncode}, stderr {r.stderr[-400:]!r}")
            shutil.rmtree(b)
            shutil.copytree(a, b)
            good = os.path.join(work, "checkpoint.good")
            shutil.copy(os.path.join(b, "checkpoint.bin"), good)
            size = os.path.getsize(good)
            with open(good, "rb") as f:
                data = f.read()
            for what, bad, expected in [("truncated", data[: size // 2], "truncated"),
                                        ("corrupt", data[:100] + bytes([data[100] ^ 1]) + data[101:], "checksum"),
                                        ("empty", b"", "not a contact checkpoint"),
                                        ("header only", data[:40], "truncated"),
                                        ("not a checkpoint", b"name = 'x'\n" * 10, "not a contact checkpoint")]:
                with open(os.path.join(b, "checkpoint.bin"), "wb") as f:
                    f.write(bad)
                r = run(base + ["--output", b, "--resume"])
                check(r.returncode == 1 and expected in r.stderr,
                      f"--resume with a {what} checkpoint: exit {r.returncode}, stderr {r.stderr[-400:]!r}")
            shutil.copy(good, os.path.join(b, "checkpoint.bin"))
            with open(scene) as f:
                text = f.read()
            changed = os.path.join(work, "changed.toml")
            with open(changed, "w") as f:
                f.write(text.replace("[output]", "[output]\n# a changed line", 1))
            r = run([args.contact_sim, changed, "--quiet", *args.overrides, "--output", b, "--resume"])
            check(r.returncode == 1 and "the scene changed" in r.stderr and "# a changed line" in r.stderr
                  and r.stderr.count("0x") >= 2,
                  f"--resume of a changed scene: exit {r.returncode}, stderr {r.stderr[-600:]!r}")
            r = run(base + ["--output", b, "--resume", "--dt", "1e-7"])
            check(r.returncode == 1 and "the scene changed" in r.stderr and "override" in r.stderr,
                  f"--resume with another override: exit {r.returncode}, stderr {r.stderr[-600:]!r}")
            check_mesh_change(args.contact_sim, work)
            print("refusals:", "ok" if not FAILURES else "failed")
            # B (a copy of A) must be untouched by the refused resumes.
        worst = compare_directories(a, b, args.tolerance)
        print(f"{args.mode}: {total} steps, resumed vs uninterrupted: max relative difference {worst:.3e}"
              + (" (bitwise)" if args.tolerance is None else f" (tolerance {args.tolerance:g})"))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
