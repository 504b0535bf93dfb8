#!/usr/bin/env bash
# The speed-against-accuracy study and the stability map (docs/accuracy.md, "Speed against accuracy"): runs every
# reference case of docs/references.md for pbd, xpbd and lumped_mass at several resolutions and efforts,
# writes docs/study.csv and docs/stability.csv and draws docs/speed_vs_accuracy.png and
# docs/stability.png (python3-matplotlib, installed from Debian when missing). About 40 s on 2 cores.
# Extra arguments go to rov_tether_study (--quick, --case NAME).
set -euo pipefail
PACKAGES_EXTRA=python3-matplotlib
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
build_target rov_tether_study_tool
OUT="$BUILD_DIR/study"
echo "== $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
"$BUILD_DIR/devel/lib/rov_tether/rov_tether_study" --out "$OUT" "$@"
cp "$OUT/study.csv" "$OUT/stability.csv" "$ROOT/docs/"
/usr/bin/python3 "$ROOT/scripts/study_figures.py" "$OUT" "$ROOT/docs"
