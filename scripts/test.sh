#!/usr/bin/env bash
# Installs what is missing, checks the formatting, builds, and runs the whole test suite
# with ctest.
#   scripts/test.sh --sanitize   the same with AddressSanitizer + UBSan (scripts/sanitize.sh)
# With CI set in the environment (CI=true, as CI services set it) both run, one after the
# other (measured from a fresh clone: benchmarks/results/reliability/README.md), then
# scripts/fuzz.sh for 20 s per reader (docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--sanitize" ]]; then
  shift
  exec bash scripts/sanitize.sh "$@"
fi
bash scripts/setup.sh
# The sources as .clang-format says (scripts/format.sh rewrites them), before the build.
bash scripts/format.sh --check
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "$(nproc)")
if [[ -n "${CI:-}" ]]; then
  bash scripts/sanitize.sh
  # Coverage-guided fuzzing of the readers, briefly and reproducibly (docs/reliability.md).
  FUZZ_SEED=1 bash scripts/fuzz.sh 20
fi
