#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a bounded time on its corpus
# in test/fuzz/corpus/<target>, one per core at a time. New inputs go to a scratch corpus in catkin_build/fuzz unless
# --update-corpus merges them into the repository's (then commit them).
#
#   scripts/fuzz.sh [--seconds N] [--junit DIR] [--update-corpus] [target...]
#
# Targets: fuzz_scenario (scenario and parameter files), fuzz_params (parameters by name, any value),
# fuzz_poses (pose sequences, times, spool, winch, parameter changes and resets into the core).
# A crash leaves its input in catkin_build/fuzz/artifacts/ and fails the run.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="/usr/bin:/bin:$PATH"
SECONDS_EACH=60
JUNIT=""
UPDATE=0
TARGETS=()
while (($#)); do
  case "$1" in
    --seconds) SECONDS_EACH="$2"; shift 2 ;;
    --junit) JUNIT="$2"; shift 2 ;;
    --update-corpus) UPDATE=1; shift ;;
    -*) sed -n '2,12p' "$0"; exit 2 ;;
    *) TARGETS+=("$1"); shift ;;
  esac
done
((${#TARGETS[@]})) || TARGETS=(fuzz_scenario fuzz_params fuzz_poses)

missing=()
for p in clang libclang-rt-14-dev libyaml-cpp-dev libeigen3-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing from Debian: ${missing[*]}"
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

OUT="$ROOT/catkin_build/fuzz"
mkdir -p "$OUT/artifacts"
# The scenario code builds obstacles through makeObstacle (src/geometry, rov_tether_geometry), with the
# mesh module's code linked in (-rdynamic: makeObstacle finds its entry point in the program).
CORE=("$ROOT"/src/core/*.cpp "$ROOT"/src/geometry/*.cpp "$ROOT"/src/spec/*.cpp "$ROOT"/src/scenario/*.cpp)
FLAGS=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
  -I"$ROOT/include" -I/usr/include/eigen3)
# The libraries' sources are compiled once, one process per core, into objects every target links
# (-fsanitize=fuzzer on an object without LLVMFuzzerTestOneInput only instruments it).
OBJ="$OUT/obj"
rm -rf "$OBJ" && mkdir -p "$OBJ"
echo "== compiling ${#CORE[@]} library sources for the fuzz targets"
export OBJ ROOT
printf '%s\n' "${CORE[@]}" | xargs -P "$(nproc)" -I{} bash -c \
  'src="{}"; rel="${src#$ROOT/src/}"; obj="$OBJ/${rel//\//_}.o"; clang++ "$@" -c "$src" -o "$obj"' _ "${FLAGS[@]}"
OBJECTS=("$OBJ"/*.o)
for target in "${TARGETS[@]}"; do
  echo "== $target: building"
  clang++ "${FLAGS[@]}" "$ROOT/test/fuzz/$target.cpp" "${OBJECTS[@]}" -lyaml-cpp -llapacke -lfcl -lccd -lassimp -rdynamic \
    -o "$OUT/$target"
done
# Each fuzzer runs on one core: as many at a time as there are cores, each for SECONDS_EACH, its log and
# result into files of its own; read back in the targets' order below.
run_one() {
  local target="$1" corpus="$ROOT/test/fuzz/corpus/$1" scratch="$OUT/corpus_$1" start
  mkdir -p "$corpus" "$scratch"
  echo "== $target: ${SECONDS_EACH} s on $(find "$corpus" -type f | wc -l) corpus inputs"
  start=$(date +%s)
  if UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 "$OUT/$target" -max_total_time="$SECONDS_EACH" \
      -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$OUT/artifacts/$target-" -print_final_stats=1 \
      "$scratch" "$corpus" >"$OUT/$target.log" 2>&1; then
    echo "passed $(($(date +%s) - start))" >"$OUT/$target.result"
  else
    echo "FAILED $(($(date +%s) - start))" >"$OUT/$target.result"
  fi
}
export -f run_one
export OUT SECONDS_EACH
rm -f "$OUT"/*.result
printf '%s\n' "${TARGETS[@]}" | xargs -P "$(nproc)" -I{} bash -c 'run_one "$1"' _ {}
status=0
cases=""
for target in "${TARGETS[@]}"; do
  read -r result took <"$OUT/$target.result" || { result="FAILED"; took=0; }
  failure=""
  if [ "$result" != passed ]; then
    status=1
    failure="<failure message=\"crash, see $OUT/$target.log\"/>"
    tail -30 "$OUT/$target.log"
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb|cov:" "$OUT/$target.log" | tail -3 || true
  echo "== $target: $result ($took s)"
  cases+="<testcase classname=\"fuzz\" name=\"$target\" time=\"$took\">$failure</testcase>"
  if [ "$UPDATE" = 1 ]; then
    "$OUT/$target" -merge=1 "$ROOT/test/fuzz/corpus/$target" "$OUT/corpus_$target" >/dev/null 2>&1
  fi
done
if [ -n "$JUNIT" ]; then
  mkdir -p "$JUNIT"
  echo "<testsuite name=\"fuzz\">$cases</testsuite>" >"$JUNIT/fuzz.xml"
fi
exit $status
