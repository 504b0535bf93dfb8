#!/usr/bin/env bash
# What sections and attachments add to a step of `direct` (issue 22: at most 10% at 100 segments), counted in
# instructions under valgrind's callgrind, so the machine's load does not move it:
#   scripts/sections_overhead.sh            (BENCH=path/to/rov_tether_bench to use a built binary as it is)
# Runs BM_StepDirectSections/SEGMENTS/{0,1,2}/{0,1} (the cable as it is; the same with an attachment of no
# mass, buoyancy or drag, which puts it on the per-segment material path with the same physics; a real cable
# of sections, floats and a water surface; under the paper's damping and under Morison) and prints the
# instructions of one step (the benchmark loop's calls of Tether::step(), inclusive, over their count) and the
# ratios to the cable as it is.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/callgrind_bench.sh"
segments="${SEGMENTS:-100}"
for drag in 0 1; do
  for kind in 0 1 2; do
    callgrind_bench "BM_StepDirectSections/$segments/$kind/$drag" "$kind$drag"
  done
done
/usr/bin/python3 - "$work" "$segments" "$here" <<'PYTHON'
import sys
work, segments = sys.argv[1], sys.argv[2]
sys.path.insert(0, sys.argv[3])
from callgrind_tree import functions, per_step

for drag, label in (("0", "the paper's damping"), ("1", "Morison")):
    (plain, _), (empty, _), (real, _) = (per_step(functions("%s/%d%s.txt" % (work, kind, drag)), "BM_StepDirectSections")
                                         for kind in range(3))
    print("BM_StepDirectSections/%s/{0,1,2}/%s (%s): instructions per step as it is %.0f, on the material path "
          "with the same physics %.0f, with sections, floats and a surface %.0f; material path / as it is = %.3f, "
          "sections / as it is = %.3f" % (segments, drag, label, plain, empty, real, empty / plain, real / plain))
PYTHON
