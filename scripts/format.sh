#!/usr/bin/env bash
# Formats every C++ source of the repository with the project's .clang-format (Google style,
# 90 columns), or with --check reports the files that differ and exits 1 (scripts/test.sh runs
# the check before building, so the tree stays formatted).
#   scripts/format.sh           rewrite the files in place
#   scripts/format.sh --check   list unformatted files; exit 1 if there are any
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT="${CLANG_FORMAT:-clang-format}"
if ! command -v "$CLANG_FORMAT" > /dev/null; then
  echo "format.sh: $CLANG_FORMAT not found (scripts/setup.sh installs clang-format)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cc')
if [[ "${1:-}" == "--check" ]]; then
  # One clang-format run over all files; its warnings name each file that differs.
  mapfile -t bad < <("$CLANG_FORMAT" --dry-run "${files[@]}" 2>&1 |
    sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: warning: .*/\1/p' | sort -u)
  if (( ${#bad[@]} > 0 )); then
    echo "format.sh: ${#bad[@]} file(s) differ from .clang-format (run scripts/format.sh):" >&2
    printf '  %s\n' "${bad[@]}" >&2
    exit 1
  fi
  echo "format.sh: ${#files[@]} C++ files formatted as .clang-format says"
elif [[ $# -eq 0 ]]; then
  "$CLANG_FORMAT" -i "${files[@]}"
else
  echo "usage: scripts/format.sh [--check]" >&2
  exit 2
fi
