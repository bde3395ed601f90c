#!/usr/bin/env bash
# Runs the scenes of the thesis' section 6 (Tables 1-3) with contact-sim, prints our table
# beside the thesis' values and draws the figures.
#
#   examples/run_thesis.sh          all 11 variants
#   examples/run_thesis.sh --demo   the 2D curved obstacle with f_c = 0.5 and the 3D
#                                   frictionless box at dt = 2e-4 (a few seconds)
#   STEP=full examples/run_thesis.sh   the thesis' formulation (default: condensed)
#   REPEAT=1 examples/run_thesis.sh    one run per variant (default 5: the table shows the
#                                      fastest and the median t_comp)
#
# Outputs: build/output/thesis/<variant>/ (contact-sim's CSV and VTK files and run.json),
# build/output/thesis/table.md and table.csv, build/output/thesis/figures/*.png.
# Needs build/bin/contact-sim (cmake --build build --target contact-sim) and Debian's
# matplotlib (/usr/bin/python3).
set -uo pipefail
cd "$(dirname "$0")/.."
SIM=build/bin/contact-sim
OUT=build/output/thesis
FIG=$OUT/figures
PY=/usr/bin/python3
PLOT=examples/plot/plot_scene.py
S=examples/thesis
[ -x "$SIM" ] || { echo "run_thesis: $SIM is missing; build it first" >&2; exit 2; }
mkdir -p "$FIG"

demo=0
[ "${1:-}" = "--demo" ] && demo=1
# Step method: condensed (default) or full (the thesis formulation over all dofs).
STEP=${STEP:-condensed}
# Runs per variant for the timing (the first one writes the outputs).
REPEAT=${REPEAT:-5}

# variant  scene  contact-sim options
all_variants=(
  "t1_dt1e-4       frictionless_3d.toml     --dt 1e-4"
  "t1_dt2e-4       frictionless_3d.toml     --dt 2e-4"
  "t1_dt1e-2       frictionless_3d.toml     --dt 1e-2"
  "t2_curved_fc0   friction_2d_curved.toml  --friction 0"
  "t2_curved_fc0.5 friction_2d_curved.toml  --friction 0.5"
  "t2_curved_fc5   friction_2d_curved.toml  --friction 5"
  "t2_flat_fc0     friction_2d_flat.toml    --friction 0"
  "t2_flat_fc0.5   friction_2d_flat.toml    --friction 0.5"
  "t2_flat_fc5     friction_2d_flat.toml    --friction 5"
  "t3_fc0          friction_3d.toml         --friction 0"
  "t3_fc0.5        friction_3d.toml         --friction 0.5"
)
if [ $demo = 1 ]; then
  variants=("${all_variants[4]}" "${all_variants[1]}")
else
  variants=("${all_variants[@]}")
fi

names=()
for v in "${variants[@]}"; do
  read -r name scene options <<<"$v"
  names+=("$name")
  rm -rf "${OUT:?}/$name"
  mkdir -p "$OUT/$name"
  # Exit code 1 (the run stopped: refused time step, solver failure) is a result too.
  # shellcheck disable=SC2086
  "$SIM" "$S/$scene" --json --quiet --step "$STEP" --output "$OUT/$name" $options >"$OUT/$name/run.json" \
    2>"$OUT/$name/summary.txt"
  echo "$name: exit code $?, $(head -1 "$OUT/$name/summary.txt")"
  # Timing on a shared machine: REPEAT - 1 more runs without output files; the table shows
  # the fastest and the median t_comp of all runs.
  for i in $(seq 2 "$REPEAT"); do
    # shellcheck disable=SC2086
    "$SIM" "$S/$scene" --json --quiet --no-output --step "$STEP" $options >"$OUT/$name/timing_$i.json" 2>/dev/null
  done
done
echo
$PY examples/plot/thesis_table.py "$OUT" "${names[@]}"
echo

plot_run() {  # variant scene title [options]
  local name=$1 scene=$2 title=$3
  shift 3
  if ! grep -q '"status": "completed"' "$OUT/$name/run.json"; then
    echo "($name did not complete: no figures)"
    return 0
  fi
  $PY $PLOT run "$OUT/$name" --scene "$S/$scene" --prefix "$FIG/$name" --title "$title" "$@"
}
has() { [[ " ${names[*]} " == *" $1 "* ]]; }

has t1_dt1e-4 && plot_run t1_dt1e-4 frictionless_3d.toml "6.1: 3D frictionless, dt = 1e-4 s" \
  --stress-times 0.008 0.02
has t1_dt2e-4 && plot_run t1_dt2e-4 frictionless_3d.toml "6.1: 3D frictionless, dt = 2e-4 s" \
  --stress-times 0.008 0.02
for obstacle in curved flat; do
  for fc in 0 0.5 5; do
    has t2_${obstacle}_fc$fc && plot_run t2_${obstacle}_fc$fc friction_2d_$obstacle.toml \
      "6.2: 2D, $obstacle obstacle, f_c = $fc"
  done
  if has t2_${obstacle}_fc0 && has t2_${obstacle}_fc0.5 && has t2_${obstacle}_fc5; then
    $PY $PLOT compare --scene $S/friction_2d_$obstacle.toml --time 0.25 \
      --out "$FIG/t2_${obstacle}_compare.png" --title "6.2: 2D, $obstacle obstacle" \
      "$OUT/t2_${obstacle}_fc0=f_c = 0" "$OUT/t2_${obstacle}_fc0.5=f_c = 0.5" "$OUT/t2_${obstacle}_fc5=f_c = 5"
  fi
done
has t3_fc0 && plot_run t3_fc0 friction_3d.toml "6.3: 3D, f_c = 0" --arrows
has t3_fc0.5 && plot_run t3_fc0.5 friction_3d.toml "6.3: 3D, f_c = 0.5" --arrows
echo
echo "table:   $OUT/table.md"
echo "figures: $FIG/"
