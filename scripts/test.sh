#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, and runs
#   1. every gtest binary (no ROS master) and every rostest (the node with a master), and the repository
#      checks test/check_*.py (no build, no master);
#   2. the same again built with AddressSanitizer and UndefinedBehaviorSanitizer, in catkin_build_sanitize
#      (SANITIZERS=0 skips it);
#   3. each libFuzzer target (clang) for FUZZ_SECONDS seconds (default 60) on its corpus in test/fuzz
#      (FUZZ=0 skips it).
# Ends with the line "N passed, N failed": gtest and rostest cases of both builds, plus one case per
# fuzz target. Exit code 0 only when everything passed.
set -euo pipefail
SANITIZERS="${SANITIZERS:-1}"
FUZZ="${FUZZ:-1}"
FUZZ_SECONDS="${FUZZ_SECONDS:-60}"
if [ "$FUZZ" != 0 ]; then
  PACKAGES_EXTRA="clang libclang-rt-14-dev"
fi
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
PLAIN_BUILD="$BUILD_DIR"
RESULTS="$PLAIN_BUILD/test_results/rov_tether"
rm -rf "$RESULTS" && mkdir -p "$RESULTS"
status=0

# A stage's heading, with the time since the suite started (where the suite's time goes: keep it under 60 min).
stage() {
  echo "== $* [$((SECONDS / 60)) min $((SECONDS % 60)) s]"
}

# Runs every gtest binary and rostest of the build in $BUILD_DIR; JUnit results go to $1.
run_suite() {
  local results="$1"
  mkdir -p "$results"
  stage "building tests in $BUILD_DIR"
  build_target tests
  # test_* binaries need no ROS master; rostest_* ones are started by rostest below.
  # Each binary runs as one gtest shard per core, the shards side by side (GTEST_TOTAL_SHARDS): every case
  # runs once, in one shard, and each shard writes its own JUnit file (count_results.py sums them).
  local shards
  shards="$(nproc)"
  for binary in "$BUILD_DIR"/devel/lib/rov_tether/test_*; do
    name="$(basename "$binary")"
    stage "$name ($shards shards)"
    local pids=()
    for ((shard = 0; shard < shards; shard++)); do
      GTEST_TOTAL_SHARDS="$shards" GTEST_SHARD_INDEX="$shard" \
        "$binary" --gtest_output="xml:$results/$name.shard$shard.xml" --gtest_brief=1 &
      pids+=("$!")
    done
    for pid in "${pids[@]}"; do
      wait "$pid" || status=1
    done
  done
  # The node with a ROS master: rostest starts its own roscore on a free port. A subshell, so each
  # build's workspace environment stays its own.
  (
    use_ros_environment
    if [ -n "${ASAN_OPTIONS_NODES:-}" ]; then
      export ASAN_OPTIONS="$ASAN_OPTIONS_NODES"
    fi
    failed=0
    for launch in "$ROOT"/test/ros/*.test; do
      log="$BUILD_DIR/rostest_$(basename "$launch").log"
      stage "rostest $(basename "$launch")"
      rostest --results-base-dir="$results/rostest" "$launch" >"$log" 2>&1 || {
        tail -40 "$log"
        failed=1  # the other rostests still run
      }
      grep -E "^\[rov_tether\.|RESULT|TESTS|FAILURES|ERRORS" "$log" || true
    done
    exit $failed
  ) || status=1
}

run_suite "$RESULTS/plain"

# Checks of the repository itself (every rostest registered, launch files clear their nodes'
# parameters): no build, no master, so once. JUnit XML through rosunit.
for check in "$ROOT"/test/check_*.py; do
  name="$(basename "$check" .py)"
  stage "$name"
  /usr/bin/python3 "$check" --gtest_output="xml:$RESULTS/plain/$name.xml" || status=1
done

if [ "$SANITIZERS" != 0 ]; then
  # ASan + UBSan: any error aborts the process (UBSan does not recover), so the case fails. Leaks are
  # reported for our gtest binaries; roscpp keeps process-lifetime singletons, so the ROS nodes run
  # without leak detection.
  BUILD_DIR="$ROOT/catkin_build_sanitize"
  mkdir -p "$BUILD_DIR"
  flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
  # The benchmarks are not built here: they run no test, and sanitized timings mean nothing.
  build_package -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" -DROV_TETHER_BENCHMARKS=OFF
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
  export ASAN_OPTIONS_NODES="detect_leaks=0:abort_on_error=1"
  stage "the same under AddressSanitizer + UndefinedBehaviorSanitizer"
  run_suite "$RESULTS/sanitizers"
  unset ASAN_OPTIONS ASAN_OPTIONS_NODES UBSAN_OPTIONS
  BUILD_DIR="$PLAIN_BUILD"
fi

if [ "$FUZZ" != 0 ]; then
  stage "fuzzing"
  "$ROOT/scripts/fuzz.sh" --seconds "$FUZZ_SECONDS" --junit "$RESULTS/fuzz" || status=1
fi

stage "counting"
/usr/bin/python3 "$ROOT/scripts/count_results.py" "$RESULTS" || status=1
exit $status
