#!/usr/bin/env bash
# Runs the whole obstacle table of ncp-petsc-bench (benchmarks/results/petsc/README.md) in one
# run: every (ranks, grid, solver configuration) in its own process under mpiexec, so that a
# crash or a hang of one configuration costs only its own row; a run killed by the time limit
# gets a row with status time_limit. Then draws the plot.
#
#   benchmarks/petsc/run.sh [BUILD_DIR] [OUT_DIR]        (defaults: build, benchmarks/results/petsc)
#
# Environment: GRIDS (default "129 257 513 1025 2049 4097"), RANKS (default "1 2"),
# TIME_LIMIT seconds per row (default 240), SOLVERS (only these configurations), QUICK=1 for a short check (grids 33 65, 60 s),
# REPEAT_BELOW (default 1000: grids of fewer nodes per side run REPEATS times, default 3, and the
# fastest converged run is the row; every solver alike, so that a row of 0.1 s measures the
# solver rather than the machine's noise). The column `runs` says how many runs a row is the best of.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
out=${2:-$root/benchmarks/results/petsc}
bench=$build/bin/ncp-petsc-bench
[ -x "$bench" ] || { echo "run.sh: $bench not found (build the target ncp-petsc-bench)" >&2; exit 1; }
mkdir -p "$out"
csv=$out/obstacle.csv
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
grids=${GRIDS:-129 257 513 1025 2049 4097}
ranks_list=${RANKS:-1 2}
time_limit=${TIME_LIMIT:-240}
if [ "${QUICK:-0}" = 1 ]; then grids="33 65"; time_limit=60; fi
repeat_below=${REPEAT_BELOW:-1000}
repeats=${REPEATS:-3}

# Configurations by grid (chosen so that the whole table fits in about half an hour on the
# 2 shared cores; the largest grid, 4097^2 = 1.7*10^7 unknowns, took 10 GiB on one rank):
# nested iteration / grid sequencing with multigrid at every size, with hypre up to 10^6; the
# direct (MUMPS LU) ones, GAMG, and hypre from the zero start without sequencing (the way the
# issue's first measurements ran) only on the smallest grid.
configs_for_grid() {
  local g=$1
  echo ncp-min-seq-mg rsls-seq-mg ssls-seq-mg
  if [ "$g" -le 1025 ]; then echo ncp-fb-seq-mg ncp-min-seq-hypre rsls-seq-hypre; fi
  if [ "$g" -le 129 ]; then
    echo ncp-min-lu ncp-fb-lu ssls-lu rsls-lu ssls-gamg rsls-gamg ncp-min-hypre ncp-fb-hypre rsls-hypre ssls-hypre
  fi
}

echo "$("$bench" --print-header),runs" > "$csv"

# The fastest converged row of `runs` runs of one configuration (each its own process) into
# $row_csv, or nothing when no run wrote a row; rc: the last run's exit status.
run_row() {
  local ranks=$1 g=$2 config=$3 runs=$4 best="" best_seconds="" run
  for run in $(seq "$runs"); do
    : > "$row_csv.one"
    set +e
    timeout --kill-after=10 "$time_limit" mpiexec -n "$ranks" --oversubscribe "$bench" \
      --grids "$g" --solvers "$config" --csv "$row_csv.one" > "$row_csv.log" 2>&1
    rc=$?
    set -e
    [ "$(wc -l < "$row_csv.one")" -ge 2 ] || break
    local line seconds status
    line=$(tail -n 1 "$row_csv.one")
    seconds=$(echo "$line" | cut -d, -f12)
    status=$(echo "$line" | cut -d, -f17)
    if [ -z "$best" ] || { [ "$status" = converged ] && awk -v a="$seconds" -v b="$best_seconds" 'BEGIN { exit !(a < b) }'; }; then
      best=$line
      best_seconds=$seconds
    fi
    [ "$status" = converged ] || break  # a failed run is not repeated
  done
  if [ -n "$best" ]; then head -n 1 "$row_csv.one" > "$row_csv"; echo "$best" >> "$row_csv"; fi
  rm -f "$row_csv.one"
}
for ranks in $ranks_list; do
  for g in $grids; do
    for config in $(configs_for_grid "$g"); do
      if [ -n "${SOLVERS:-}" ] && [[ " $SOLVERS " != *" $config "* ]]; then continue; fi
      row_csv=$(mktemp)
      started=$(date +%s.%N)
      runs=1
      if [ "$g" -lt "$repeat_below" ]; then runs=$repeats; fi
      rc=0
      run_row "$ranks" "$g" "$config" "$runs"
      if [ "$(wc -l < "$row_csv")" -ge 2 ]; then
        echo "$(tail -n 1 "$row_csv"),$runs" >> "$csv"
      else
        # No row: timed out (124/137) or crashed. Record it with the time it was charged.
        elapsed=$(awk -v a="$started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
        # The first PETSc error line names the failure (commas dropped for the CSV).
        native="exit_$rc: $( (grep -m1 -E '\[0\]PETSC ERROR: [A-Z]|what\(\)|ncp-petsc-bench:' "$row_csv.log" \
                  | sed -e 's/.*PETSC ERROR: //' -e 's/,/;/g' | head -c 120) || true)"
        status=failure
        if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then status=time_limit; native=killed_after_${time_limit}s; fi
        seq=0; case $config in *-seq-*) seq=1;; esac
        linear=${config##*-}
        echo "$config,$ranks,$((g * g)),$g,,$linear,,$seq,,,,$elapsed,,,,,$status,$native,,1" >> "$csv"
        echo "run.sh: $config ranks=$ranks grid=$g: $status ($native); log tail:" >&2
        tail -n 5 "$row_csv.log" >&2 || true
      fi
      tail -n 1 "$csv"
      rm -f "$row_csv" "$row_csv.log"
    done
  done
done
/usr/bin/python3 "$here/plot_obstacle.py" "$csv" "$out/obstacle_time.png"
