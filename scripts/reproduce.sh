#!/usr/bin/env bash
# The main job: installs what it needs, builds the `exoid` command only (Release; scripts/test.sh
# builds the rest), and reproduces the RLS-PSO paper on the simulated APAL leg against ground
# truth. Report: results/reproduce/report.md.
# Extra arguments go to `exoid reproduce` (see `build/experiments/exoid reproduce --help`).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/build.sh" --main
exec "${BUILD_DIR:-$root/build}/experiments/exoid" reproduce "$@"
