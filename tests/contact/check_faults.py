#!/usr/bin/python3
"""No result lost on a fault (docs/reliability.md).

  check_faults.py --contact-sim build/bin/contact-sim --fc-solve build/bin/fc-solve \
                  --scene examples/thesis/friction_2d_flat.toml --problem data/fc3d/X.dat

Full disk is imitated by a file-size limit (RLIMIT_FSIZE, `ulimit -f`), an unwritable output
by a path below a regular file and a directory in place of the output file (root may write
anywhere else). For each fault the tool must exit with 3, name the file and the reason on
stderr, never print `completed` or `converged`, and leave no file that claims more than it
holds: every CSV line has the header's column count, no .vtu/.pvd is empty or cut short, no
reactions file exists unless complete. SIGINT / SIGTERM after the first progress line must
end the run after a finished step with 130 / 143, "interrupted at step N (t = ... s) of M",
and CSVs complete up to step N (steps.csv has exactly N rows, numbered 1..N).
Skips (exit 77, ctest SKIP_RETURN_CODE) if the file-size limit cannot be set.
"""
import argparse
import json
import os
import re
import resource
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


def limit_file_size(limit_bytes):
    def set_limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))
    return set_limit


def run(cmd, limit_bytes=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                          preexec_fn=limit_file_size(limit_bytes) if limit_bytes else None)


def check_csv_complete(path):
    """Every line ends with a newline and has the header's number of columns; returns the
    number of data rows."""
    with open(path, "rb") as f:
        data = f.read()
    name = os.path.basename(path)
    if not data:
        check(False, f"{name}: empty (not even the header)")
        return 0
    check(data.endswith(b"\n"), f"{name}: last line cut short: {data[-60:]!r}")
    lines = data.decode().split("\n")[:-1]
    columns = lines[0].count(",") + 1
    bad = [i + 1 for i, line in enumerate(lines) if line.count(",") + 1 != columns]
    check(not bad, f"{name}: lines {bad[:5]} do not have {columns} columns")
    return len(lines) - 1


def check_directory_honest(directory):
    """No file in `directory` claims more than it holds."""
    for name in sorted(os.listdir(directory)):
        path = os.path.join(directory, name)
        if name.endswith(".partial"):
            check(False, f"{name}: a temporary file was left behind")
        elif name.endswith(".csv"):
            check_csv_complete(path)
        elif name.endswith((".vtu", ".pvd")):
            with open(path, "rb") as f:
                data = f.read()
            check(data.rstrip().endswith(b"</VTKFile>"), f"{name}: {len(data)} bytes, not a complete VTK file")


def check_output_failure(result, what, path_part):
    check(result.returncode == 3, f"{what}: exit {result.returncode}, expected 3\n{result.stderr[-800:]}")
    check(path_part in result.stderr, f"{what}: the message does not name {path_part}: {result.stderr[-400:]}")
    check("completed" not in result.stdout and "converged" not in result.stdout.lower(),
          f"{what}: claims success on stdout: {result.stdout[-300:]}")


def test_contact_sim_file_size_limit(args, work):
    # A full run first, to place the limit inside the largest file.
    full = os.path.join(work, "full")
    base = [args.contact_sim, args.scene, "--quiet"]
    r = run(base + ["--output", full])
    check(r.returncode == 0, f"unlimited run: exit {r.returncode}\n{r.stderr[-500:]}")
    largest = max(os.path.getsize(os.path.join(full, n)) for n in os.listdir(full))
    for limit in (1024, largest // 2):
        out = os.path.join(work, f"limit_{limit}")
        r = run(base + ["--output", out], limit_bytes=limit)
        what = f"contact-sim with a {limit}-byte file-size limit"
        check_output_failure(r, what, out)
        check("File too large" in r.stderr, f"{what}: the OS reason is missing: {r.stderr[-300:]}")
        check_directory_honest(out)
    print(f"contact-sim file-size limits 1024 and {largest // 2} bytes: checked")


def test_contact_sim_unwritable(args, work):
    blocker = os.path.join(work, "a_file")
    with open(blocker, "w") as f:
        f.write("not a directory\n")
    for out in (blocker, os.path.join(blocker, "sub")):
        r = run([args.contact_sim, args.scene, "--quiet", "--output", out])
        check_output_failure(r, f"contact-sim --output {out}", out)
    print("contact-sim into a file / below a file: checked")


def test_fc_solve(args, work):
    reactions = os.path.join(work, "reactions.txt")
    r = run([args.fc_solve, args.problem, "--reactions", reactions])
    check(r.returncode == 0, f"fc-solve unlimited: exit {r.returncode}\n{r.stderr}")
    size = os.path.getsize(reactions)
    limited = os.path.join(work, "reactions_limited.txt")
    r = run([args.fc_solve, args.problem, "--reactions", limited], limit_bytes=size // 2)
    check_output_failure(r, f"fc-solve with a {size // 2}-byte file-size limit", limited)
    check(not os.path.exists(limited), "fc-solve: a cut-short reactions file exists under the final name")
    check(not os.path.exists(limited + ".partial"), "fc-solve: the .partial file was left behind")
    for target in (work, os.path.join(work, "a_file", "r.txt")):  # a directory; below a file
        r = run([args.fc_solve, args.problem, "--reactions", target])
        check_output_failure(r, f"fc-solve --reactions {target}", target)
    print(f"fc-solve: file-size limit {size // 2} bytes, directory, below a file: checked")


def test_interrupt(args, work, sig, expected_code, json_output):
    out = os.path.join(work, f"interrupt_{sig.name}")
    cmd = [args.contact_sim, args.scene, "--output", out, "--end-time", str(args.long_end_time)]
    if json_output:
        cmd.append("--json")
    process = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    stderr_lines = []
    deadline = time.time() + 300
    for line in process.stderr:  # the first progress line: the run is stepping
        stderr_lines.append(line)
        if re.match(r"\s*step \d+ / \d+", line) or time.time() > deadline:
            break
    process.send_signal(sig)
    stdout, rest = process.communicate(timeout=300)
    stderr = "".join(stderr_lines) + rest
    what = f"contact-sim stopped by {sig.name}"
    check(process.returncode == expected_code, f"{what}: exit {process.returncode}, expected {expected_code}\n{stderr[-800:]}")
    m = re.search(r"interrupted at step (\d+) \(t = ([0-9.e+-]+) s\) of (\d+)", stderr)
    check(m is not None, f"{what}: no 'interrupted at step N (t = ... s) of M' on stderr: {stderr[-500:]}")
    if json_output:
        summary = json.loads(stdout)
        check(summary["status"] == "interrupted", f"{what}: --json status {summary['status']}")
    if m:
        step, total = int(m.group(1)), int(m.group(3))
        check(0 < step < total, f"{what}: stopped at step {step} of {total}")
        rows = check_csv_complete(os.path.join(out, "steps.csv"))
        check(rows == step, f"{what}: steps.csv has {rows} rows, the run reported step {step}")
        with open(os.path.join(out, "steps.csv")) as f:
            numbers = [int(line.split(",")[0]) for line in f.readlines()[1:]]
        check(numbers == list(range(1, step + 1)), f"{what}: steps.csv is not steps 1..{step}")
        print(f"{what}: exit {process.returncode} at step {step} of {total}")
    check_directory_honest(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--contact-sim", required=True)
    parser.add_argument("--fc-solve", required=True)
    parser.add_argument("--scene", required=True, help="a short scene that writes every output")
    parser.add_argument("--problem", required=True, help="a Siconos .dat problem fc-solve solves")
    parser.add_argument("--long-end-time", type=float, default=30.0,
                        help="end time [s] of the interrupted runs (long enough to be stopped)")
    args = parser.parse_args()
    try:
        subprocess.run(["true"], preexec_fn=limit_file_size(4096), check=True)
    except (OSError, ValueError, subprocess.SubprocessError) as e:
        print(f"SKIP: cannot set a file-size limit (RLIMIT_FSIZE): {e}")
        return 77
    with tempfile.TemporaryDirectory(prefix="check_faults_") as work:
        test_contact_sim_file_size_limit(args, work)
        test_contact_sim_unwritable(args, work)
        test_fc_solve(args, work)
        test_interrupt(args, work, signal.SIGINT, 130, json_output=False)
        test_interrupt(args, work, signal.SIGTERM, 143, json_output=True)
    if FAILURES:
        print(f"{len(FAILURES)} failures")
        return 1
    print("all fault checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
