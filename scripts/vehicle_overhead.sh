#!/usr/bin/env bash
# What a dynamic vehicle end adds to a step of `direct` (issue 25: at most 10% at 100 segments), counted in
# instructions under valgrind's callgrind, so the machine's load does not move it:
#   scripts/vehicle_overhead.sh            (BENCH=path/to/rov_tether_bench to use a built binary as it is)
# Runs BM_StepDirectDynamicVehicle/SEGMENTS/{0,1}/{0,1,2} (bending off/on; vehicle end kinematic and pinned,
# dynamic, or kinematic along the dynamic vehicle's own path: the same cable and set-up) and prints, per case,
# the instructions of one step (the benchmark loop's calls of Tether::step(), inclusive, over their count), the
# ratios dynamic / pinned and dynamic / kinematic on the same path (which leaves out what the vehicle's motion
# costs the chain's solve, and is what the coupling itself costs), and what the coupling's own calls
# (VehicleCoupling::predict, inverseMass, finish) take per sub-step. WALL=1 adds one timed run (REPETITIONS, 15,
# repetitions interleaved at random, pinned to one core, --benchmark_min_time=0.2) and its CPU-time ratios, of
# the medians and of the minima, for the record: a loaded machine moves them, and they are higher than the
# instruction ratios (the chain's loops run as AVX2 clones, the body's 6x6 algebra as scalar code), and the
# coupling's calls alone in one sub-step (BM_VehicleCouplingSubStep) beside one whole body step.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/callgrind_bench.sh"
segments="${SEGMENTS:-100}"
for bending in 0 1; do
  for dynamic in 0 1 2; do
    callgrind_bench "BM_StepDirectDynamicVehicle/$segments/$bending/$dynamic" "$bending$dynamic"
  done
done
/usr/bin/python3 - "$work" "$segments" "$here" <<'PYTHON'
import sys
work, segments = sys.argv[1], sys.argv[2]
sys.path.insert(0, sys.argv[3])
from callgrind_tree import functions, per_step

def coupling(found):
    """Instructions per call of the coupling's three functions, summed (one call each per sub-step)."""
    total = 0.0
    for part in ("VehicleCoupling::predict(", "VehicleCoupling::inverseMass(", "VehicleCoupling::finish("):
        (inclusive, callers), = [v for k, v in found.items() if part in k]
        total += inclusive / sum(c for _, c in callers.values())
    return total

for bending in "01":
    kin, dyn, path = (functions("%s/%s%d.txt" % (work, bending, v)) for v in range(3))
    (k, k_calls), (d, d_calls), (p, p_calls) = (per_step(f, "BM_StepDirectDynamicVehicle") for f in (kin, dyn, path))
    print("BM_StepDirectDynamicVehicle/%s/%s/{0,1,2} (%s): instructions per step kinematic pinned %.0f, dynamic "
          "%.0f, kinematic on the dynamic's path %.0f (%d, %d, %d steps); dynamic / pinned = %.3f, dynamic / same "
          "path = %.3f; the coupling's calls %.0f per sub-step"
          % (segments, bending, "bending on" if bending == "1" else "bending off", k, d, p, k_calls, d_calls, p_calls, d / k, d / p,
             coupling(dyn)))
PYTHON
if [ "${WALL:-0}" = 1 ]; then
  # Pinned to one core where taskset exists (the benchmark is single-threaded; a migration costs it caches).
  pin=(); command -v taskset >/dev/null && pin=(taskset -c 0)
  "${pin[@]}" "$BENCH" --benchmark_filter="^BM_StepDirectDynamicVehicle/$segments/|^BM_VehicleBodyStep\$|^BM_VehicleCouplingSubStep\$" \
    --benchmark_min_time=0.2 --benchmark_repetitions="${REPETITIONS:-15}" --benchmark_enable_random_interleaving=true \
    --benchmark_format=json >"$work/wall.json" 2>/dev/null
  /usr/bin/python3 - "$work/wall.json" <<'PYTHON'
import json, statistics, sys
runs = [b for b in json.load(open(sys.argv[1]))["benchmarks"] if b.get("run_type") == "iteration"]
# A step's CPU time [us] per repetition: the vehicle benchmark's iterations are windows of steps (items: steps
# per second). The median says what a step costs; the minimum is what a repetition not slowed by the machine's
# other load costs, the steadier of the two on a shared machine.
times = {}
for b in runs:
    times.setdefault(b["run_name"], []).append(1e6 / b["items_per_second"] if "items_per_second" in b else b["cpu_time"])
n = len(next(iter(times.values())))
for name in sorted(k for k in times if k.endswith("/0")):
    dynamic, path = name[:-1] + "1", name[:-1] + "2"
    for label, pick in (("median", statistics.median), ("minimum", min)):
        k, d, p = pick(times[name]), pick(times[dynamic]), pick(times[path])
        print("%s,1,2: CPU time per step (%s of %d) kinematic pinned %.2f us, dynamic %.2f us, kinematic on the "
              "same path %.2f us; dynamic / pinned = %.3f, dynamic / same path = %.3f"
              % (name, label, n, k, d, p, d / k, d / p))
print("BM_VehicleBodyStep: one body step %.3f us CPU (median of %d)" % (statistics.median(times["BM_VehicleBodyStep"]), n))
print("BM_VehicleCouplingSubStep: the coupling's calls in one sub-step %.3f us CPU (median of %d)"
      % (statistics.median(times["BM_VehicleCouplingSubStep"]), n))
PYTHON
fi
