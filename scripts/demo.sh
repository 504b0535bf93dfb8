#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the spool pay-out scenario (an ROV drives
# out 8 m, around and back) with the offline runner, then prints a summary and where the output is.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

SCENARIO="${1:-$ROOT/scenarios/spool_payout.yaml}"
OUT="${OUT:-$ROOT/out/demo}"
echo "== running $(basename "$SCENARIO")"
"$BUILD_DIR/devel/lib/rov_tether/rov_tether_run" "$SCENARIO" --out "$OUT"
echo
echo "== deployed length and tension over time (every 5 s)"
awk -F, 'NR == 1 { printf "%8s %12s %14s %16s\n", "t [s]", "deployed [m]", "T spool [N]", "T vehicle [N]"; next }
         ($1 + 0) % 5 < 1e-6 { printf "%8.1f %12.3f %14.3f %16.3f\n", $1, $2, $3, $4 }' "$OUT/state.csv"
echo
echo "CSV files are in $OUT (format: README.md, section 'Scenario runner')."
