#!/usr/bin/python3
"""Input fuzz test of contact-sim: mutates valid scene (TOML) and mesh (.msh) files with a
fixed seed, runs each case in a child process with a wall-time and memory limit, and fails
on
  - a crash (a signal, an exit code other than 0, 1, 2, or a sanitizer report),
  - a hang (the wall-time limit),
  - exit 0 on an input that is certainly nonsense (a value of the wrong type, NaN, Inf,
    +-1e308, an integer beyond int64, arrays nested deeper than the limit, a duplicated
    key, an unknown key, binary garbage),
  - an error (exit 1 or 2) whose message names neither the scene file nor the mesh file.

  fuzz_inputs.py --contact-sim build/bin/contact-sim --cases 40 --seed 1
Every failing case is kept in --keep-dir with its command line, for reproduction.
"""
import argparse
import os
import random
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
SCENES = [os.path.join(SOURCE, "examples", "scenes", "block_drop_2d.toml"),
          os.path.join(SOURCE, "examples", "validation", "incline.toml"),
          os.path.join(HERE, "square_msh.toml")]
MESH = os.path.join(HERE, "square.msh")

# Values that no scene key accepts: NaN, Inf, beyond every range, beyond int64.
NONSENSE_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1e308", "99999999999999999999",
                    "-99999999999999999999"]
# Edge values some keys accept and others refuse.
EDGE_NUMBERS = ["0", "-0.0", "-1", "1e-308", "1e15", "-1e15", "4294967297", "2147483648",
                "9223372036854775807", "-9223372036854775808", "0.5"]
OTHER_TYPES = {"string": '"x"', "bool": "true", "array": "[1, 2]", "table": "{ a = 1 }",
               "datetime": "1979-05-27T07:32:00Z"}
ASSIGNMENT = re.compile(r'^(\s*)([A-Za-z0-9_]+)(\s*=\s*)(.*?)(\s*(#.*)?)$')


def value_kind(value):
    if value.startswith('"') or value.startswith("'"):
        return "string"
    if value in ("true", "false"):
        return "bool"
    if value.startswith("["):
        return "array"
    if value.startswith("{"):
        return "table"
    return "number"


def mutate_scene(rng, text):
    """(mutated text, what was done, whether the result is certainly invalid)."""
    lines = text.split("\n")
    assignments = [i for i, line in enumerate(lines) if ASSIGNMENT.match(line)]
    kind = rng.choice(["type", "nonsense-number", "edge-number", "truncate", "nest", "missing",
                       "duplicate", "garbage", "unknown-key", "garbage-file"])
    if kind in ("type", "nonsense-number", "edge-number"):
        i = rng.choice(assignments)
        indent, key, equals, value, comment = ASSIGNMENT.match(lines[i]).groups()[:5]
        if kind == "type":
            choices = [k for k in OTHER_TYPES if k != value_kind(value)]
            new = OTHER_TYPES[rng.choice(choices)]
        else:
            pool = NONSENSE_NUMBERS if kind == "nonsense-number" else EDGE_NUMBERS
            numbers = list(re.finditer(r"-?[0-9][0-9.eE+-]*", value))
            if value_kind(value) not in ("number", "array") or not numbers:
                new = rng.choice(pool)  # a number where a string or bool was: wrong type
                kind = "type"
            else:
                m = rng.choice(numbers)
                new = value[:m.start()] + rng.choice(pool) + value[m.end():]
        lines[i] = indent + key + equals + new + (comment or "")
        return "\n".join(lines), "%s: line %d '%s' = %s" % (kind, i + 1, key, new), \
            kind in ("type", "nonsense-number")
    if kind == "truncate":
        cut = rng.randrange(len(text))
        return text[:cut], "truncate at byte %d" % cut, False
    if kind == "nest":
        i = rng.choice(assignments)
        indent, key, equals = ASSIGNMENT.match(lines[i]).groups()[:3]
        depth = rng.choice([33, 100, 1000, 100000, 300000])
        opener, closer = rng.choice([("[", "]"), ("{a=", "}")])
        lines[i] = indent + key + equals + opener * depth + "1" + closer * depth
        return "\n".join(lines), "nest '%s' %d deep with %s" % (key, depth, opener), True
    if kind == "missing":
        i = rng.choice(assignments)
        removed = lines.pop(i)
        return "\n".join(lines), "missing line %d: %s" % (i + 1, removed.strip()), False
    if kind == "duplicate":
        i = rng.choice(assignments)
        lines.insert(i + 1, lines[i])
        return "\n".join(lines), "duplicate line %d: %s" % (i + 1, lines[i].strip()), True
    if kind == "unknown-key":
        i = rng.choice(assignments)
        lines.insert(i + 1, "colour_%d = 3" % rng.randrange(1000))
        return "\n".join(lines), "unknown key after line %d" % (i + 1), True
    garbage = bytes([rng.randrange(0x80, 0x100)]) + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 200)))
    if kind == "garbage":
        i = rng.randrange(len(lines) + 1)
        lines.insert(i, garbage.decode("latin-1"))
        return "\n".join(lines), "binary garbage line at %d" % (i + 1), True
    return garbage.decode("latin-1") * rng.randrange(1, 50), "binary garbage file", True


def mutate_mesh(rng, text):
    """(mutated .msh text, what was done); a mutated mesh may still be valid."""
    lines = text.split("\n")
    kind = rng.choice(["number", "number", "truncate", "missing", "duplicate", "garbage", "swap"])
    i = rng.randrange(len(lines))
    if kind == "number":
        tokens = list(re.finditer(r"-?[0-9][0-9.eE+-]*", lines[i]))
        if tokens:
            m = rng.choice(tokens)
            new = rng.choice(["0", "-1", "1e12", "4294967297", "99999999999999999999", "2147483648",
                              "nan", "1e308", "3", "100000000", "100000001"])
            lines[i] = lines[i][:m.start()] + new + lines[i][m.end():]
            return "\n".join(lines), "mesh line %d token -> %s" % (i + 1, new)
    if kind == "truncate":
        cut = rng.randrange(len(text))
        return text[:cut], "mesh truncated at byte %d" % cut
    if kind == "missing":
        lines.pop(i)
        return "\n".join(lines), "mesh line %d removed" % (i + 1)
    if kind == "duplicate":
        lines.insert(i, lines[i])
        return "\n".join(lines), "mesh line %d duplicated" % (i + 1)
    if kind == "swap" and i + 1 < len(lines):
        lines[i], lines[i + 1] = lines[i + 1], lines[i]
        return "\n".join(lines), "mesh lines %d and %d swapped" % (i + 1, i + 2)
    lines.insert(i, "".join(chr(rng.randrange(256)) for _ in range(rng.randrange(1, 100))))
    return "\n".join(lines), "mesh garbage line at %d" % (i + 1)


def limits(memory_mb, cpu_s):
    def apply():
        if memory_mb > 0:
            resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_s, cpu_s + 1))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def run_case(args, workdir, scene_text, mesh_text, quiet):
    scene = os.path.join(workdir, "case.toml")
    with open(scene, "w", encoding="latin-1") as f:
        f.write(scene_text)
    with open(os.path.join(workdir, "square.msh"), "w", encoding="latin-1") as f:
        f.write(mesh_text)
    command = [os.path.abspath(args.contact_sim), scene, "--no-output"] + (["--quiet"] if quiet else [])
    start = time.monotonic()
    try:
        p = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, timeout=args.time_limit, cwd=workdir,
                           preexec_fn=limits(args.memory_mb, int(args.time_limit) + 1))
    except subprocess.TimeoutExpired:
        return command, None, "", time.monotonic() - start
    return command, p.returncode, p.stderr.decode("utf-8", "replace"), time.monotonic() - start


def judge(code, stderr, certainly_invalid):
    """The defect of one run, or None."""
    if code is None:
        return "hang (no exit within the time limit)"
    if "ERROR: AddressSanitizer" in stderr or "runtime error:" in stderr or "LeakSanitizer" in stderr:
        return "sanitizer report"
    if code < 0 or code not in (0, 1, 2):
        return "crash (exit code %d)" % code
    if code == 0 and certainly_invalid:
        return "exit 0 on nonsense"
    if code != 0 and "case.toml" not in stderr and "square.msh" not in stderr:
        return "error message names neither the scene nor the mesh file"
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--contact-sim", required=True)
    parser.add_argument("--cases", type=int, default=40)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time-limit", type=float, default=30.0, help="wall seconds per case")
    parser.add_argument("--memory-mb", type=int, default=2048, help="address-space limit (0 = none)")
    parser.add_argument("--keep-dir", default="fuzz-failures")
    parser.add_argument("--show", action="store_true", help="print every case and its message")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    seeds = [open(path, encoding="utf-8").read() for path in SCENES]
    # Scene paths inside the seeds are relative: keep the mesh next to the case.
    # No output files; the incline seed runs 0.02 s instead of 0.4 s (a short case).
    seeds = [re.sub(r'(?m)^directory = .*$', '', s) for s in seeds]
    seeds = [s.replace("end_time = 0.4 ", "end_time = 0.02") for s in seeds]
    mesh_seed = open(MESH, encoding="utf-8").read()
    counts, failures, slowest = {}, [], 0.0
    with tempfile.TemporaryDirectory(prefix="contact_fuzz_") as workdir:
        for case in range(args.cases):
            seed_index = rng.randrange(len(seeds))
            scene_text, mesh_text = seeds[seed_index], mesh_seed
            if seed_index == 2 and rng.random() < 0.5:
                mesh_text, what = mutate_mesh(rng, mesh_text)
                certainly_invalid = False
            else:
                scene_text, what, certainly_invalid = mutate_scene(rng, scene_text)
            quiet = rng.random() < 0.5
            command, code, stderr, seconds = run_case(args, workdir, scene_text, mesh_text, quiet)
            slowest = max(slowest, seconds)
            counts[code] = counts.get(code, 0) + 1
            defect = judge(code, stderr, certainly_invalid)
            if args.show:
                print("case %d: %s -> exit %s: %s" % (case, what, code, stderr.strip().split("\n")[-1][:300]))
            if (case + 1) % 100 == 0:
                print("fuzz: %d of %d cases, %d defects so far" % (case + 1, args.cases, len(failures) + bool(defect)),
                      flush=True)
            if defect:
                keep = os.path.join(args.keep_dir, "case_%d" % case)
                os.makedirs(keep, exist_ok=True)
                shutil.copy(os.path.join(workdir, "case.toml"), keep)
                shutil.copy(os.path.join(workdir, "square.msh"), keep)
                failures.append("case %d (%s, seed %s): %s\n  %s\n  stderr: %s" % (
                    case, what, os.path.basename(SCENES[seed_index]), defect, " ".join(command),
                    stderr.strip()[-600:]))
    print("fuzz: %d cases (seed %d), exit codes %s, slowest case %.2f s, %d defects" % (
        args.cases, args.seed, {("timeout" if k is None else k): v for k, v in sorted(counts.items(), key=str)},
        slowest, len(failures)))
    for f in failures:
        print(f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
