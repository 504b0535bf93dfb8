#!/usr/bin/env bash
# What the default bending stiffness costs a step of `direct` against the chain alone (issue 24: at most 2x),
# counted in instructions under valgrind's callgrind, so the machine's load does not move it:
#   scripts/bending_cost.sh            (BENCH=path/to/rov_tether_bench to use a built binary as it is)
# Runs BM_StepDirect/N and BM_StepDirectBending/N (SEGMENTS, "100 1000" by default) and prints the instructions
# of one step (the benchmark loop's calls of Tether::step(), inclusive, over their count), the ratio bending /
# chain, and the share of the bending step's instructions in its largest parts (the Newton iteration's
# assembly, block factorisation with the forward pass that goes along with it, substitution, residual and
# energy). WALL=1 adds one timed run (REPETITIONS, 9, repetitions interleaved at random, pinned to one core)
# and its CPU-time ratios, of the medians and of the minima: a loaded machine moves them, and time does not
# follow instructions one for one (the block factorisation is two chains of dependent divisions, one block row
# after the other in each).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/callgrind_bench.sh"
segments="${SEGMENTS:-100 1000}"
for n in $segments; do
  callgrind_bench "BM_StepDirect/$n" "chain$n"
  callgrind_bench "BM_StepDirectBending/$n" "bending$n"
done
/usr/bin/python3 - "$work" "$here" $segments <<'PYTHON'
import sys
work = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from callgrind_tree import functions, per_step

# Each part is every function whose name holds the pattern: the block solve's loops are compiled as clones
# (AVX-512, AVX2, baseline), and callgrind names each clone on its own.
# From 8 block rows on the factorisation and substitution are the twisted ones (factorTwisted, substituteTwisted);
# the first solve's forward pass goes along with factorTwisted (counted in it) and its backward pass is
# substituteTwistedBackward.
PARTS = (("assembly", ("PrimalNewton::assemble(",)), ("factorisation", ("factorBlocks<true", "factorTwisted<true")),
         ("substitution", ("substituteBlocks<true", "substituteTwisted<true", "substituteTwistedBackward<true")),
         ("residual", ("PrimalNewton::residual(",)), ("energy", ("PrimalNewton::energy(",)))
for n in sys.argv[3:]:
    chain, bending = functions("%s/chain%s.txt" % (work, n)), functions("%s/bending%s.txt" % (work, n))
    (c, c_calls), (b, b_calls) = per_step(chain, "BM_StepDirect("), per_step(bending, "BM_StepDirectBending(")
    step_total = sum(v[0] for k, v in bending.items() if k.endswith("rov_tether::Tether::step()"))
    shares = []
    for label, names in PARTS:
        found = [v[0] for k, v in bending.items() if any(name in k for name in names)]
        if found:
            shares.append("%s %.0f%%" % (label, 100.0 * sum(found) / step_total))
    print("BM_StepDirectBending/%s against BM_StepDirect/%s: instructions per step %.0f and %.0f (%d, %d steps); "
          "bending / chain = %.2f; of the bending step: %s" % (n, n, b, c, b_calls, c_calls, b / c, ", ".join(shares)))
PYTHON
if [ "${WALL:-0}" = 1 ]; then
  pin=(); command -v taskset >/dev/null && pin=(taskset -c 0)
  filter="$(printf '^BM_StepDirect/%s$|^BM_StepDirectBending/%s$|' $(for n in $segments; do echo "$n $n"; done))"
  "${pin[@]}" "$BENCH" --benchmark_filter="${filter%|}" --benchmark_min_time=0.2 \
    --benchmark_repetitions="${REPETITIONS:-9}" --benchmark_enable_random_interleaving=true \
    --benchmark_format=json >"$work/wall.json" 2>/dev/null
  /usr/bin/python3 - "$work/wall.json" $segments <<'PYTHON'
import json, statistics, sys
runs = [b for b in json.load(open(sys.argv[1]))["benchmarks"] if b.get("run_type") == "iteration"]
times = {}
for b in runs:
    times.setdefault(b["run_name"], []).append(b["cpu_time"])
for n in sys.argv[2:]:
    chain, bending = times["BM_StepDirect/%s" % n], times["BM_StepDirectBending/%s" % n]
    for label, pick in (("median", statistics.median), ("minimum", min)):
        print("BM_StepDirectBending/%s against BM_StepDirect/%s: CPU time per step (%s of %d) %.2f us and %.2f us; "
              "bending / chain = %.2f" % (n, n, label, len(chain), pick(bending), pick(chain),
                                          pick(bending) / pick(chain)))
PYTHON
fi
