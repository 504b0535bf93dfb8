#!/usr/bin/env bash
# Runs one rostest N times in a row and prints each run's result and its "[ measured ]" lines: how a flaky
# test is shown to be fixed (issue 26 asked for 10 runs of overload.test in each build).
#   scripts/repeat_rostest.sh test/ros/overload.test 10                      # the plain build
#   BUILD_DIR=$PWD/catkin_build_sanitize scripts/repeat_rostest.sh test/ros/overload.test 10
# The build must exist (scripts/test.sh or scripts/setup.sh makes it). The runs share one master of their own
# on port 11500 (rostest --reuse-master), so a rostest running elsewhere on the machine (port 22422) does
# not collide with them; REPEAT_PORT=N takes another port, for two of these at once. Under a sanitizer build
# the nodes run with ASAN_OPTIONS=detect_leaks=0, as in scripts/test.sh. Exit code: the number of failed runs.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
test_file="$(realpath "${1:?usage: scripts/repeat_rostest.sh TEST.test [N]}")"
runs="${2:-10}"
build="${BUILD_DIR:-$ROOT/catkin_build}"
export PATH="/usr/bin:/bin:$PATH"
set +u
source "$build/devel/setup.bash"
set -u
port="${REPEAT_PORT:-11500}"
ros_home="$build/ros_home_repeat"
[[ "$port" == 11500 ]] || ros_home="${ros_home}_$port"
export ROS_HOME="$ros_home" ROS_MASTER_URI="http://localhost:$port"
if [[ "$build" == *sanitize* ]]; then
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
fi
roscore -p "$port" >/dev/null 2>&1 &
master=$!
trap 'kill $master 2>/dev/null; wait $master 2>/dev/null' EXIT
sleep 5
failed=0
for i in $(seq 1 "$runs"); do
  rm -rf "$ROS_HOME/test_results"
  if output="$(timeout 600 rostest --reuse-master "$test_file" 2>&1)" && grep -q "RESULT: SUCCESS" <<<"$output"; then
    result=SUCCESS
  else
    result=FAIL
    failed=$((failed + 1))
  fi
  measured="$(grep -rhoa "\[ measured \][^&<]*" "$ROS_HOME/test_results" 2>/dev/null | head -20 | tr '\n' ' ')"
  echo "run $i: $result $measured"
done
echo "$((runs - failed)) of $runs runs passed"
exit "$failed"
