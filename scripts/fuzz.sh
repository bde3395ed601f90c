#!/usr/bin/env bash
# Coverage-guided fuzzing of the readers (docs/reliability.md):
#   scripts/fuzz.sh [SECONDS] [TARGETS]
# builds the libFuzzer targets with clang, ASan and UBSan in build-fuzz (NCP_BUILD_FUZZERS)
# and runs each target for SECONDS (default 60) from a corpus seeded with the examples' and
# tests' files (plus tests/fuzz/regressions/<target>/). TARGETS: space-separated names, default
# all five: fuzz_scene fuzz_gmsh_mesh fuzz_siconos_dat fuzz_fclib fuzz_checkpoint (the FCLIB target reads
# through ncp's own HDF5 reader, ncp/fc/src/fclib_hdf5.cpp, which throws where libfclib exited). FUZZ_SEED=N makes a
# run reproducible (libFuzzer -seed=N; default: libFuzzer's random seed). Crash inputs go to
# build-fuzz/findings/<target>/; a crash fails the script - fix it and copy the input into
# tests/fuzz/regressions/<target>/, where the ctest fuzz_replay_<target> replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
targets="${2:-fuzz_scene fuzz_gmsh_mesh fuzz_siconos_dat fuzz_fclib fuzz_checkpoint}"
jobs="${FUZZ_BUILD_JOBS:-2}"
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (Debian packages clang libclang-rt-14-dev, scripts/setup.sh)" >&2
  exit 1
fi
mkdir -p build-fuzz
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# The readers -O1 with coverage and sanitizers (tests/fuzz/libfuzzer/CMakeLists.txt); the
# rest -O0 with assertions on (Eigen's index checks): it is not what is fuzzed.
CCACHE_BASEDIR="$PWD" cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O0 \
  -DCMAKE_CXX_COMPILER=clang++ -DNCP_BUILD_FUZZERS=ON -DNCP_BUILD_TESTS=OFF \
  -DNCP_BUILD_EXAMPLES=OFF -DNCP_BUILD_BENCHMARKS=OFF -DNCP_BUILD_PYTHON=OFF \
  -DNCP_WITH_SICONOS=OFF "${launcher[@]}" >build-fuzz/build.log 2>&1 &&
CCACHE_BASEDIR="$PWD" cmake --build build-fuzz -j "$jobs" --target $targets >>build-fuzz/build.log 2>&1 ||
  { tail -30 build-fuzz/build.log >&2; echo "fuzz.sh: the fuzz build failed (build-fuzz/build.log)" >&2; exit 1; }

seeds_of() {
  case "$1" in
    fuzz_scene) ls examples/scenes/*.toml examples/thesis/*.toml examples/validation/*.toml \
                   tests/contact/data/*.toml tests/fuzz/*.toml ;;
    fuzz_gmsh_mesh) ls examples/scenes/*.msh tests/fuzz/*.msh ;;
    fuzz_siconos_dat) find data/fc3d -name '*.dat' -size -20k ;;  # small seeds: fast mutations
    fuzz_fclib) ls data/fc3d/*.hdf5 ;;
    fuzz_checkpoint) ls tests/fuzz/*.ckpt ;;
    *) echo "fuzz.sh: unknown target $1" >&2; exit 2 ;;
  esac
}

status=0
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
for target in $targets; do
  corpus="build-fuzz/corpus/$target" findings="build-fuzz/findings/$target"
  mkdir -p "$corpus" "$findings"
  seeds_of "$target" | xargs -r cp -t "$corpus"
  find "tests/fuzz/regressions/$target" -type f ! -name README.md -exec cp -t "$corpus" {} + 2>/dev/null || true
  log="build-fuzz/$target.log"
  seed_option=()
  [[ -n "${FUZZ_SEED:-}" ]] && seed_option=(-seed="$FUZZ_SEED")
  echo "fuzz.sh: $target for ${seconds} s (corpus $corpus, log $log)"
  if ! "build-fuzz/bin/$target" "$corpus" "${seed_option[@]}" -max_total_time="$seconds" \
        -timeout=25 -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$findings/" \
        -print_final_stats=1 >"$log" 2>&1; then
    echo "fuzz.sh: $target FOUND A CRASH: $(ls "$findings")" >&2
    tail -40 "$log" >&2
    status=1
  fi
  grep -E "^#[0-9]+.*DONE|stat::number_of_executed_units|cov:" "$log" | tail -3 || true
done
exit $status
