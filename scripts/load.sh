#!/usr/bin/env bash
# Load and soak runs of tether_node (docs/reliability.md, "Load and soak"). Each run starts its own ROS master and
# node, drives it with rov_tether_load and prints what the node reports in /diagnostics (physics
# real-time factor, step time, physics load, iterations) and its resident memory.
#
#   scripts/load.sh [poses_1khz] [cable_10k] [eight_tethers] [soak]     (default: all four)
#
#   poses_1khz     the paper's cable, vehicle poses at 1 kHz, 30 s
#   cable_10k      1 km of cable at 0.1 m (10,000 segments, all deployed), poses at 50 Hz, 30 s
#   eight_tethers  8 tethers in one process (config/eight_tethers.yaml), 50 Hz poses each, 30 s
#   soak           30 min of simulated time at 10x (3 min of wall time): memory and step time over time
# SOAK_MINUTES (default 30) shortens the soak.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
build_target rov_tether_load
use_ros_environment
RUNS=("$@")
((${#RUNS[@]})) || RUNS=(poses_1khz cable_10k eight_tethers soak)
SOAK_MINUTES="${SOAK_MINUTES:-30}"
LOAD="$BUILD_DIR/devel/lib/rov_tether/rov_tether_load"
export ROS_MASTER_URI="http://localhost:11399"
LOGS="$BUILD_DIR/load"
mkdir -p "$LOGS"
echo "== $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"

roscore -p 11399 >"$LOGS/roscore.log" 2>&1 &
CORE=$!
cleanup() { kill "$CORE" 2>/dev/null || true; wait 2>/dev/null || true; }
trap cleanup EXIT
for _ in $(seq 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.1; done

# run NAME SIM_TIME LAUNCH_ARGS... -- DRIVER_ARGS...
run() {
  local name="$1" sim="$2"
  shift 2
  local launch=()
  while (($#)) && [ "$1" != "--" ]; do launch+=("$1"); shift; done
  shift
  rosparam set use_sim_time "$sim"
  rosparam delete /tether_node >/dev/null 2>&1 || true  # no parameter (say `tethers`) left from the last run
  roslaunch "${launch[@]}" >"$LOGS/$name.node.log" 2>&1 &
  local node=$!
  local pid=""
  for _ in $(seq 100); do
    pid="$(pgrep -f "rov_tether/tether_node" | head -1 || true)"
    [ -n "$pid" ] && rosnode list 2>/dev/null | grep -q tether_node && break
    sleep 0.1
  done
  echo "== $name"
  "$LOAD" --pid "$pid" "$@" | tee "$LOGS/$name.log"
  kill -TERM "$node" 2>/dev/null || true  # background jobs ignore SIGINT in scripts
  wait "$node" 2>/dev/null || true
  for _ in $(seq 100); do pgrep -f "rov_tether/tether_node" >/dev/null || break; sleep 0.1; done
}

for r in "${RUNS[@]}"; do
  case "$r" in
    poses_1khz)
      run poses_1khz false rov_tether tether.launch overrides:="$ROOT/config/paper_cable.yaml" -- \
        --rate 1000 --duration 30 --report 5 --start 3,0,-1 --radius 1 ;;
    cable_10k)
      run cable_10k false rov_tether tether.launch overrides:="$ROOT/config/load_1km.yaml" -- \
        --rate 50 --duration 30 --report 5 --start 700,0,-50 --radius 5 ;;
    eight_tethers)
      run eight_tethers false rov_tether tethers.launch -- --topics "$(printf 'rov%d/pose,' 0 1 2 3 4 5 6 7)" \
        --rate 50 --duration 30 --report 5 --spacing 4 --start 0,3,-1 --radius 1 ;;
    soak)
      run soak true rov_tether tether.launch overrides:="$ROOT/config/paper_cable.yaml" -- \
        --clock-speed 10 --rate 50 --duration $((SOAK_MINUTES * 60)) --report $((SOAK_MINUTES * 6)) \
        --start 3,0,-1 --radius 2 ;;
    *) echo "unknown run '$r'"; exit 2 ;;
  esac
done
