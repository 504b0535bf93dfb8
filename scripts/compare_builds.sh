#!/usr/bin/env bash
# A scenario's cost on this build against another build's libraries, in one session: the runner of this build
# runs the scenario with its own libraries and with those of BASE (through LD_LIBRARY_PATH, which comes before
# the runner's RUNPATH), ROUNDS times each, alternating (pinned to one core where taskset exists), then once
# each under callgrind. Prints each run's CPU time, the medians, and the instructions (noise-free):
#   bash scripts/compare_builds.sh BASE_LIBDIR [SCENARIO] [ROUNDS]
# BASE_LIBDIR holds the other build's librov_tether_*.so (e.g. <its build>/devel/lib); SCENARIO defaults to
# scenarios/spool_payout.yaml, ROUNDS to 5. The libraries must be ABI-compatible with this runner (a change
# inside the core's sources, as when measuring one).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/setup.sh" >/dev/null
build_target rov_tether_run >/dev/null
base="$(cd "$1" && pwd)"
scenario="${2:-$ROOT/scenarios/spool_payout.yaml}"
rounds="${3:-5}"
RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
pin=()
command -v taskset >/dev/null && pin=(taskset -c 0)
paths() {  # the base's libraries (when given) before the environment's own paths
  local list="$1"
  if [ -n "${LD_LIBRARY_PATH:-}" ]; then
    list="${list:+$list:}$LD_LIBRARY_PATH"
  fi
  echo "$list"
}
cpu() {  # prints the runner's CPU seconds for one run ($1: base or this)
  local lib=""
  [ "$1" = base ] && lib="$base"
  local seconds
  seconds="$(LD_LIBRARY_PATH="$(paths "$lib")" "${pin[@]}" "$RUN" "$scenario" --out "$work/$1" |
    sed -n 's/^simulated .*steps, \([0-9.]*\) s CPU.*/\1/p')"
  [ -n "$seconds" ] || { echo "no 'simulated' line from $RUN on $scenario" >&2; exit 1; }
  echo "$seconds"
}
for ((i = 0; i < rounds; ++i)); do
  echo "base $(cpu base) s, this $(cpu this) s"
done | tee "$work/times.txt"
/usr/bin/python3 - "$work/times.txt" <<'PYTHON'
import statistics, sys
pairs = [line.split() for line in open(sys.argv[1])]
base = statistics.median(float(p[1]) for p in pairs)
this = statistics.median(float(p[4]) for p in pairs)
print("median CPU: base %.3f s, this build %.3f s; this / base = %.3f" % (base, this, this / base))
PYTHON
command -v valgrind >/dev/null || { echo "(valgrind is missing: no instruction counts)"; exit 0; }
for which in base this; do
  lib=""
  [ "$which" = base ] && lib="$base"
  LD_LIBRARY_PATH="$(paths "$lib")" valgrind --tool=callgrind --callgrind-out-file="$work/$which.cg" "$RUN" "$scenario" \
    --out "$work/$which" >/dev/null 2>"$work/$which.log"
  echo "$which: $(sed -n 's/.*I *refs: *//p' "$work/$which.log") instructions"
done
