#!/usr/bin/env python3
"""rostest (test/ros/rov_heading.test): simulated_rov.py turns at most ~max_yaw_rate, so the tether's
attachment point, attachment_offset behind the vehicle (config/demo.yaml: 0.3 m), never moves from one pose
to the next by more than the vehicle's motion allows:

    |attachment step| <= (v_max + |offset_xy| * yaw_rate_max) * dt + 1e-6 m

v_max is the fastest leg of the waypoints (a piecewise-linear path never moves faster), the second term
bounds the chord the offset sweeps when the heading turns by yaw_rate_max * dt, and 1e-6 m covers rounding
(poses are float64, stamps are whole nanoseconds). Checked on the demo's dive (deterministic, every 50 ms
and at jittered intervals, over two loops) and on the poses the running node publishes.
"""
import math
import os
import random
import signal
import subprocess
import sys
import time
import unittest

import rospkg
import rospy
import rostest
import yaml
from geometry_msgs.msg import PoseStamped
from rosgraph_msgs.msg import Clock

PACKAGE = rospkg.RosPack().get_path("rov_tether")
sys.path.insert(0, os.path.join(PACKAGE, "scripts"))
import simulated_rov  # noqa: E402  (scripts/ is not a Python package)

ROUNDING = 1e-6  # [m]
TIMEOUT = 30.0  # [s] for the node's first pose
LATE = 2.0  # [s] the test subscribes this long after it starts


def demo_offset():
    with open(os.path.join(PACKAGE, "config", "demo.yaml")) as f:
        return yaml.safe_load(f)["attachment_offset"]


def attachment(position, yaw, offset):
    """World position of the attachment: position + Rz(yaw) offset (the vehicle only yaws)."""
    c, s = math.cos(yaw), math.sin(yaw)
    return [position[0] + c * offset[0] - s * offset[1], position[1] + s * offset[0] + c * offset[1],
            position[2] + offset[2]]


def init_node():
    """This test's node, once (each case that needs one calls it)."""
    if not rospy.core.is_initialized():
        rospy.init_node("rov_heading_test")


class RovHeading(unittest.TestCase):
    def check_steps(self, times, poses, waypoints, max_yaw_rate, offset, label):
        """Every attachment step within its bound; returns the largest step over its bound (<= 1)."""
        v_max = simulated_rov.max_speed(waypoints)
        lever = math.hypot(offset[0], offset[1])
        worst = 0.0
        points = [attachment(p, yaw, offset) for p, yaw in poses]
        for k in range(1, len(points)):
            dt = times[k] - times[k - 1]
            bound = (v_max + lever * math.radians(max_yaw_rate)) * dt + ROUNDING
            step = math.dist(points[k], points[k - 1])
            self.assertLessEqual(step, bound, "%s: attachment moved %.4f m in %.3f s at t = %.2f s (bound %.4f m)"
                                 % (label, step, dt, times[k], bound))
            worst = max(worst, step / bound)
        print("[ measured ] %s: %d poses, largest attachment step %.0f%% of its bound (v_max %.3f m/s, "
              "lever %.2f m, %.0f deg/s)" % (label, len(points), 100 * worst, v_max, lever, max_yaw_rate),
              file=sys.stderr)
        return worst

    def test_1_demo_dive_moves_the_attachment_smoothly(self):
        offset = demo_offset()
        rng = random.Random(1)
        for label, steps in (("demo dive at 20 Hz", [0.05] * 2200),
                             ("demo dive, jittered 10-100 ms", [rng.uniform(0.01, 0.1) for _ in range(2000)])):
            dive = simulated_rov.Dive(simulated_rov.DIVE)
            times, poses, t = [], [], 0.0
            for dt in steps:
                times.append(t)
                poses.append(dive.pose(t))
                t += dt
            self.assertGreater(t, 2 * dive.period, "two loops, so the closing leg and the wrap are covered")
            self.check_steps(times, poses, dive.waypoints, simulated_rov.MAX_YAW_RATE, offset, label)

    def test_2_heading_still_follows_the_travel(self):
        # The limit delays a turn, it does not replace it: the 117 degree turn at 16 s takes 117/30 = 3.9 s,
        # so from 20 s on the vehicle faces along its leg (16 s -> 26 s: towards (-3.5, 7)).
        dive = simulated_rov.Dive(simulated_rov.DIVE)
        yaw = None
        for k in range(0, 25 * 20 + 1):
            _, yaw = dive.pose(k / 20)
        self.assertAlmostEqual(yaw, math.atan2(7.0, -3.5), delta=1e-9)

    def test_3_published_poses_move_the_attachment_smoothly(self):
        init_node()
        waypoints = rospy.get_param("/simulated_rov/waypoints")
        dive = simulated_rov.Dive(waypoints)  # the node's path with its closing leg, for v_max
        # The dive waits for a listener (~wait_for_listener): subscribed late, the first pose is still the
        # first waypoint's, exactly (a dive already under way would be LATE x 1 m/s = 2 m along its first leg).
        rospy.sleep(LATE)
        received = []
        rospy.Subscriber("/rov_pose", PoseStamped, received.append, queue_size=100)
        deadline = rospy.Time.now() + rospy.Duration(TIMEOUT)
        while not received and rospy.Time.now() < deadline:
            rospy.sleep(0.01)
        self.assertTrue(received, "no pose on /rov_pose within %.0f s" % TIMEOUT)
        first = received[0].pose.position
        self.assertEqual([first.x, first.y, first.z], waypoints[0][1:],
                         "the vehicle holds its first waypoint until someone listens")
        end = rospy.Time.now() + rospy.Duration(dive.period + 1.0)  # one whole loop and its wrap
        while not rospy.is_shutdown() and rospy.Time.now() < end:
            rospy.sleep(0.1)
        self.assertGreater(len(received), 20 * dive.period / 2, "poses at about 20 Hz")
        times = [m.header.stamp.to_sec() for m in received]
        poses = [([m.pose.position.x, m.pose.position.y, m.pose.position.z],
                  2 * math.atan2(m.pose.orientation.z, m.pose.orientation.w)) for m in received]
        self.check_steps(times, poses, dive.waypoints, simulated_rov.MAX_YAW_RATE, demo_offset(), "running node")

    def test_4_bad_parameters_are_refused_naming_them(self):
        # ~rate 0 crashed (ZeroDivisionError), NaN raised, -5 published as fast as it could; waypoints whose times do
        # not increase jumped the vehicle 7 m in one pose; a NaN one published NaN poses. Each is refused, naming it.
        script = os.path.join(PACKAGE, "scripts", "simulated_rov.py")
        for run_number, (argument, expected) in enumerate((
                ("_rate:=0", "~rate = 0: must be a finite number in [0.5, 1000] Hz"),
                ("_rate:=.nan", "~rate = nan: must be a finite number in [0.5, 1000] Hz"),
                ("_rate:=-5", "~rate = -5: must be a finite number in [0.5, 1000] Hz"),
                ("_waypoints:=[[0, 1.5, 0, -1], [10, 5, 0, -1], [5, 1.5, 6, -1]]",
                 "~waypoints[2]: its time 5 s must be after the one before, 10 s"),
                ("_waypoints:=[[0, 1.5, 0, -1], [10, .nan, 0, -1]]", "~waypoints[1] = [10, nan, 0, -1]: must be"))):
            # A name of its own each run: a run's private parameters stay on the master.
            run = subprocess.run([sys.executable, script, "__name:=bad_rov%d" % run_number, argument], stdin=subprocess.DEVNULL,
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT)
            self.assertEqual(run.returncode, 1, argument + ":\n" + run.stdout)
            self.assertIn(expected, run.stdout, argument)
            self.assertNotIn("Traceback", run.stdout, argument)

    def test_5_under_simulated_time_the_dive_starts_at_the_first_clock(self):
        # With ~wait_for_listener 0 the dive's clock started at ROS time 0, before the first /clock: a clock starting
        # at 1000 s put the first pose 1000 s along the looping dive (x 6.9, y 5.1: 9 m from the start), twice with
        # one stamp. It starts at the first clock now: the first pose is the first waypoint's, stamps never repeat.
        init_node()
        script = os.path.join(PACKAGE, "scripts", "simulated_rov.py")
        received = []
        sub = rospy.Subscriber("/clocked/pose", PoseStamped, received.append, queue_size=1000)
        clock = rospy.Publisher("/clock", Clock, queue_size=10)
        rospy.set_param("/use_sim_time", True)  # read by the script at its start; this test keeps the wall clock
        run = subprocess.Popen([sys.executable, script, "__name:=clocked_rov", "_wait_for_listener:=0",
                                "rov_pose:=/clocked/pose"], stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
        try:
            time.sleep(3.0)  # its start-up, with no clock: nothing may come
            self.assertEqual(received, [], "a pose before the first /clock")
            t, end = 1000.0, time.monotonic() + TIMEOUT
            while len(received) < 10 and time.monotonic() < end:
                clock.publish(Clock(clock=rospy.Time.from_sec(t)))
                t += 0.01
                time.sleep(0.005)
        finally:
            sub.unregister()
            rospy.delete_param("/use_sim_time")
            run.send_signal(signal.SIGINT)
            output, _ = run.communicate(timeout=TIMEOUT)
        self.assertGreaterEqual(len(received), 10, output)
        first = received[0].pose.position
        self.assertLess(math.dist([first.x, first.y, first.z], simulated_rov.DIVE[0][1:]), 0.1 * 0.5,
                        "the first pose within 0.1 s of the dive's start at its 0.5 m/s first leg")
        stamps = [m.header.stamp for m in received]
        self.assertEqual(len(stamps), len(set(stamps)), "a stamp twice")


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "rov_heading", RovHeading)
