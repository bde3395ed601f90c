"""Runs the README's runnable snippets as a newcomer would, from a scratch directory
outside the repository.

A fenced block preceded by a marker line is checked:
    <!-- doctest: file NAME -->          the block is saved as NAME in the scratch directory
    <!-- doctest: shell -->              run by bash there, build/bin first on PATH; exit 0
    <!-- doctest: python -->             run by this interpreter there, PYTHONPATH=build/python
    <!-- doctest: file-equals PATH -->   the block equals the repository file PATH
Blocks run in README order.  Fenced blocks without a marker are not run; the test fails if
the README has no marked block of each kind it knows (a test that cannot fail is a defect).
Every relative link of the README and of docs/*.md must name an existing file (the files
in WRITTEN_ELSEWHERE come from other branches of issue 30 and are only reported).

    /usr/bin/python3 tests/doc/run_readme.py --readme README.md --bin build/bin --python build/python
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")
WRITTEN_ELSEWHERE = set()
MARKED_BLOCK = re.compile(r"<!-- doctest: (\S+)(?: (\S+))? -->\n```[\w+-]*\n(.*?)```", re.S)


def blocks(readme_text):
    """[(kind, argument, body, line)] of the marked blocks."""
    return [(m.group(1), m.group(2), m.group(3), readme_text.count("\n", 0, m.start()) + 1)
            for m in MARKED_BLOCK.finditer(readme_text)]


def broken_links(repo):
    """[(file, target)] of relative links that name no file."""
    files = [os.path.join(repo, "README.md")]
    docs = os.path.join(repo, "docs")
    files += [os.path.join(docs, f) for f in sorted(os.listdir(docs)) if f.endswith(".md")]
    broken = []
    for path in files:
        with open(path) as f:
            for target in LINK.findall(f.read()):
                if "://" in target:
                    continue
                resolved = os.path.normpath(os.path.join(os.path.dirname(path), target))
                if not os.path.exists(resolved):
                    broken.append((os.path.relpath(path, repo), os.path.relpath(resolved, repo)))
    return broken


def run(kind, argument, body, env, scratch, repo):
    """None when the block passes, else what went wrong."""
    if kind == "file":
        with open(os.path.join(scratch, argument), "w") as f:
            f.write(body)
        return None
    if kind == "file-equals":
        with open(os.path.join(repo, argument)) as f:
            text = f.read()
        return None if text == body else f"differs from {argument}"
    command = {"shell": ["bash", "-e", "-c", body], "python": [sys.executable, "-c", body]}.get(kind)
    if command is None:
        return f"unknown doctest kind {kind!r}"
    p = subprocess.run(command, cwd=scratch, env=env, capture_output=True, text=True, timeout=120)
    sys.stdout.write(p.stdout)
    if p.returncode != 0:
        return f"exit code {p.returncode}\n{p.stdout}\n{p.stderr}"
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--readme", required=True)
    parser.add_argument("--bin", required=True, help="directory of contact-sim etc.")
    parser.add_argument("--python", required=True, help="directory of the ncp and contact packages")
    args = parser.parse_args()
    readme = os.path.abspath(args.readme)
    repo = os.path.dirname(readme)
    with open(readme) as f:
        found = blocks(f.read())
    kinds = {kind for kind, *_ in found}
    missing = {"file", "shell", "python", "file-equals"} - kinds
    if missing:
        sys.exit(f"{readme}: no marked block of kind {sorted(missing)}")
    env = dict(os.environ, PATH=os.path.abspath(args.bin) + os.pathsep + os.environ["PATH"],
               PYTHONPATH=os.path.abspath(args.python), MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")
    failures = 0
    for path, target in broken_links(repo):
        pending = target in WRITTEN_ELSEWHERE
        print(f"{path}: link to {target}: {'not in this branch (written elsewhere)' if pending else 'BROKEN'}")
        failures += 0 if pending else 1
    with tempfile.TemporaryDirectory(prefix="readme-") as scratch:
        for kind, argument, body, line in found:
            problem = run(kind, argument, body, env, scratch, repo)
            print(f"README.md:{line}: {kind} {argument or ''}: {'ok' if problem is None else 'FAILED'}")
            if problem is not None:
                print(problem)
                failures += 1
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
