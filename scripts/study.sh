#!/usr/bin/env bash
# The speed-against-accuracy study and the stability map (docs/accuracy.md, "Speed against accuracy"): runs every
# reference case of docs/references.md for pbd, xpbd, lumped_mass and direct at several resolutions and efforts,
# writes docs/study.csv and docs/stability.csv and draws docs/speed_vs_accuracy.png and
# docs/stability.png (python3-matplotlib, installed from Debian when missing). 6 min 27 s (4 min 20 s of CPU:
# the tool runs on one core) on a shared 2-core machine; its last lines are study_figures.py's summary.
# Extra arguments go to rov_tether_study (--quick, --case NAME, --no-stability): such a partial run leaves its
# CSV files and figures in catkin_build/study/ and does not touch docs/, which holds the full run only.
set -euo pipefail
PACKAGES_EXTRA=python3-matplotlib
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
build_target rov_tether_study_tool
OUT="$BUILD_DIR/study"
echo "== $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
# Results of an earlier run must not pass for this one's (--no-stability writes no stability.csv).
rm -f "$OUT/study.csv" "$OUT/stability.csv"
"$BUILD_DIR/devel/lib/rov_tether/rov_tether_study" --out "$OUT" "$@"
if (($# > 0)); then
  # A partial run: docs/ keeps the full run's CSV files and figures.
  if [ -f "$OUT/stability.csv" ]; then
    /usr/bin/python3 "$ROOT/scripts/study_figures.py" "$OUT" "$OUT"
  fi
  echo "== a partial run (extra arguments: $*): results in $OUT, docs/ left as it was"
  exit 0
fi
cp "$OUT/study.csv" "$OUT/stability.csv" "$ROOT/docs/"
/usr/bin/python3 "$ROOT/scripts/study_figures.py" "$OUT" "$ROOT/docs"
