#!/usr/bin/env python3
"""rostest (test/ros/dynamic_vehicle.test): tether_node with a dynamic vehicle (vehicle_model dynamic, the
BlueROV2 Heavy) on a locked 10 m tether, 8 m out, driven by ~cmd_wrench under simulated time the test owns.

- A constant 40 N surge, away from the spool: the vehicle runs out the 2 m of slack and comes to rest on the
  taut tether (the taut stop of issue 25): the pull on it (~wrench) within 2% of 40 N and its speed (~odom)
  below 0.02 m/s over the last SETTLED seconds. Its pull is 40 N along the tether plus the vehicle's 1 N of
  net weight (13.5 kg against 0.0134 m^3 of fresh water) across it: |F| = sqrt(40^2 + 1^2) = 40.01 N, within
  the 2%. ~odom's twist is in the body frame (child_frame_id rov): surge u, the vehicle facing +x.
- A NaN command is refused (a warning on /rosout, counted in /diagnostics) and the thrust goes on.
- A solver change the dynamic vehicle cannot take is refused whole and rolled back (`dynparam get`), and a later
  change is taken.
- The commands stop: the last one holds the thrust for cmd_wrench_timeout (0.5 s of ROS time; the physics
  runs interpolation_delay 0.1 s behind, so to physics time last + 0.4 s), then the thrust is zero: the
  pull drops below 10% of 40 N, and the stretched tether pulls the vehicle back towards the spool.
"""
import math
import time
import sys
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from rosgraph_msgs.msg import Log

from rov_tether.msg import TetherState

NODE = "/tether_node"
TICK = 0.005  # [s] simulated time per /clock message, the node's physics period
THRUST = 40.0  # [N] surge
HOLD = 40.0  # [s] of simulated time with the command on: 2 m of slack at up to 0.49 m/s, then settling
SETTLED = 5.0  # [s] the last seconds of HOLD in which the vehicle must be at rest
TIMEOUT = 0.5  # [s] cmd_wrench_timeout (config/node.yaml)
DELAY = 0.1  # [s] interpolation_delay (config/node.yaml)
AFTER = 4.0  # [s] of simulated time watched after the last command


class DynamicVehicle(unittest.TestCase):
    def setUp(self):
        rospy.init_node("dynamic_vehicle_test")
        self.sim_time = 1000.0
        self.wrenches = []  # (physics time, |F|, F_x) of ~wrench
        self.odoms = []  # (physics time, x, speed, surge u)
        self.state_stamp = 0.0
        self.logs = []
        self.refused = -1
        self.clock_pub = rospy.Publisher("/clock", Clock, queue_size=10)
        self.command_pub = rospy.Publisher(NODE + "/cmd_wrench", WrenchStamped, queue_size=10)
        rospy.Subscriber(NODE + "/wrench", WrenchStamped, self.on_wrench, queue_size=1000)
        rospy.Subscriber(NODE + "/odom", Odometry, self.on_odom, queue_size=1000)
        rospy.Subscriber(NODE + "/state", TetherState, self.on_state, queue_size=1000)
        rospy.Subscriber("/rosout", Log, lambda m: self.logs.append(m.msg), queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=100)

    def on_wrench(self, msg):
        f = msg.wrench.force
        self.wrenches.append((msg.header.stamp.to_sec(), math.sqrt(f.x ** 2 + f.y ** 2 + f.z ** 2), f.x))

    def on_odom(self, msg):
        v = msg.twist.twist.linear
        self.odom_frames = (msg.header.frame_id, msg.child_frame_id)
        self.odoms.append((msg.header.stamp.to_sec(), msg.pose.pose.position.x,
                           math.sqrt(v.x ** 2 + v.y ** 2 + v.z ** 2), v.x))

    def on_state(self, msg):
        self.state_stamp = msg.header.stamp.to_sec()
        self.state_solver, self.state_drag = msg.solver, msg.drag

    def on_diagnostics(self, msg):
        for status in msg.status:
            values = {kv.key: kv.value for kv in status.values}
            if "cmd_wrench refused" in values:
                self.refused = int(values["cmd_wrench refused"])

    def command(self, force):
        msg = WrenchStamped()
        msg.header.stamp = rospy.Time.from_sec(self.sim_time)
        msg.header.frame_id = "rov"
        msg.wrench.force.x = force
        self.command_pub.publish(msg)
        self.last_command = self.sim_time

    def wait_for(self, done, timeout):
        end = time.time() + timeout
        while not done() and time.time() < end and not rospy.is_shutdown():
            time.sleep(0.01)
        return done()

    def drive(self, seconds, force=None):
        """Advances simulated time by `seconds` in TICKs, commanding `force` (None: nothing) every 10 ticks; the
        clock waits for the node whenever its ~state falls more than 0.5 s behind (as test_node.cpp's does)."""
        for k in range(int(round(seconds / TICK))):
            self.sim_time += TICK
            self.clock_pub.publish(Clock(clock=rospy.Time.from_sec(self.sim_time)))
            if force is not None and k % 10 == 0:
                self.command(force)
            time.sleep(0.0002)
            if k % 50 == 49:
                behind = self.sim_time - 0.5
                self.wait_for(lambda: self.state_stamp >= behind, 10.0)

    def test_taut_stop_timeout_and_refusal(self):
        # The node and the test's subscriptions connect; the clock starts.
        self.clock_pub.publish(Clock(clock=rospy.Time.from_sec(self.sim_time)))
        self.assertTrue(self.wait_for(lambda: self.command_pub.get_num_connections() > 0 and
                                      self.clock_pub.get_num_connections() > 0, 30.0), "the node subscribes")
        self.drive(1.0)
        self.assertTrue(self.wait_for(lambda: len(self.odoms) > 0, 10.0), "~odom comes")
        self.assertEqual(self.odom_frames, ("world", "rov"))

        start = self.sim_time
        self.drive(HOLD / 2, THRUST)
        nan = WrenchStamped()
        nan.header.stamp = rospy.Time.from_sec(self.sim_time)
        nan.wrench.force.x = float("nan")
        self.command_pub.publish(nan)
        self.drive(HOLD / 2, THRUST)
        last_command = self.last_command
        self.drive(AFTER)
        self.wait_for(lambda: self.state_stamp >= self.sim_time - 0.3, 10.0)

        settled = [w for w in self.wrenches if last_command - SETTLED <= w[0] <= last_command - DELAY]
        at_rest = [o for o in self.odoms if last_command - SETTLED <= o[0] <= last_command - DELAY]
        self.assertGreater(len(settled), 50)
        self.assertGreater(len(at_rest), 50)
        peak = max(w[1] for w in self.wrenches if w[0] >= start)
        pulls = [w[1] for w in settled]
        print("[ measured ] dynamic vehicle, 40 N on a locked 10 m tether: pull %.3f-%.3f N over the last %.0f s "
              "(peak %.1f N at the stop), speed at most %.4f m/s, x %.4f m" %
              (min(pulls), max(pulls), SETTLED, peak, max(o[2] for o in at_rest), at_rest[-1][1]), file=sys.stderr)
        for t, pull, fx in settled:
            self.assertLess(abs(pull - THRUST), 0.02 * THRUST, "pull at %.2f s" % t)
            self.assertLess(fx, 0.0, "towards the spool")
        for t, x, speed, u in at_rest:
            self.assertLess(speed, 0.02, "speed at %.2f s" % t)
        self.assertGreater(at_rest[-1][1], 9.9, "at the tether's length, 10 m from the spool")

        # The NaN: refused, warned, counted; the thrust went on (the pull stayed, checked above).
        self.assertTrue(any("non-finite" in m for m in self.logs), "a warning names the refused command")
        self.assertTrue(self.wait_for(lambda: self.refused >= 1, 10.0), "counted in /diagnostics")

        # The last command holds until the timeout, then the thrust is zero.
        held = [w for w in self.wrenches if last_command < w[0] <= last_command + TIMEOUT - DELAY - 0.1]
        self.assertGreater(len(held), 5)
        for t, pull, fx in held:
            self.assertLess(abs(pull - THRUST), 0.02 * THRUST, "held at %.2f s" % t)
        released = [w for w in self.wrenches if w[0] >= last_command + TIMEOUT - DELAY + 2.0]
        self.assertGreater(len(released), 10)
        for t, pull, fx in released:
            self.assertLess(pull, 0.1 * THRUST, "no thrust: the pull at %.2f s" % t)
        back = [o for o in self.odoms if o[0] >= last_command + TIMEOUT - DELAY + 2.0]
        print("[ measured ] after the commands stopped: pull at most %.3f N, x %.4f m (at rest %.4f m)" %
              (max(w[1] for w in released), back[-1][1], at_rest[-1][1]), file=sys.stderr)
        self.assertLess(back[-1][1], at_rest[-1][1], "drifts back towards the spool")
        self.assertTrue(any("stale" in m and "cmd_wrench" in m for m in self.logs), "the stale command is warned")

        # A solver the vehicle cannot be coupled into passes dynamic_reconfigure's own checks but the tether's
        # refuses it: refused whole, with an error, and what `dynparam get` and the parameter server show goes back
        # to direct, so that a later change is taken (the refused solver stuck there, and every later change, made
        # from it, was refused too).
        client = dynamic_reconfigure.client.Client(NODE, timeout=30)
        client.update_configuration({"solver": "pbd"})
        self.drive(0.5)
        self.assertTrue(self.wait_for(lambda: any("parameters refused whole" in m for m in self.logs), 10.0),
                        "the refusal is logged")
        self.assertTrue(self.wait_for(lambda: client.get_configuration(timeout=10)["solver"] == "direct", 10.0),
                        "dynparam get shows the solver that runs")
        self.assertEqual(rospy.get_param(NODE + "/solver"), "direct")
        client.update_configuration({"drag": 0.8})
        self.drive(0.5)
        self.assertTrue(self.wait_for(lambda: abs(self.state_drag - 0.8) < 1e-12, 10.0), "a later change is taken")
        self.assertEqual(self.state_solver, "direct")


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "dynamic_vehicle", DynamicVehicle)
