#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main demo.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
echo
echo "== examples/ncp: a user-defined NCP =="
build/bin/ncp-example
echo
echo "== the ncp problem collection, every standard start point =="
build/bin/ncp-collection
echo
echo "== the thesis' scenes (section 6), a subset: 2D friction on the curved obstacle, 3D frictionless =="
bash examples/run_thesis.sh --demo
echo "(all scenes: examples/run_thesis.sh; validations: examples/run_validation.sh; gallery: examples/README.md)"
