#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every test binary and ends with the line
# "N passed, N failed" (gtest cases). Exit code 0 only when everything passed.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

echo "== building tests"
build_target tests

RESULTS="$BUILD_DIR/test_results/rov_tether"
rm -rf "$RESULTS" && mkdir -p "$RESULTS"
status=0
for binary in "$BUILD_DIR"/devel/lib/rov_tether/test_*; do
  name="$(basename "$binary")"
  echo "== $name"
  "$binary" --gtest_output="xml:$RESULTS/$name.xml" --gtest_brief=1 || status=1
done

/usr/bin/python3 "$ROOT/scripts/count_results.py" "$RESULTS" || status=1
exit $status
