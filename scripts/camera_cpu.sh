#!/usr/bin/env bash
# Measures tether_node's CPU use with a 1280 x 720 camera at 30 Hz (config/camera_720p.yaml: the paper's
# cable, 100 segments, 10 iterations, bending on, physics at 200 Hz; a simulated ROV publishing poses and
# tf at 20 Hz; the camera looks back along the tether from the vehicle). First with subscribers to the
# camera's ~hd/mask, ~hd/depth and ~hd/coverage, then without. CPU is read from /proc/<pid>/stat (user +
# system time of the node process) over SECONDS_PER_RUN (default 30) after a 5 s warm-up. OUTPUTS
# (default "mask depth coverage") chooses what is subscribed, e.g. OUTPUTS=coverage for the rendering alone.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
use_ros_environment
export ROS_MASTER_URI=http://localhost:11432
SECONDS_PER_RUN="${SECONDS_PER_RUN:-30}"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

roscore -p 11432 >/dev/null 2>&1 & pids+=($!)
until rostopic list >/dev/null 2>&1; do sleep 0.2; done
roslaunch rov_tether tether.launch overrides:="$ROOT/config/camera_720p.yaml" >/dev/null 2>&1 & pids+=($!)
# (the devel script by path: rosrun finds several simulated_rov.py copies under catkin_build/ and asks)
# The camera 0.3 m behind the vehicle's centre, looking back (yaw 180 degrees).
"$BUILD_DIR/devel/lib/rov_tether/simulated_rov.py" _rate:=20 _publish_tf:=true _camera_frame:=rov_camera_optical \
  _camera_pose:="[-0.3, 0.0, 0.0, 0.0, 0.0, 180.0]" \
  _waypoints:="[[0, 8.0, 0.0, -1.0], [10, 5.0, 6.0, -1.0], [20, 8.0, 0.0, -1.0]]" >/dev/null 2>&1 & pids+=($!)
# The pid from this master (other tether_node processes may run on the machine).
until node_pid=$(rosnode info /tether_node 2>/dev/null | awk '/^Pid:/ {print $2}') && [ -n "$node_pid" ]; do
  sleep 0.2
done
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

OUTPUTS="${OUTPUTS:-mask depth coverage}"
subs=()
rostopic echo /tether_node/hd/coverage/coverage >/tmp/rov_tether_camera_coverage.txt 2>&1 & subs+=($!)
for output in $OUTPUTS; do
  if [ "$output" != coverage ]; then
    rostopic hz "/tether_node/hd/$output" >"/tmp/rov_tether_camera_hz_$output.txt" 2>&1 & subs+=($!)
  fi
done
pids+=("${subs[@]}")
sleep 5
with_camera=$(cpu_percent "$SECONDS_PER_RUN")
for p in "${subs[@]}"; do kill "$p"; wait "$p" 2>/dev/null || true; done
rates=""
for output in $OUTPUTS; do
  if [ "$output" != coverage ]; then
    rates+="$output at $(grep "average rate" "/tmp/rov_tether_camera_hz_$output.txt" | tail -1 | awk '{print $3}' || true) Hz, "
  fi
done
coverage=$(grep -E '^[0-9]' /tmp/rov_tether_camera_coverage.txt | sort -g |
  awk '{a[NR]=$1} END {if (NR) printf "%s to %s", a[1], a[NR]}' || true)
sleep 5
without_camera=$(cpu_percent "$SECONDS_PER_RUN")
echo "tether_node, paper's cable (100 segments), physics 200 Hz, poses 20 Hz, a 1280x720 camera at 30 Hz:"
echo "  subscribed to ${OUTPUTS// /, } (${rates}coverage ${coverage:-?}): ${with_camera}% of one core"
echo "  without subscribers:                                 ${without_camera}% of one core"
