#!/bin/sh
# Fetches Siconos' frictional contact test problems (numerics/src/FrictionContact/test/data,
# Apache License 2.0) at a fixed commit into DIR (default build/siconos-fc): DIR/local holds
# the 45 local problems (.dat, 2D and 3D, every storage) that benchmarks/results/fc-siconos
# was run on, DIR/global the GFC3D / gfc2d global-form ones (fc-solve --global).
# Usage: scripts/get_siconos_fc_data.sh [DIR]
set -eu
commit=6070f0f6fcd9e12457f509211e88a1a583b811bc
dir=${1:-build/siconos-fc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git -C "$tmp" init -q
git -C "$tmp" remote add origin https://github.com/siconos/siconos.git
git -C "$tmp" config core.sparseCheckout true
echo numerics/src/FrictionContact/test/data/ > "$tmp/.git/info/sparse-checkout"
git -C "$tmp" fetch -q --depth 1 --filter=blob:none origin "$commit"
git -C "$tmp" checkout -q FETCH_HEAD
mkdir -p "$dir/local" "$dir/global"
for f in "$tmp"/numerics/src/FrictionContact/test/data/*.dat; do
  name=$(basename "$f")
  case "$name" in
    ACinputs.dat) ;;                               # not a contact problem
    GFC3D_TwoRods1-condensed.dat) ;;               # local form of GFC3D_TwoRods1; not in the 45
    GFC3D_*|gfc2d_*) cp "$f" "$dir/global/" ;;
    *) cp "$f" "$dir/local/" ;;
  esac
done
echo "$(ls "$dir/local" | wc -l) local and $(ls "$dir/global" | wc -l) global problems in $dir"
