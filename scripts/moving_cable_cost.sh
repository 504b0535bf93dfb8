#!/usr/bin/env bash
# What a moving cable's step costs against a static one's (issue 24: at most 3x at N = 1000), in one run:
#   scripts/moving_cable_cost.sh [SEGMENTS...]      (default 100 1000; BENCH=path/to/rov_tether_bench to use a
#                                                    built binary as it is)
# Runs BM_StepDirectBending/N (the default EI, the end pinned) and BM_StepDirectBendingMoving/N/{0,1} (the end
# moving across the cable at 1 m/s with the winch locked; driving away at 0.5 m/s with a brake paying out), three
# repetitions each, and prints the CPU time of one step (medians), the ratio moving / static and the mean
# Newton iterations a sub-step.
set -euo pipefail
if [ -z "${BENCH:-}" ]; then
  source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
  build_target rov_tether_bench
  BENCH="$BUILD_DIR/devel/lib/rov_tether/rov_tether_bench"
fi
sizes="${*:-100 1000}"
filter="^BM_StepDirectBending(Moving)?/($(tr ' ' '|' <<<"$sizes"))(/[01])?\$"
"$BENCH" --benchmark_filter="$filter" --benchmark_min_time=0.3 --benchmark_repetitions=3 \
  --benchmark_format=json 2>/dev/null | /usr/bin/python3 -c '
import collections, json, statistics, sys
runs = collections.defaultdict(list)
for b in json.load(sys.stdin)["benchmarks"]:
    if b.get("run_type") != "iteration":
        continue
    if b.get("error_occurred"):
        sys.exit("%s: %s" % (b["run_name"], b.get("error_message", "failed")))
    # [us] of CPU a step: the static benchmark steps once an iteration, the moving one a window of steps.
    per_step = b["cpu_time"] / b.get("steps_per_iteration", 1.0)
    runs[b["run_name"]].append((per_step, b.get("newton_iterations", float("nan"))))
for size in sys.argv[1].split():
    static = statistics.median(t for t, _ in runs["BM_StepDirectBending/%s" % size])
    for case, what in (("0", "moving across, winch locked"), ("1", "driving away, brake paying out")):
        moving = runs["BM_StepDirectBendingMoving/%s/%s" % (size, case)]
        cost = statistics.median(t for t, _ in moving)
        print("N = %s, %s: %.1f us a step against %.1f us static, moving / static = %.2f; Newton %.2f a sub-step"
              % (size, what, cost, static, cost / static, statistics.median(n for _, n in moving)))
' "$sizes"
