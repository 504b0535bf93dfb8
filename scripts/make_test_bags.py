#!/usr/bin/env python3
"""Generates the recorded dives of test/data/ (vehicle poses on /rov_pose, geometry_msgs/PoseStamped, world
frame, z up, spool at the origin) with python3-rosbag. Deterministic: the same bags on every run.

usage: make_test_bags.py [OUT_DIR]   (default: test/data next to this script's package)
"""
import math
import os
import random
import sys

import rosbag
import rospy
from geometry_msgs.msg import PoseStamped
from simulated_rov import position_at as path  # piecewise-linear [x, y, z] along [t, x, y, z] waypoints

START = 1000.0  # [s] bag time of the first message; every bag starts here, so replays overlap in time
RATE = 20.0  # [Hz] pose rate


def pose(t, x, y, z, yaw):
    msg = PoseStamped()
    msg.header.stamp = rospy.Time.from_sec(START + t)
    msg.header.frame_id = "world"
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, z
    msg.pose.orientation.z = math.sin(yaw / 2)
    msg.pose.orientation.w = math.cos(yaw / 2)
    return msg


def write(out_dir, name, duration, position, description, nan_at=None):
    """position(t) -> (x, y, z); yaw follows the direction of travel."""
    with rosbag.Bag(os.path.join(out_dir, name + ".bag"), "w") as bag:
        yaw, previous = 0.0, None
        for k in range(int(duration * RATE) + 1):
            t = k / RATE
            x, y, z = position(t)
            if previous and math.hypot(x - previous[0], y - previous[1]) > 1e-3:
                yaw = math.atan2(y - previous[1], x - previous[0])
            previous = (x, y, z)
            msg = pose(t, x, y, z, yaw)
            if nan_at is not None and abs(t - nan_at) < 0.5 / RATE:
                msg.pose.position.x = float("nan")
            bag.write("/rov_pose", msg, msg.header.stamp)
    print("%-20s %5.0f s  %s" % (name, duration, description))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "test", "data")
    os.makedirs(out_dir, exist_ok=True)

    excursion = [[0, 1.5, 0, -1], [2, 1.5, 0, -1], [22, 7.5, 0, -2], [27, 7.5, 0, -2], [47, 1.5, 0, -1], [50, 1.5, 0, -1]]
    write(out_dir, "straight_excursion", 50, lambda t: path(excursion, t),
          "out 6 m at 0.3 m/s, hold, back")

    legs = [[0, 3.0, -3, -2]]
    t, x = 0.0, 3.0
    for leg in range(6):  # 6 m legs at 1.5 m/s, 1 m apart, in a 5 x 6 m box 3 m from the spool, so the
        # radial speed stays under max_winch_speed (1 m/s)
        y_end = 3.0 if leg % 2 == 0 else -3.0
        t += 4.0
        legs.append([t, x, y_end, -2])
        x += 1.0
        t += 0.7
        legs.append([t, x, y_end, -2])
    write(out_dir, "lawnmower", t, lambda s: path(legs, s), "fast lawn-mower survey, 1.5 m/s legs")

    rng = random.Random(7)
    jitter = [(rng.gauss(0, 0.03), rng.gauss(0, 0.03), rng.gauss(0, 0.02)) for _ in range(int(30 * RATE) + 1)]
    write(out_dir, "hover_jitter", 30,
          lambda t: (4.0 + 0.2 * math.sin(0.3 * t) + jitter[int(round(t * RATE))][0],
                     jitter[int(round(t * RATE))][1], -2.0 + jitter[int(round(t * RATE))][2]),
          "station keeping at 4 m with 3 cm jitter and a slow 0.2 m sway")

    def jumping(t):
        x, y, z = path([[0, 1.5, 0, -1], [15, 4.5, 0, -1.5], [30, 4.5, 3, -1.5]], t)
        return (x, y + 5.0, z) if t >= 15 else (x, y, z)  # a localisation reset moves it 5 m at t = 15 s

    write(out_dir, "pose_jump", 30, jumping, "dive with a 5 m pose jump at 15 s")
    write(out_dir, "nan_pose", 30, lambda t: path([[0, 1.5, 0, -1], [30, 6.0, 2.0, -2]], t),
          "slow dive with one NaN pose at 15 s", nan_at=15.0)


if __name__ == "__main__":
    main()
