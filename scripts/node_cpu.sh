#!/usr/bin/env bash
# Measures tether_node's CPU use end to end: the paper's cable (config/paper_cable.yaml: 100 segments,
# 10 iterations, bending on), physics at 200 Hz, a simulated ROV publishing poses at 20 Hz; first with a
# subscriber to ~markers (drawn at 30 Hz), then without. CPU is read from /proc/<pid>/stat (user + system
# time of the node process) over SECONDS_PER_RUN (default 30) after a 5 s warm-up.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
use_ros_environment
export ROS_MASTER_URI=http://localhost:11431
SECONDS_PER_RUN="${SECONDS_PER_RUN:-30}"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

roscore -p 11431 >/dev/null 2>&1 & pids+=($!)
until rostopic list >/dev/null 2>&1; do sleep 0.2; done
roslaunch rov_tether tether.launch overrides:="$ROOT/config/paper_cable.yaml" >/dev/null 2>&1 & pids+=($!)
rosrun rov_tether simulated_rov.py _rate:=20 \
  _waypoints:="[[0, 8.0, 0.0, -1.0], [10, 5.0, 6.0, -1.0], [20, 8.0, 0.0, -1.0]]" >/dev/null 2>&1 & pids+=($!)
until node_pid=$(pgrep -f "devel/lib/rov_tether/tether_node" | head -1) && [ -n "$node_pid" ]; do sleep 0.2; done
until rostopic echo -n 1 /tether_node/state >/dev/null 2>&1; do sleep 0.2; done

cpu_percent() {  # CPU of $node_pid over $1 seconds, in % of one core
  local ticks=$(getconf CLK_TCK)
  read -r -a a < <(cut -d' ' -f14,15 "/proc/$node_pid/stat")
  local t0=$(date +%s.%N)
  sleep "$1"
  read -r -a b < <(cut -d' ' -f14,15 "/proc/$node_pid/stat")
  local t1=$(date +%s.%N)
  echo "scale=2; 100 * (${b[0]} + ${b[1]} - ${a[0]} - ${a[1]}) / $ticks / ($t1 - $t0)" | bc
}

rostopic hz /tether_node/markers >/tmp/rov_tether_marker_hz.txt 2>&1 & marker_pid=$!; pids+=($marker_pid)
sleep 5
with_markers=$(cpu_percent "$SECONDS_PER_RUN")
kill "$marker_pid"; wait "$marker_pid" 2>/dev/null || true
marker_rate=$(grep -m1 "average rate" /tmp/rov_tether_marker_hz.txt | awk '{print $3}')
sleep 5
without_markers=$(cpu_percent "$SECONDS_PER_RUN")
segments=$(rostopic echo -n 1 /tether_node/state/segment_tension 2>/dev/null | tr ',' '\n' | grep -c '[0-9]' || true)
echo "tether_node, paper's cable ($segments segments, 10 iterations, bending on), physics 200 Hz, poses 20 Hz:"
echo "  with a ~markers subscriber (markers at ${marker_rate:-?} Hz): ${with_markers}% of one core"
echo "  without subscribers:                                ${without_markers}% of one core"
