# Sourced by scripts/vehicle_overhead.sh and scripts/sections_overhead.sh: the benchmark binary (BENCH, or built
# here), a scratch directory ($work, removed on exit) and callgrind_bench NAME KEY, which runs the one benchmark
# NAME under callgrind and leaves its caller tree (callgrind_annotate --tree=caller --inclusive=yes) in
# $work/KEY.txt for scripts/callgrind_tree.py.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ -z "${BENCH:-}" ]; then
  source "$here/setup.sh"
  build_target rov_tether_bench
  BENCH="$BUILD_DIR/devel/lib/rov_tether/rov_tether_bench"
fi
command -v valgrind >/dev/null || { echo "valgrind is missing (apt-get install valgrind)"; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

callgrind_bench() {
  local name="$1" key="$2"
  valgrind --tool=callgrind --callgrind-out-file="$work/$key.cg" "$BENCH" \
    --benchmark_filter="^$name\$" --benchmark_min_time=0.05 >"$work/$key.log" 2>&1 ||
    { cat "$work/$key.log"; exit 1; }
  callgrind_annotate --tree=caller --inclusive=yes --threshold=100 "$work/$key.cg" >"$work/$key.txt" 2>/dev/null
}
