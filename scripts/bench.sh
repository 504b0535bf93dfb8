#!/usr/bin/env bash
# Builds and runs the step benchmark (Google Benchmark); with --camera first, the camera renderer's
# (rov_tether_bench_camera). Extra arguments go to the benchmark binary.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
echo "== $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
# Three repetitions, medians reported: the machine is shared and single runs wander by 30%.
binary=rov_tether_bench
if [ "${1:-}" = "--camera" ]; then
  binary=rov_tether_bench_camera
  shift
fi
"$BUILD_DIR/devel/lib/rov_tether/$binary" --benchmark_min_time=0.5 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true "$@" | grep -v -E "_(mean|stddev|cv) "
