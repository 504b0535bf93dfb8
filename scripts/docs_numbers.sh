#!/usr/bin/env bash
# Prints the numbers the README and docs/ quote from the shipped scenarios, as the runner reports them, so
# that a stale figure is found by running this (issue 21). Each block names the command it ran.
#   bash scripts/docs_numbers.sh             every shipped scenario, as shipped, then the variants below
#   bash scripts/docs_numbers.sh spool_payout  one of them
# Where the numbers are quoted: spool_payout in the README's quick start; the shipped scenarios' table
# (pillar_wrap's tension and deployed length, the "try" variants) and the camera dataset example in
# docs/runner.md; heavy_dive and its strain-rule variant in docs/model.md (How the tension winches work);
# pillar_wrap and pillar_wrap_dynamic with a slow winch (the snag) in docs/runner.md, "A dynamic vehicle" (the pose
# stream's pull at the vehicle also in docs/model.md, "A vehicle at an obstacle", and docs/limitations.md, "A
# pose-driven vehicle has no force limit");
# spool_payout without noise in docs/benchmarks.md ("Why twice a step: the noise").
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" >/dev/null
RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run"
OUT="$BUILD_DIR/docs_numbers"
names=("$@")
variants=()
if ((${#names[@]} == 0)); then
  for file in "$ROOT"/scenarios/*.yaml; do
    names+=("$(basename "$file" .yaml)")
  done
  # The runs the docs quote besides the shipped scenarios as they are: "file [--set ...]" each.
  variants=("paper_fig4_iterations --set iterations=1"
            "heavy_dive --set winch_mode=strain --set solver=pbd"
            "datasets/forward_camera_dive"
            "pillar_wrap --set max_winch_speed=0.3"
            "pillar_wrap_dynamic --set max_winch_speed=0.3"
            "spool_payout --set noise=0"
            "tms --set winch_speed=-0.3")
fi
run() {
  local name="$1" out="$2"
  shift 2
  echo "== rov_tether_run scenarios/$name.yaml --out $out${*:+ $*}"
  "$RUN" "$ROOT/scenarios/$name.yaml" --out "$out" "$@" |
    grep -E "^(simulated|deployed length|tension|max strain|newton|tether |warning|camera | {16}[0-9])" || true
  # Where the sub-steps short of solver_tolerance were (docs/runner.md): state.csv's rows that carry one.
  if [ -f "$out/state.csv" ]; then
    /usr/bin/python3 - "$out/state.csv" "$@" <<'PYTHON'
import csv, sys
tolerance = 1e-8
for arg in sys.argv[2:]:
    if arg.startswith("solver_tolerance="):
        tolerance = float(arg.split("=", 1)[1])
rows = [r for r in csv.DictReader(open(sys.argv[1])) if "newton_residual" in r and r["newton_residual"] != "nan"]
short = [r for r in rows if float(r["newton_residual"]) > tolerance]
if short:
    print("short of tolerance in the rows at " + ", ".join(
        "t = %s s (residual %s, %s iterations)" % (r["t"].rstrip("0").rstrip("."), r["newton_residual"], r["newton_max"])
        for r in short))
PYTHON
  fi
}
for name in "${names[@]}"; do
  run "$name" "$OUT/$name"
done
for ((i = 0; i < ${#variants[@]}; ++i)); do
  # shellcheck disable=SC2086  # a variant is a name and its --set arguments, split on purpose
  run ${variants[i]%% *} "$OUT/variant_$i" $(echo "${variants[i]}" | cut -s -d' ' -f2-)
done
if ((${#variants[@]} > 0)); then
  # docs/model.md, "A vehicle at an obstacle": pillar_wrap_dynamic written at every step (output_rate 200 Hz,
  # a copy of the scenario), its largest pulls at the vehicle, where the vehicle was and how fast it came.
  every="$OUT/pillar_wrap_dynamic_every_step"
  mkdir -p "$every"
  sed -e 's/^output_rate:.*/output_rate: 200.0/' -e "s|\.\./config/|$ROOT/config/|" \
    "$ROOT/scenarios/pillar_wrap_dynamic.yaml" >"$every/scenario.yaml"
  echo "== pillar_wrap_dynamic at every step: the largest pulls at the vehicle"
  "$RUN" "$every/scenario.yaml" --out "$every" >/dev/null
  /usr/bin/python3 - "$every/vehicle.csv" <<'PYTHON'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
pulls = [float(r["tether_tension"]) for r in rows]
for i in sorted(sorted(range(1, len(rows)), key=lambda i: -pulls[i])[:3]):
    r, before = rows[i], rows[i - 1]
    print("t %s s: pull %.0f N (%.0f N the step before); vehicle %.3f m from the pillar's axis, coming at %.2f m/s"
          % (r["t"], pulls[i], pulls[i - 1], math.hypot(float(r["x"]), float(r["y"])),
             math.hypot(float(before["u"]), float(before["v"]))))
PYTHON
fi
