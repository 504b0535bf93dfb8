#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the ROS demo: tether_node beside a simulated
# ROV that dives out 8 m, around and back (the spool pays out and reels in), with a live one-line
# summary. rviz opens when a display is there ($DISPLAY set and rviz installed, or RVIZ=true to install
# it); otherwise the demo runs headless. DURATION (s, default 55: one dive) ends it; 0 runs until Ctrl-C.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

DURATION="${DURATION:-55}"
RVIZ="${RVIZ:-auto}"
if [ "$RVIZ" = auto ]; then
  RVIZ=false
  [ -n "${DISPLAY:-}" ] && command -v rviz >/dev/null 2>&1 && RVIZ=true
fi
if [ "$RVIZ" = true ] && ! command -v rviz >/dev/null 2>&1; then
  PACKAGES=(rviz) install_missing
fi

use_ros_environment
# The colour scale as the demo's node draws it: config/demo.yaml over config/node.yaml.
setting() { sed -n "s/^$1: *\([0-9.]*\).*/\1/p" "$ROOT/config/demo.yaml" "$ROOT/config/node.yaml" | head -1; }
FULL_SCALE="$(setting tension_full_scale)"
STRIPES="$(setting stripe_segments)"
echo "== tether_node demo: rviz $RVIZ, ${DURATION}s (DURATION=0 runs until Ctrl-C)"
if [ "$RVIZ" = true ]; then
  echo "   rviz: fixed frame 'world'; the cable is the MarkerArray /tether_node/markers, coloured by tension"
  echo "   (light blue 0 N, cyan, green, yellow, red at ${FULL_SCALE} N and above; grey where it is compressed),"
  echo "   with lighter stripes every ${STRIPES} segments that travel as cable pays out; the legend above the"
  echo "   spool says the same."
else
  echo "   headless (no display). To see it: run on a desktop, or RVIZ=true bash scripts/demo.sh, and in rviz"
  echo "   add a MarkerArray on /tether_node/markers with fixed frame 'world' (or use config/tether.rviz)."
fi
echo "   Other outputs: rostopic echo /tether_node/state, /tether_node/wrench, /diagnostics;"
echo "   rosservice call /tether_node/get_tension \"{arc_length_from_vehicle: 0.0, segment: -1}\""
# roslaunch joins the master of ROS_MASTER_URI, or starts one there when none runs.
# The summary node is "required" when DURATION > 0: its end stops the demo. scripts/launch_filter.py keeps
# what the nodes say and drops roslaunch's own chatter (escapes, the SUMMARY block, start and shut-down
# lines, the summary node's end); a node that crashes still shows.
set +e
roslaunch rov_tether demo.launch rviz:="$RVIZ" summary_duration:="$DURATION" 2>&1 |
  /usr/bin/python3 "$ROOT/scripts/launch_filter.py" tether_summary
launch_status=${PIPESTATUS[0]}
set -e
echo "== demo finished (${DURATION}s, roslaunch exit code $launch_status); DURATION=0 keeps it running, RVIZ=true shows rviz"
exit "$launch_status"
