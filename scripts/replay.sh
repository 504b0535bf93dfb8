#!/usr/bin/env bash
# Replays a recorded dive as `roslaunch rov_tether replay.launch ARGS` does, and exits with the replay's
# code: 0 when the bag was played into the node and poses were taken, 1 when the bag is missing or holds
# no poses, when no pose was taken, or a process failed (the output says which). roslaunch alone exits 0
# whatever its nodes do.
#   rosrun rov_tether replay.sh bag:=dive.bag pose_topic:=/mavros/local_position/pose output:=dive_tether.bag
set -u
result=$(mktemp "${TMPDIR:-/tmp}/rov_tether_replay.XXXXXX")
trap 'rm -f "$result"' EXIT
roslaunch rov_tether replay.launch result_file:="$result" "$@"
launch=$?
if [ "$launch" -ne 0 ]; then
  exit "$launch"  # roslaunch itself failed (a bad argument, no such file)
fi
code=$(head -n 1 "$result")
if [ -z "$code" ]; then
  echo "replay.sh: the player ended without a result (interrupted?)" >&2
  exit 1
fi
exit "$code"
