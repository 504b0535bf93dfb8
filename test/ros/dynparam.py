#!/usr/bin/env python3
"""rostest (test/ros/dynparam.test): the README's command for live changes works as written.

`rosrun dynamic_reconfigure dynparam set /tether_node iterations 3` must exit 0, and the node must then
simulate with 3 iterations (~state), store 3 on the parameter server, and report it to `dynparam get`.
Debian ships no rqt_reconfigure, so this is the documented way to change parameters live.
"""
import ast
import subprocess
import time
import unittest

import rospkg
import rospy
import rostest
import yaml

from rov_tether.msg import TetherState

NODE = "/tether_node"
ITERATIONS = 3  # the README's example; default.yaml has 10
TIMEOUT = 30.0  # [s] for the node to come up and for a change to show; about 1 s on an idle machine


class Dynparam(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("dynparam_test")
        path = rospkg.RosPack().get_path("rov_tether") + "/config/default.yaml"
        with open(path) as f:
            cls.default_iterations = yaml.safe_load(f)["iterations"]

    def test_dynparam_set_changes_the_iterations(self):
        state = rospy.wait_for_message(NODE + "/state", TetherState, timeout=TIMEOUT)
        self.assertEqual(state.iterations, self.default_iterations)
        self.assertNotEqual(self.default_iterations, ITERATIONS, "the change must be visible")

        command = ["rosrun", "dynamic_reconfigure", "dynparam", "set", NODE, "iterations", str(ITERATIONS)]
        done = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)

        # The physics swaps the new set in between steps; ~state is published at 30 Hz (node.yaml).
        end = time.monotonic() + TIMEOUT
        while state.iterations != ITERATIONS and time.monotonic() < end:
            state = rospy.wait_for_message(NODE + "/state", TetherState, timeout=TIMEOUT)
        self.assertEqual(state.iterations, ITERATIONS)
        self.assertEqual(rospy.get_param(NODE + "/iterations"), ITERATIONS)

        got = subprocess.run(["rosrun", "dynamic_reconfigure", "dynparam", "get", NODE], capture_output=True,
                             text=True, timeout=TIMEOUT)
        self.assertEqual(got.returncode, 0, got.stdout + got.stderr)
        self.assertEqual(ast.literal_eval(got.stdout.strip())["iterations"], ITERATIONS)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "dynparam", Dynparam)
