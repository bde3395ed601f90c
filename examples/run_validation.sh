#!/usr/bin/env bash
# Runs the validations against exact solutions (examples/validation/validate.py): elastic
# bar impact on 4 meshes and 3 time steps, a block sliding to rest, a block on an incline
# at 4 angles. Prints the error tables; writes build/output/validation/validation.md and
# build/output/validation/figures/*.png. Needs build/bin/contact-sim and /usr/bin/python3.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/bin/contact-sim ] || { echo "run_validation: build/bin/contact-sim is missing; build it first" >&2; exit 2; }
/usr/bin/python3 examples/validation/validate.py --sim build/bin/contact-sim --out build/output/validation
