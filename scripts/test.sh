#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, and runs
#   1. every gtest binary (no ROS master) and every rostest (the node with a master), the checks
#      test/check_*.py (no master; check_core_cmake.py builds the core with plain CMake in a scratch directory)
#      and the Python API's tests test/python (pytest);
#   2. the same again built with AddressSanitizer and UndefinedBehaviorSanitizer, in catkin_build_sanitize
#      (SANITIZERS=0 skips it);
#   3. each libFuzzer target (clang) for FUZZ_SECONDS seconds (default 60) on its corpus in test/fuzz
#      (FUZZ=0 skips it).
# Ends with the line "N passed, N failed": gtest and rostest cases of both builds, the checks and pytest
# cases (once), plus one case per fuzz target. Exit code 0 only when everything passed.
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
  # Each binary runs as four gtest shards per core (GTEST_TOTAL_SHARDS), one per core at a time, the next
  # starting as one ends: every case runs once, in one shard, and each shard writes its own JUnit file
  # (count_results.py sums them). Small shards keep both cores busy to the end, where one shard per core
  # left one core idle while the other ran the slow cases (a sanitized test_core: 5 min against 17).
  local cores shards
  cores="$(nproc)"
  shards=$((4 * cores))
  for binary in "$BUILD_DIR"/devel/lib/rov_tether/test_*; do
    name="$(basename "$binary")"
    stage "$name ($shards shards, $cores at a time)"
    # A shard that fails exits 1 through bash (never by a signal), so xargs still runs the others. gtest
    # exits 1 when a case failed, and its JUnit file says which; any other code (a sanitizer's abort before
    # the file is written, a leak reported after it) is written down as a failed case of its own, so the
    # count cannot read green.
    seq 0 $((shards - 1)) | xargs -P "$cores" -I{} bash -c '
      GTEST_TOTAL_SHARDS="$1" GTEST_SHARD_INDEX="$2" "$3" --gtest_output="xml:$4.shard$2.xml" --gtest_brief=1 && exit 0
      code=$?
      if [ "$code" != 1 ]; then
        printf "<testsuites><testsuite name=\"shards\"><testcase classname=\"%s\" name=\"shard%s_exit_code_%s\"><failure message=\"the shard exited with code %s\"/></testcase></testsuite></testsuites>\n" \
          "$(basename "$3")" "$2" "$code" "$code" >"$4.shard$2.exit.xml"
      fi
      exit 1' _ "$shards" {} "$binary" "$results/$name" || status=1
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
# parameters) and of the core's plain CMake build: no master, so once. JUnit XML through rosunit.
for check in "$ROOT"/test/check_*.py; do
  name="$(basename "$check" .py)"
  stage "$name"
  /usr/bin/python3 "$check" --gtest_output="xml:$RESULTS/plain/$name.xml" || status=1
done

# The Python API (import rov_tether: test/python, pytest) against the plain build, once; its JUnit file is
# counted with the rest. No cache directory is left in the tree (-p no:cacheprovider).
stage "pytest test/python"
(
  use_ros_environment
  ROV_TETHER_RUN="$BUILD_DIR/devel/lib/rov_tether/rov_tether_run" /usr/bin/python3 -m pytest -q -p no:cacheprovider \
    --junitxml="$RESULTS/plain/pytest.xml" "$ROOT/test/python"
) || status=1

if [ "$SANITIZERS" != 0 ]; then
  # ASan + UBSan: any error aborts the process (UBSan does not recover), so the case fails. Leaks are
  # reported for our gtest binaries; roscpp keeps process-lifetime singletons, so the ROS nodes run
  # without leak detection.
  BUILD_DIR="$ROOT/catkin_build_sanitize"
  mkdir -p "$BUILD_DIR"
  flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
  # Built at -O1 with line tables only (-g1: a report still names file and line), as the sanitizers' own
  # documentation advises: a third of the compile time of -O3 -g for a test file, and this build was the
  # suite's longest stage. The build type Sanitize keeps the physics libraries (core, mesh, camera) at -O3
  # (CMakeLists.txt), so the sanitized node keeps the pace its rostests expect; NDEBUG as in Release.
  # The benchmarks are not built here: they run no test, and sanitized timings mean nothing. Nor is the Python
  # module: Python would have to preload the sanitizer runtime to import it (test/python runs once, above).
  build_package -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" -DROV_TETHER_BENCHMARKS=OFF -DROV_TETHER_PYTHON=OFF
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
