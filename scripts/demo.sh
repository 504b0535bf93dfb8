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
echo "== tether_node demo: rviz $RVIZ, ${DURATION}s (DURATION=0 runs until Ctrl-C)"
if [ "$RVIZ" = true ]; then
  echo "   rviz: fixed frame 'world'; the cable is the MarkerArray /tether_node/markers, coloured by tension"
  echo "   (blue 0 N -> red 50 N), with darker stripes every 5 segments that travel as cable pays out."
else
  echo "   headless (no display). To see it: run on a desktop, or RVIZ=true bash scripts/demo.sh, and in rviz"
  echo "   add a MarkerArray on /tether_node/markers with fixed frame 'world' (or use config/tether.rviz)."
fi
echo "   Other outputs: rostopic echo /tether_node/state, /tether_node/wrench, /diagnostics;"
echo "   rosservice call /tether_node/get_tension \"{arc_length_from_vehicle: 0.0, segment: -1}\""
# roslaunch joins the master of ROS_MASTER_URI, or starts one there when none runs.
# The summary node is "required" when DURATION > 0: its end stops the demo; roslaunch's shutdown chatter
# about it is filtered out.
set +e
roslaunch rov_tether demo.launch rviz:="$RVIZ" summary_duration:="$DURATION" 2>&1 |
  sed -u 's/\x1b\[[0-9;]*m//g' |
  grep --line-buffered -vE "^(\s*\*|SUMMARY|=+|PARAMETERS|NODES|  /|auto-starting|setting /|process\[|started roslaunch|ROS_MASTER_URI|started core service|core service|\]2;|logging to|Checking log|Press Ctrl-C|$)|REQUIRED process|has died|finished cleanly|log file:|Initiating shutdown|killing on exit|shutting down processing monitor|^done$"
launch_status=${PIPESTATUS[0]}
set -e
echo "== demo finished (${DURATION}s, roslaunch exit code $launch_status); DURATION=0 keeps it running, RVIZ=true shows rviz"
exit "$launch_status"
