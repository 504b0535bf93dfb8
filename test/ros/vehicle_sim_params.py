#!/usr/bin/env python3
"""rostest (test/ros/vehicle_sim.test): scripts/vehicle_sim.py refuses bad private parameters and stops when told.

Each bad value is started as a user would start it (`vehicle_sim.py _rate:=abc`, against the test's master): the
simulator must exit with code 1 and a FATAL naming the parameter, the value it was given and the range. It took
`_rate:=abc` as a crash, a list `[1, 2]` as a TypeError traceback, `_mass:=inf` as a mass (and then stepped NaN),
and `_rate:=1e-6` as a step of 11 days, during which it slept through SIGTERM.

At the lowest rate it allows (0.5 Hz: a step of 2 s), SIGTERM right after a pose (the start of its 2 s sleep) ends
it before that step would have ended: its waits look for shutdown every 0.05 s (it slept out the whole step).

Under simulated time, /clock going back (a bag in a loop) restarts its clock there, and a leap far ahead is jumped
to, each with a warning: it slept until the clock came back to where it had been (no pose for as long), and it
stepped through a leap of any length, publishing every step's pose long after its time.
"""
import os
import signal
import subprocess
import sys
import threading
import time
import unittest

import rospkg
import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from rosgraph_msgs.msg import Clock

TIMEOUT = 20.0  # [s] rospy's start-up and the refusal; under 2 s on an idle machine
# The simulator's lowest rate [Hz]. After publishing the pose stamped t it sleeps until t + 1 / SLOW_RATE, the next
# step's time (scripts/vehicle_sim.py: sleep_until(t + h)), in ROS time, here the wall clock (no /clock).
SLOW_RATE = 0.5


class VehicleSimParams(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("vehicle_sim_params_test")
        cls.script = os.path.join(rospkg.RosPack().get_path("rov_tether"), "scripts", "vehicle_sim.py")

    def start(self, name, *arguments):
        return subprocess.Popen([sys.executable, self.script, "__name:=" + name] + list(arguments),
                                stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)

    def refused(self, argument, expected):
        """vehicle_sim.py with `argument` exits with code 1, its output holding `expected` with {ns} its private
        namespace (a node name of its own: what one run puts on the master stays there)."""
        self.runs = getattr(self, "runs", 0) + 1
        name = "bad%d" % self.runs
        expected = expected.format(ns="/" + name)
        run = self.start(name, argument)
        try:
            output, _ = run.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            run.kill()
            output, _ = run.communicate()
            self.fail("%s: still running after %.0f s (not refused):\n%s" % (argument, TIMEOUT, output))
        self.assertEqual(run.returncode, 1, argument + ":\n" + output)
        self.assertNotIn("Traceback", output, argument)
        self.assertIn(expected, output, argument)

    def test_1_bad_parameters_are_refused_naming_them(self):
        rate = "must be a finite number in [0.5, 1000] Hz"
        self.refused("_rate:=abc", "{ns}/rate = 'abc': " + rate)
        self.refused("_rate:=[1, 2]", "{ns}/rate = [1, 2]: " + rate)
        self.refused("_rate:=1.0e-6", "{ns}/rate = 1e-06: " + rate)
        self.refused("_rate:=.nan", "{ns}/rate = nan: " + rate)
        self.refused("_mass:=inf", "{ns}/mass = 'inf': must be a finite number > 0 kg")
        self.refused("_mass:=0", "{ns}/mass = 0: must be a finite number > 0 kg")
        self.refused("_added_mass:=[1, 2]", "{ns}/added_mass = [1, 2]: must be a list of 3 finite numbers, each >= 0 kg")
        self.refused("_linear_drag:=[1, -2, 3]", "{ns}/linear_drag = [1, -2, 3]: must be a list of 3 finite numbers")
        self.refused("_thrust:=[1, 2, .inf]", "{ns}/thrust = [1, 2, inf]: must be a list of 3 finite numbers")
        self.refused("_start:=[0, 0, 2000000.0]", "{ns}/start = [0, 0, 2000000.0]: must be a list of 3 finite numbers, "
                     "each within +-1e+06 m")
        self.refused("_slack_memory:=-1", "{ns}/slack_memory = -1: must be a finite number in [0, 3600] s")
        self.refused("_tether_force:=spring", "{ns}/tether_force = 'spring': must be one of coupling, wrench, none")
        self.refused("_world_frame:=3", "{ns}/world_frame = 3: must be a non-empty string")

    def test_2_a_number_written_as_text_on_the_command_line_is_taken(self):
        # `_rate:=1e3` is the string '1e3' to rospy (YAML 1.1): it is 1000 Hz, as roslaunch's <param> gives it.
        poses = []
        sub = rospy.Subscriber("/rov_pose", PoseStamped, poses.append, queue_size=10)
        run = self.start("text_rate", "_rate:=1e3", "_tether_force:=none")
        try:
            end = time.monotonic() + TIMEOUT
            while not poses and run.poll() is None and time.monotonic() < end:
                time.sleep(0.05)
            self.assertIsNone(run.poll(), run.stdout.read() if run.poll() is not None else "")
            self.assertTrue(poses, "no pose from vehicle_sim.py _rate:=1e3")
        finally:
            sub.unregister()
            run.send_signal(signal.SIGTERM)
            run.communicate(timeout=TIMEOUT)

    def test_3_sigterm_ends_it_promptly_at_its_lowest_rate(self):
        # The bound is the step it sleeps through, not a guess at how long rospy takes to shut down (0.7 s measured,
        # more on a loaded machine): a simulator that slept the step out cannot end before the next step's time, the
        # last pose's stamp + 1 / rate (2 s), however fast the machine; one that looks for shutdown every 0.05 s ends
        # after SIGTERM (sent 0.1 s after the pose came) plus its shutdown, well before it. Both times are ROS time,
        # the clock the simulator's stamps and sleeps keep.
        posed = threading.Event()
        stamps = []
        sub = rospy.Subscriber("/slow/pose", PoseStamped,
                               lambda m: (stamps.append(m.header.stamp.to_sec()), posed.set()), queue_size=10)
        run = self.start("slow", "_rate:=%g" % SLOW_RATE, "_tether_force:=none", "_pose_topic:=/slow/pose")
        try:
            self.assertTrue(posed.wait(TIMEOUT), "no pose from vehicle_sim.py _rate:=0.5")
            posed.clear()
            self.assertTrue(posed.wait(TIMEOUT), "no second pose")  # its sleep of a whole step begins now
            next_step = stamps[-1] + 1.0 / SLOW_RATE  # when the step it is sleeping through ends
            time.sleep(0.1)
            sent = rospy.Time.now().to_sec()
            run.send_signal(signal.SIGTERM)
            run.communicate(timeout=TIMEOUT)
            ended = rospy.Time.now().to_sec()
        finally:
            sub.unregister()
            if run.poll() is None:
                run.kill()
                run.communicate()
        print("[ measured ] vehicle_sim.py at %g Hz ended %.3f s after SIGTERM, %.3f s before its next step's time "
              "(bound: before it)" % (SLOW_RATE, ended - sent, next_step - ended))
        self.assertLess(ended, next_step, "it slept out the step it was in")

    def test_4_the_clock_going_back_restarts_it_and_a_leap_ahead_is_jumped_to(self):
        stamps = []
        sub = rospy.Subscriber("/jump/pose", PoseStamped, lambda m: stamps.append(m.header.stamp.to_sec()),
                               queue_size=1000)
        clock = rospy.Publisher("/clock", Clock, queue_size=10)
        rospy.set_param("/use_sim_time", True)  # read by the simulator at its start; this test keeps the wall clock
        run = self.start("jump", "_rate:=100", "_tether_force:=none", "_pose_topic:=/jump/pose")

        def tick(start, seconds):
            """/clock from `start` for `seconds` of simulated time in 0.01 s ticks, at about ten times real time."""
            t = start
            while t <= start + seconds + 1e-9:
                clock.publish(Clock(clock=rospy.Time.from_sec(t)))
                t += 0.01
                time.sleep(0.001)

        def came(ok):
            """A pose whose stamp ok() takes comes within TIMEOUT of wall time while the clock stands."""
            end = time.monotonic() + TIMEOUT
            while not any(ok(t) for t in stamps) and time.monotonic() < end:
                time.sleep(0.05)
            return any(ok(t) for t in stamps)

        failure = None
        try:
            end, start = time.monotonic() + TIMEOUT, 1000.0
            while not stamps and time.monotonic() < end:  # until the simulator hears the clock
                tick(start, 0.05)
                start += 0.06
            self.assertTrue(stamps, "no pose under /clock")
            tick(start, 1.0)
            self.assertTrue(came(lambda t: t >= start + 0.9), "no pose near %.1f s: %s" % (start + 1.0, stamps[-3:]))
            tick(500.0, 1.0)  # back by 500 s, as a bag played in a loop starts again
            self.assertTrue(came(lambda t: 500.0 <= t <= 501.0), "no pose after the clock went back to 500 s")
            before = len(stamps)
            tick(2000.0, 0.5)  # 1499 s ahead
            self.assertTrue(came(lambda t: t >= 2000.0), "no pose after the clock leapt to 2000 s")
            stepped = [t for t in stamps[before:] if 501.5 < t < 2000.0]
            self.assertFalse(stepped, "%d poses stamped between the clock's 501 and 2000 s: stepped through the leap"
                             % len(stepped))
        except AssertionError as error:
            failure = error
        finally:
            sub.unregister()
            rospy.delete_param("/use_sim_time")
            run.send_signal(signal.SIGTERM)
            output, _ = run.communicate(timeout=TIMEOUT)
        if failure is not None:
            self.fail("%s\nvehicle_sim.py said:\n%s" % (failure, output))
        self.assertIn("ROS time went back from 100", output)
        self.assertEqual(output.count("ROS time went back"), 1, output)
        self.assertIn("ROS time leapt 14", output)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "vehicle_sim_params", VehicleSimParams, sys.argv)
