#!/usr/bin/env bash
# Prints the numbers the README and docs/ quote from the shipped scenarios, as the runner reports them, so
# that a stale figure is found by running this (issue 21). Each block names the command it ran.
#   bash scripts/docs_numbers.sh             every shipped scenario, as shipped, then the variants below
#   bash scripts/docs_numbers.sh spool_payout  one of them
# Where the numbers are quoted: spool_payout in the README's quick start; the shipped scenarios' table
# (pillar_wrap's tension and deployed length, the "try" variants) and the camera dataset example in
# docs/runner.md; heavy_dive and its strain-rule variant in docs/model.md (How the tension winches work);
# pillar_wrap and pillar_wrap_dynamic with a slow winch (the snag) in docs/runner.md, "A dynamic vehicle".
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
            "pillar_wrap_dynamic --set max_winch_speed=0.3")
fi
run() {
  local name="$1" out="$2"
  shift 2
  echo "== rov_tether_run scenarios/$name.yaml --out $out${*:+ $*}"
  "$RUN" "$ROOT/scenarios/$name.yaml" --out "$out" "$@" |
    grep -E "^(simulated|deployed length|tension|max strain|tether |warning|camera )" || true
}
for name in "${names[@]}"; do
  run "$name" "$OUT/$name"
done
for ((i = 0; i < ${#variants[@]}; ++i)); do
  # shellcheck disable=SC2086  # a variant is a name and its --set arguments, split on purpose
  run ${variants[i]%% *} "$OUT/variant_$i" $(echo "${variants[i]}" | cut -s -d' ' -f2-)
done
