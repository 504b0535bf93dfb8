#!/usr/bin/env bash
# Installs what rov_tether needs from Debian's archive (only what is missing), then configures and
# builds the package in ./catkin_build. Sourced by every script in scripts/.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Not "build": rosrun ignores executables under <package>/build/, and the package is the repository root.
BUILD_DIR="${BUILD_DIR:-$ROOT/catkin_build}"
# The first python3 on PATH may not be Debian's (and then lacks catkin_pkg): ROS tools use /usr/bin.
export PATH="/usr/bin:/bin:$PATH"

PACKAGES=(build-essential cmake pkg-config catkin python3-catkin-pkg python3-empy libeigen3-dev libyaml-cpp-dev liblapacke-dev
          libgtest-dev libbenchmark-dev libfcl-dev libassimp-dev
          ros-core-dev libroscpp-dev ros-message-generation python3-genmsg python3-gencpp libstd-msgs-dev
          libstd-srvs-dev python3-std-srvs libgeometry-msgs-dev python3-geometry-msgs libvisualization-msgs-dev
          python3-visualization-msgs libdiagnostic-msgs-dev python3-diagnostic-msgs libdiagnostic-updater-dev
          libtf2-ros-dev libtf2-eigen-dev libtf2-msgs-dev libmessage-filters-dev libdynamic-reconfigure-config-init-mutex-dev
          python3-dynamic-reconfigure librostest-dev python3-rostest python3-rospy python3-roslaunch
          python3-rosbag librosbag-dev rosbash python3-rosnode python3-rostopic python3-rosservice
          python3-rosparam python3-tf2-ros bc
          libopencv-dev libpng-dev libsensor-msgs-dev python3-sensor-msgs libimage-transport-dev libcv-bridge-dev libroslib-dev
          libnav-msgs-dev ros-nav-msgs python3-nav-msgs libtopic-tools-dev
          pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
          ${PACKAGES_EXTRA:-})

install_missing() {
  local missing=()
  # shellcheck disable=SC2153  # PACKAGES may be overridden for one call: PACKAGES=(rviz) install_missing
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]} == 0)); then
    return
  fi
  echo "== installing from Debian: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build_package() {
  echo "== building in $BUILD_DIR"
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
    -DCATKIN_ENABLE_TESTING=ON "$@" >"$BUILD_DIR.cmake.log" 2>&1 || { cat "$BUILD_DIR.cmake.log"; return 1; }
  build_target all
}

# Builds one target; shows compiler diagnostics, and the whole log when the build fails.
build_target() {
  local log="$BUILD_DIR.build.log"
  if ! cmake --build "$BUILD_DIR" --target "$1" -j"$(nproc)" >"$log" 2>&1; then
    grep -E "error|Error" "$log" | head -40
    echo "build of '$1' failed; full log: $log"
    return 1
  fi
  grep -E "warning:" "$log" || true
}

# Enters the built workspace's ROS environment (roslaunch, rostest, rosrun find rov_tether).
use_ros_environment() {
  set +u
  # shellcheck disable=SC1091
  source "$BUILD_DIR/devel/setup.bash"
  set -u
  export ROS_HOME="${ROS_HOME:-$BUILD_DIR/ros_home}"
}

install_missing
mkdir -p "$BUILD_DIR"
build_package
