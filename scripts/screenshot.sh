#!/usr/bin/env bash
# Takes the README's rviz screenshot: the ROS demo (tether_node + simulated ROV + rviz with
# config/tether.rviz) on a virtual display (Xvfb), captured AT seconds (default 20) into the dive. LAUNCH
# picks another demo: LAUNCH=pillar_demo.launch OUT=docs/images/pillar_demo.png AT=44 scripts/screenshot.sh
set -euo pipefail
PACKAGES_EXTRA="rviz xvfb xauth x11-apps imagemagick libgl1-mesa-dri"
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
use_ros_environment
export ROS_MASTER_URI=http://localhost:11441
OUT="${OUT:-$ROOT/docs/rviz_demo.png}"
AT="${AT:-20}"
LAUNCH="${LAUNCH:-demo.launch}"
export OUT AT LAUNCH
xvfb-run -a -s "-screen 0 1280x720x24" bash -c '
  roslaunch --port 11441 rov_tether "$LAUNCH" rviz:=true summary:=false >/dev/null 2>&1 & launch=$!
  sleep "$AT"  # the moment of the dive to show, not a synchronisation
  xwd -root -silent | convert xwd:- -crop 1280x720+0+0 "png:$OUT"
  kill -INT "$launch"; wait "$launch" || true'
echo "wrote $OUT"
