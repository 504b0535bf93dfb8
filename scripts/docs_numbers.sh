#!/usr/bin/env bash
# Prints the numbers the README and docs/ quote from the shipped scenarios, as the runner reports them, so
# that a stale figure is found by running this (issue 21). Each block names the command it ran.
#   bash scripts/docs_numbers.sh             every shipped scenario, as shipped
#   bash scripts/docs_numbers.sh spool_payout  one of them
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh" >/dev/null
RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run"
OUT="$BUILD_DIR/docs_numbers"
names=("$@")
if ((${#names[@]} == 0)); then
  for file in "$ROOT"/scenarios/*.yaml; do
    names+=("$(basename "$file" .yaml)")
  done
fi
for name in "${names[@]}"; do
  echo "== rov_tether_run scenarios/$name.yaml --out $OUT/$name"
  "$RUN" "$ROOT/scenarios/$name.yaml" --out "$OUT/$name" |
    grep -E "^(simulated|deployed length|tension|max strain|tether |warning)" || true
done
