#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs every gtest binary (no ROS master) and
# every rostest (the node with a master), and ends with the line "N passed, N failed" (gtest and rostest
# cases). Exit code 0 only when everything passed.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

echo "== building tests"
build_target tests

RESULTS="$BUILD_DIR/test_results/rov_tether"
rm -rf "$RESULTS" && mkdir -p "$RESULTS"
status=0
# test_* binaries need no ROS master; rostest_* ones are started by rostest below.
for binary in "$BUILD_DIR"/devel/lib/rov_tether/test_*; do
  name="$(basename "$binary")"
  echo "== $name"
  "$binary" --gtest_output="xml:$RESULTS/$name.xml" --gtest_brief=1 || status=1
done

# The node with a ROS master: rostest starts its own roscore on a free port.
use_ros_environment
for launch in "$ROOT"/test/ros/*.test; do
  echo "== rostest $(basename "$launch")"
  rostest --results-base-dir="$RESULTS/rostest" "$launch" >"$BUILD_DIR/rostest_$(basename "$launch").log" 2>&1 || {
    status=1
    tail -40 "$BUILD_DIR/rostest_$(basename "$launch").log"
  }
  grep -E "^\[rov_tether\.|RESULT|TESTS|FAILURES|ERRORS" "$BUILD_DIR/rostest_$(basename "$launch").log" || true
done

/usr/bin/python3 "$ROOT/scripts/count_results.py" "$RESULTS" || status=1
exit $status
