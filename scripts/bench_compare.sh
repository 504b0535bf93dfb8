#!/usr/bin/env bash
# Compares the step benchmark of another git revision with this tree's, in one run:
#   scripts/bench_compare.sh REV [benchmark regex]     (default regex: BM_StepPbd/100$)
# Builds REV's benchmark in a temporary worktree, then runs the two binaries alternately, five rounds
# each, and prints each one's median and the ratio now / REV. Alternating rounds share the machine's
# noise, so the ratio is what to read, not the absolute times.
# With INSTRUCTIONS=1 it also counts, under valgrind's callgrind, the instructions of the benchmark's
# set-up steps (the same steps in both builds, whatever the machine does): a noise-free ratio.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
rev="${1:?usage: scripts/bench_compare.sh REV [regex]}"
filter="${2:-BM_StepPbd/100\$}"
work="$(mktemp -d)"
trap 'git -C "$ROOT" worktree remove --force "$work/src" >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
git -C "$ROOT" worktree add -q --detach "$work/src" "$rev"
echo "== building $rev's benchmark"
cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=OFF >"$work/cmake.log" 2>&1 || { cat "$work/cmake.log"; exit 1; }
cmake --build "$work/build" --target rov_tether_bench -j"$(nproc)" >"$work/build.log" 2>&1 || { tail -30 "$work/build.log"; exit 1; }
build_target rov_tether_bench
old="$work/build/devel/lib/rov_tether/rov_tether_bench"
new="$BUILD_DIR/devel/lib/rov_tether/rov_tether_bench"
/usr/bin/python3 - "$rev" "$old" "$new" "$filter" <<'PYTHON'
import collections, json, statistics, subprocess, sys
rev, binaries, pattern = sys.argv[1], {"old": sys.argv[2], "new": sys.argv[3]}, sys.argv[4]
times = collections.defaultdict(list)
for _ in range(5):
    for which, binary in binaries.items():
        out = subprocess.run([binary, "--benchmark_filter=" + pattern, "--benchmark_min_time=0.3",
                              "--benchmark_format=json"], check=True, capture_output=True, text=True).stdout
        for b in json.loads(out)["benchmarks"]:
            times[(b["name"], which)].append(b["cpu_time"])
for name in sorted({n for n, _ in times}):
    if not times[(name, "old")] or not times[(name, "new")]:
        print("%s: only in %s" % (name, rev if times[(name, "old")] else "this tree"))
        continue
    old, new = statistics.median(times[(name, "old")]), statistics.median(times[(name, "new")])
    print("%s: %s %.3f us, now %.3f us (medians of 5 alternating rounds), now / %s = %.3f"
          % (name, rev, old, new, rev, new / old))
PYTHON
if [ "${INSTRUCTIONS:-0}" = 1 ]; then
  command -v valgrind >/dev/null || PACKAGES=(valgrind) install_missing
  for which in old new; do
    binary="$old"; [ "$which" = new ] && binary="$new"
    valgrind --tool=callgrind --callgrind-out-file="$work/$which.callgrind" "$binary" --benchmark_filter="$filter" \
      --benchmark_min_time=0.01 >/dev/null 2>&1
    # Instructions of every call of step() made by advanceTo() (the benchmark's fixed set-up), and the call count.
    callgrind_annotate --tree=caller --inclusive=yes "$work/$which.callgrind" 2>/dev/null |
      grep -B8 -E '^ *[0-9,]+ \([ 0-9.]+%\)  \*  .*::step\(\)' | grep -E '::advanceTo\(' | head -1 |
      sed -E 's/^ *([0-9,]+) .*\(([0-9,]+)x\).*/\1 \2/; s/,//g' >"$work/$which.count"
  done
  /usr/bin/python3 - "$rev" "$work/old.count" "$work/new.count" <<'PYTHON'
import sys
rev = sys.argv[1]
(old_i, old_n), (new_i, new_n) = (map(int, open(p).read().split()) for p in sys.argv[2:4])
print("instructions in the set-up steps (callgrind): %s %d, now %d (the same %d calls of advanceTo), now / %s = %.4f"
      % (rev, old_i, new_i, new_n, rev, new_i / old_i))
PYTHON
fi
