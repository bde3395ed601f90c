"""Checks the project's Markdown pages: links, the docs index, and every fenced code block.

Every fenced block (```) of every Markdown page of the repository carries a marker, an HTML
comment on the line before its opening fence (docs/README.md, "Code blocks", is the reference):

    <!-- doctest: file NAME -->         saved as NAME in the scratch directory
    <!-- doctest: file-equals PATH -->  must equal the repository file PATH, byte for byte
    <!-- doctest: shell -->             run by `bash -e` in the scratch directory; exit 0
    <!-- doctest: python -->            run by this interpreter in the scratch directory; exit 0
    <!-- doctest: shell-mpi -->         as shell, run only by --mpi (OpenMPI's root variables set)
    <!-- doctest: output -->            what a command prints: not run
    <!-- doctest: fragment -->          a piece of a program, not complete: not run
    <!-- doctest: skip REASON -->       not run, for the REASON given (a word or more)

The scratch directory is a fresh one outside the repository holding a copy of examples/ and
build/bin, build/python linked to the build's: commands written as in the source tree
(`build/bin/contact-sim examples/scenes/...`) and as once installed (`contact-sim`, on PATH)
both run there. Pages run in path order, their blocks in page order, all in one directory.

    --links   every relative link names an existing file (and an existing heading for
              `page.md#anchor`), every docs/*.md page is linked from docs/README.md, every
              fenced block has a known marker; needs no build
    (default) the file, file-equals, shell and python blocks
    --mpi     the shell-mpi blocks

    /usr/bin/python3 tests/doc/run_docs.py --repo . --links
    /usr/bin/python3 tests/doc/run_docs.py --repo . --bin build/bin --python build/python [--mpi]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

RUN_KINDS = {"file", "file-equals", "shell", "python", "shell-mpi"}
KINDS = RUN_KINDS | {"output", "fragment", "skip"}
MARKER = re.compile(r"^\s*<!-- doctest: (\S+)(?: (.*?))? -->\s*$")
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})([^`\s]*)\s*$")
LINK = re.compile(r"\]\(([^)\s]+)\)")
SKIPPED_DIRS = {"build", ".git", "ISSUES"}


def markdown_pages(repo):
    """Relative paths of the repository's Markdown pages, sorted."""
    pages = []
    for root, dirs, files in os.walk(repo):
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("."))
        pages += [os.path.relpath(os.path.join(root, f), repo) for f in files if f.endswith(".md")]
    return sorted(pages)


def fenced_blocks(text):
    """[(kind or None, argument, body, line)] of the fenced blocks of a page, in order."""
    lines = text.split("\n")
    found, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence = m.group(1), m.group(2)
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*" + re.escape(fence) + r"\s*$", lines[j]):
            j += 1
        body = "\n".join(l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1:j])
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        marker = MARKER.match(lines[k]) if k >= 0 else None
        kind, argument = (marker.group(1), marker.group(2)) if marker else (None, None)
        found.append((kind, argument, body + "\n" if body else body, i + 1))
        i = j + 1
    return found


def outside_code(text, spans=True):
    """The page without its fenced blocks and (spans) inline code spans: links there are text."""
    kept, fence = [], None
    for line in text.split("\n"):
        m = FENCE.match(line)
        if fence is None and m:
            fence = m.group(2)
        elif fence is not None and re.match(r"^\s*" + re.escape(fence) + r"\s*$", line):
            fence = None
        elif fence is None:
            kept.append(re.sub(r"`[^`]*`", "", line) if spans else line)
    return "\n".join(kept)


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[`*_]|\[|\]\([^)]*\)", "", heading.strip().lower())
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def anchors(path):
    """Anchors of a Markdown file's headings (duplicates numbered as GitHub does)."""
    seen, result = {}, set()
    for line in outside_code(open(path).read(), spans=False).split("\n"):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            s = slug(m.group(1))
            result.add(s if s not in seen else f"{s}-{seen[s]}")
            seen[s] = seen.get(s, 0) + 1
    return result


def link_problems(repo, pages):
    """Messages for links that name no file or heading, and for unmarked blocks."""
    problems = []
    for page in pages:
        path = os.path.join(repo, page)
        text = open(path).read()
        for target in LINK.findall(outside_code(text)):
            if re.match(r"^[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
                if file_part else path
            if not os.path.exists(resolved):
                problems.append(f"{page}: link to {target}: no such file")
            elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                problems.append(f"{page}: link to {target}: no heading '#{anchor}' there")
        for kind, argument, _, line in fenced_blocks(text):
            if kind is None:
                problems.append(f"{page}:{line}: fenced block without a doctest marker")
            elif kind not in KINDS:
                problems.append(f"{page}:{line}: unknown doctest kind {kind!r}; known: "
                                + ", ".join(sorted(KINDS)))
            elif kind in {"file", "file-equals", "skip"} and not argument:
                problems.append(f"{page}:{line}: doctest {kind} needs an argument")
    return problems


def index_problems(repo):
    """Pages of docs/ that docs/README.md does not link."""
    docs = os.path.join(repo, "docs")
    index = os.path.join(docs, "README.md")
    if not os.path.exists(index):
        return ["docs/README.md (the index) is missing"]
    linked = {os.path.normpath(os.path.join(docs, t.partition("#")[0]))
              for t in LINK.findall(open(index).read())}
    return [f"docs/{f}: not linked from docs/README.md" for f in sorted(os.listdir(docs))
            if f.endswith(".md") and f != "README.md" and os.path.join(docs, f) not in linked]


def run_block(kind, argument, body, env, scratch, repo):
    """None when the block passes, else what went wrong."""
    if kind == "file":
        target = os.path.join(scratch, argument)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with open(target, "w") as f:
            f.write(body)
        return None
    if kind == "file-equals":
        with open(os.path.join(repo, argument)) as f:
            return None if f.read() == body else f"differs from {argument}"
    command = {"shell": ["bash", "-e", "-c", body], "shell-mpi": ["bash", "-e", "-c", body],
               "python": [sys.executable, "-c", body]}[kind]
    p = subprocess.run(command, cwd=scratch, env=env, capture_output=True, text=True, timeout=300)
    sys.stdout.write(p.stdout[-2000:])
    return None if p.returncode == 0 else f"exit code {p.returncode}\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}"


def make_scratch(scratch, repo, bin_dir, python_dir):
    """A copy of examples/ and build/{bin,python} linked to the build's."""
    shutil.copytree(os.path.join(repo, "examples"), os.path.join(scratch, "examples"))
    os.makedirs(os.path.join(scratch, "build"))
    os.symlink(os.path.abspath(bin_dir), os.path.join(scratch, "build", "bin"))
    os.symlink(os.path.abspath(python_dir), os.path.join(scratch, "build", "python"))


def run_pages(repo, pages, kinds, bin_dir, python_dir):
    """Runs the blocks of the given kinds; the number of failures."""
    env = dict(os.environ, PATH=os.path.abspath(bin_dir) + os.pathsep + os.environ["PATH"],
               PYTHONPATH=os.path.abspath(python_dir), MPLBACKEND="Agg",
               PYTHONDONTWRITEBYTECODE="1", OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    failures, ran = 0, set()
    with tempfile.TemporaryDirectory(prefix="docs-") as scratch:
        make_scratch(scratch, repo, bin_dir, python_dir)
        for page in pages:
            for kind, argument, body, line in fenced_blocks(open(os.path.join(repo, page)).read()):
                if kind not in kinds:
                    continue
                problem = run_block(kind, argument, body, env, scratch, repo)
                ran.add(kind)
                print(f"{page}:{line}: {kind} {argument or ''}: {'ok' if problem is None else 'FAILED'}")
                if problem is not None:
                    print(problem)
                    failures += 1
    for kind in sorted(kinds - ran):  # a test that cannot fail is a defect
        print(f"no block of kind {kind} found")
        failures += 1
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repo", required=True, help="the source tree")
    parser.add_argument("--links", action="store_true", help="check links, index and markers")
    parser.add_argument("--mpi", action="store_true", help="run the shell-mpi blocks")
    parser.add_argument("--bin", help="directory of contact-sim etc.")
    parser.add_argument("--python", help="directory of the ncp and contact packages")
    parser.add_argument("pages", nargs="*", help="only these pages (relative to --repo)")
    args = parser.parse_args()
    repo = os.path.abspath(args.repo)
    pages = args.pages or markdown_pages(repo)
    if args.links:
        problems = link_problems(repo, pages) + index_problems(repo)
        print("\n".join(problems) if problems else f"{len(pages)} pages: links, index, markers ok")
        sys.exit(1 if problems else 0)
    if not args.bin or not args.python:
        parser.error("--bin and --python are needed to run blocks")
    kinds = {"shell-mpi"} if args.mpi else {"file", "file-equals", "shell", "python"}
    if args.mpi:  # the MPI blocks may read files written by earlier blocks
        kinds |= {"file"}
    sys.exit(1 if run_pages(repo, pages, kinds, args.bin, args.python) else 0)


if __name__ == "__main__":
    main()
