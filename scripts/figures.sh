#!/usr/bin/env bash
# Regenerates the figures of the README (spool_payout.png, images/lazy_wave.png) and docs/runner.md
# (paper_2d_damping.png, paper_fig11_noise.png, spool_payout_shapes.png) in docs/ from the shipped scenarios (needs python3-matplotlib,
# installed from Debian when missing).
set -euo pipefail
PACKAGES_EXTRA=python3-matplotlib
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run"
OUT="$BUILD_DIR/figures"
S="$ROOT/scenarios"
"$RUN" "$S/spool_payout.yaml" --out "$OUT/payout" >/dev/null
"$RUN" "$S/lazy_wave.yaml" --out "$OUT/lazy_wave" >/dev/null
"$RUN" "$S/spool_payout.yaml" --out "$OUT/payout_strain" --set winch_mode=strain --set solver=pbd >/dev/null
"$RUN" "$S/paper_2d_experiment.yaml" --out "$OUT/drag_1" --set drag=1 --set noise=0 >/dev/null
"$RUN" "$S/paper_2d_experiment.yaml" --out "$OUT/drag_098" --set drag=0.98 --set noise=0 >/dev/null
"$RUN" "$S/paper_2d_experiment.yaml" --out "$OUT/drag_09" --set noise=0 >/dev/null
for variant in noise no_noise; do
  noise=0.0005; [ "$variant" = no_noise ] && noise=0
  "$RUN" "$S/paper_2d_experiment.yaml" --out "$OUT/$variant" --set bending=false --set noise=$noise \
    --set seed=3 >/dev/null
done
/usr/bin/python3 "$ROOT/scripts/figures.py" "$OUT" "$ROOT/docs"
