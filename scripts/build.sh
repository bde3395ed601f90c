#!/usr/bin/env bash
# Configures (Release) and builds into build/ with all cores.
set -euo pipefail
cd "$(dirname "$0")/.."
# With ccache (scripts/setup.sh installs it) a rebuild of unchanged sources is a cache hit,
# also from another clone: CCACHE_BASEDIR makes the cached paths relative to this checkout.
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
export CCACHE_BASEDIR="$PWD"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build build -j "$(nproc)"
