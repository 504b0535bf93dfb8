#!/usr/bin/env python3
"""rostest (test/ros/external_coupling.test): issue 25's external-coupling experiment. A vehicle of
m = 13.5 + 6.4 kg with drag 13.7 v + 141 v|v| thrusts F = 40 N straight away from the spool on a locked 10 m
tether deployed at the distance, the vehicle 0.4 mm beyond it (taut at start at 4 N, a tenth of the thrust:
a tether at no tension is slack to the linearisation, K zero, and the node would say it came taut only
interpolation_delay later; docs/node.md, "External vehicle simulators"), simulated by scripts/vehicle_sim.py
applying the node's ~coupling implicitly; at simulator rates 50 and 200 Hz, against nodes with interpolation_delay 0
and 0.1 s (four runs at once). Each run must:

- never pull harder than the elastic-impact bound. From the moment the tether is taut (the pull first reaches
  5% of F) with the vehicle at speed v, energy: the spring's 1/2 P^2 / k at the peak pull P is at most the
  vehicle's 1/2 m v^2 plus the thrust's work F P / k (drag and the cable's damping only take energy out; the
  stretch to P is at least P / k, k = EA / L the straight cable's stiffness), so P <= F + sqrt(F^2 + k m v^2).
  (The issue writes F + v sqrt(k m), the limit for v sqrt(k m) >> F; started taut, v is about 0 and the
  bound is the step load's 2 F.)
- behave as the same vehicle coupled inside the step (the issue's reference, the node's own dynamic vehicle):
  test/ros/external_coupling_reference.yaml, run by rov_tether_run before the experiment. Its peak pull P_ref
  and its settling time T_ref (from coming taut until the pull stays within 2% of F and the vehicle below
  0.02 m/s) are measured, not assumed. Each run's peak is at most 1.2 P_ref (the issue's 20%), and from
  T_ref + 5 s after it came taut (the issue's margin) until the end, WINDOW later, its pull is within 2% of F
  and its vehicle slower than 0.02 m/s. (The closed form says how long the reference could take at most: the
  vehicle on the tether's spring k with its linear drag c = 13.7 N s/m rings at sqrt(k / m) = 22 rad/s,
  its envelope decaying as exp(-c t / 2 m), time constant 2.9 s: within 2% of F after
  ln(sqrt(F^2 + k m v^2) / 0.02 F) 2 m / c, 11.4 s from rest. The cable's own damping makes it faster.)
- publish ~coupling once per physics step (stamps 5 ms apart).

Simulated time, advanced by this test in steps of 5 ms once every simulator has stepped to the clock and
every node's ~coupling is within 0.2 s of where its interpolation_delay puts it: the processes keep up
with the clock whatever the machine's load, so the run measures the coupling, not the scheduler.
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import roslib.packages
import rospkg
import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from rosgraph_msgs.msg import Clock

from rov_tether.msg import TetherCoupling

THRUST = 40.0               # [N] along +x, away from the spool
MASS = 13.5 + 6.4           # [kg] with added mass
LINEAR_DRAG = 13.7          # [N s/m]
STIFFNESS = 1.0e5 / 10.0    # [N/m] EA / deployed length
TIME_STEP = 0.005           # [s] the nodes' physics step (config/default.yaml)
CLOCK_STEP = 0.005          # [s] the test's clock increments
TAUT_PULL = 0.05 * THRUST   # [N] the tether counts as taut from this pull on
MARGIN = 5.0                # [s] the margin on the reference's settling time
PEAK_MARGIN = 1.2           # the issue's: a run's peak pull at most 20% above the reference's
SETTLED_PULL = 0.02 * THRUST  # [N] settled: the pull within 2% of the thrust ...
SETTLED_SPEED = 0.02        # [m/s] ... and the vehicle slower than this
WINDOW = 3.0                # [s] watched after the settling time
NODE_SLACK = 0.2            # [s] a node's ~coupling may lag the clock by this beyond its interpolation_delay
RUNS = {"d0/v50": (0.0, 50.0), "d0/v200": (0.0, 200.0), "d100/v50": (0.1, 50.0), "d100/v200": (0.1, 200.0)}


def settling(samples, taut):
    """[s] from `taut` until the samples [(t, |pull - F|, |v|)] stay settled; inf if the last one is not."""
    unsettled = [t for t, pull_error, speed in samples if pull_error > SETTLED_PULL or speed >= SETTLED_SPEED]
    if not unsettled:
        return 0.0
    later = [t for t, _, _ in samples if t > unsettled[-1]]
    return later[0] - taut if later else math.inf


def lag_summary(lags):
    """How far a node's ~coupling was behind the clock beyond its delay, as the clock moved on [s]."""
    if not lags:
        return "none"
    ordered = sorted(lags)
    return "median %.3f s, 99%% %.3f s, max %.3f s" % (ordered[len(ordered) // 2], ordered[int(0.99 * len(ordered))],
                                                       ordered[-1])


def reference():
    """(P_ref [N], T_ref [s]): the peak pull and the settling time of the same vehicle coupled inside the step,
    from rov_tether_run on test/ros/external_coupling_reference.yaml (its vehicle.csv, one row per step)."""
    runner = roslib.packages.find_node("rov_tether", "rov_tether_run")[0]
    scenario = os.path.join(rospkg.RosPack().get_path("rov_tether"), "test", "ros", "external_coupling_reference.yaml")
    out = tempfile.mkdtemp(prefix="external_coupling_reference_")
    try:
        subprocess.run([runner, scenario, "--out", out], check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "vehicle.csv")) as f:
            rows = [(float(r["t"]), float(r["tether_tension"]), float(r["u"])) for r in csv.DictReader(f)]
    finally:
        shutil.rmtree(out)
    taut = next(t for t, pull, _ in rows if pull >= TAUT_PULL)
    peak = max(pull for _, pull, _ in rows)
    settled = settling([(t, abs(pull - THRUST), abs(u)) for t, pull, u in rows], taut)
    print("[ measured ] reference (coupled in the step): taut at %.3f s, peak pull %.1f N, settled %.2f s after"
          % (taut, peak, settled), file=sys.stderr)
    return peak, settled


def impact_bound(v_impact):
    """[N] the largest pull after coming taut at v_impact (see the module's docstring)."""
    return THRUST + math.sqrt(THRUST ** 2 + STIFFNESS * MASS * v_impact ** 2)


class Run:
    """What one simulator and its tether did: poses (t, x) and couplings (t, |F0|)."""

    def __init__(self, name, delay, rate):
        self.name, self.delay, self.period = name, delay, 1.0 / rate
        self.poses, self.pulls = [], []
        self.stiffness = math.nan
        self.lags = []  # [s] how far its ~coupling was behind the clock, beyond its delay, as the clock moved on
        self.lock = threading.Lock()
        self.pose_sub = rospy.Subscriber("/%s/pose" % name, PoseStamped, self.on_pose, queue_size=1000,
                                         tcp_nodelay=True)
        self.coupling_sub = rospy.Subscriber("/%s/coupling" % name, TetherCoupling, self.on_coupling,
                                             queue_size=1000, tcp_nodelay=True)

    def on_pose(self, msg):
        with self.lock:
            self.poses.append((msg.header.stamp.to_sec(), msg.pose.position.x))

    def on_coupling(self, msg):
        f = msg.force
        with self.lock:
            self.pulls.append((msg.header.stamp.to_sec(), math.sqrt(f.x * f.x + f.y * f.y + f.z * f.z)))
            self.stiffness = msg.stiffness[0]  # [N/m] K along the tether (x): reported

    def caught_up(self, clock):
        """The simulator stepped to the clock, and the node's ~coupling is where its delay puts it."""
        with self.lock:
            if self.poses and self.poses[-1][0] <= clock - self.period - 1e-6:
                return False  # (none yet: its first step is not due yet, or its first pose came unseen)
            # A node runs its tethers together, never past the latest pose of any (the 50 Hz one holds both),
            # and further behind when poses come late (its delay grows to the gaps it sees): NODE_SLACK.
            behind = self.delay + NODE_SLACK
            return not self.pulls or self.pulls[-1][0] >= clock - behind - 1e-6

    def note_lag(self, clock):
        with self.lock:
            if self.pulls:
                self.lags.append(clock - self.pulls[-1][0] - self.delay)

    def describe(self, clock):
        with self.lock:
            pose = self.poses[-1][0] - clock if self.poses else math.nan
            pull = self.pulls[-1][0] - clock if self.pulls else math.nan
        return "%s: pose %.3f s, coupling %.3f s from the clock" % (self.name, pose, pull)

    def taut(self):
        """Time [s] the pull first reached TAUT_PULL, or None."""
        with self.lock:
            return next((t for t, pull in self.pulls if pull >= TAUT_PULL), None)

    def speeds(self):
        """[(t, v)] of the vehicle from its consecutive poses (the simulator's own velocity: x' = x + h v')."""
        with self.lock:
            poses = list(self.poses)
        return [(b[0], (b[1] - a[1]) / (b[0] - a[0])) for a, b in zip(poses, poses[1:]) if b[0] > a[0]]


class ExternalCoupling(unittest.TestCase):
    def test_a_vehicle_thrusting_on_a_taut_tether_settles_without_bouncing(self):
        reference_peak, reference_settling = reference()
        self.allowed = reference_settling + MARGIN  # [s] after coming taut, for every run
        rospy.init_node("external_coupling_test")
        clock_pub = rospy.Publisher("/clock", Clock, queue_size=10)
        runs = [Run(name, delay, rate) for name, (delay, rate) in RUNS.items()]
        clock = 1000.0
        wall_start = time.time()
        # The nodes and the simulators start: the clock stands until every ~coupling and every simulator's pose
        # topic has its publisher.
        while not rospy.is_shutdown() and not all(r.coupling_sub.get_num_connections() > 0 and
                                                  r.pose_sub.get_num_connections() > 0 for r in runs):
            clock_pub.publish(Clock(rospy.Time.from_sec(clock)))
            time.sleep(0.1)
            self.assertLess(time.time() - wall_start, 120.0, "the nodes and simulators did not start")
        stalls, end = 0, None
        while not rospy.is_shutdown():
            clock += CLOCK_STEP
            clock_pub.publish(Clock(rospy.Time.from_sec(clock)))
            wait_start = time.time()
            while not all(r.caught_up(clock) for r in runs):
                if time.time() - wait_start > 5.0:
                    stalls += 1
                    if stalls <= 3:
                        print("stall at %.3f s: %s" % (clock - 1000.0, "; ".join(r.describe(clock) for r in runs)),
                              file=sys.stderr)
                    break
                time.sleep(0.0002)
            for r in runs:
                r.note_lag(clock)
            if end is None:
                tauts = [r.taut() for r in runs]
                if all(t is not None for t in tauts):
                    # The last run to come taut gets the reference's settling time, the margin and the window.
                    end = max(tauts) + self.allowed + WINDOW
            if end is not None and clock >= end:
                break
            self.assertLess(clock - 1000.0, 120.0, "no run came taut: %s" % [(r.name, len(r.pulls)) for r in runs])
        print("[ measured ] %.1f s simulated in %.1f s of wall time, %d clock stalls of 5 s" %
              (clock - 1000.0, time.time() - wall_start, stalls), file=sys.stderr)
        measured = [self.measure(run) for run in runs]  # every run's figures printed before any assertion
        for run, figures in zip(runs, measured):
            self.check(run, reference_peak, *figures)

    @staticmethod
    def impact_speed(run, taut):
        """[m/s] the vehicle's speed at the last pose by the time the tether came taut."""
        speeds = [abs(v) for t, v in run.speeds() if t <= taut + 1e-9]
        return speeds[-1] if speeds else 0.0

    def measure(self, run):
        """Prints the run's figures and returns what check() asserts."""
        taut = run.taut()
        v_impact = self.impact_speed(run, taut)
        with run.lock:
            pulls = list(run.pulls)
        speeds = run.speeds()
        peak = max(pull for _, pull in pulls)
        settled_from = taut + self.allowed
        late_pulls = [pull for t, pull in pulls if t >= settled_from]
        late_speeds = [abs(v) for t, v in speeds if t >= settled_from]
        # Its own settling time, for the record: the later of the pull's and the speed's.
        settled = max(settling([(t, abs(pull - THRUST), 0.0) for t, pull in pulls], taut),
                      settling([(t, 0.0, abs(v)) for t, v in speeds], taut))
        gaps = [round((b[0] - a[0]) / TIME_STEP, 6) for a, b in zip(pulls, pulls[1:])]
        print("[ measured ] %s: taut at %.3f s at %.4f m/s, peak pull %.1f N (bound %.1f N), settled %.2f s after; "
              "from %.2f s after: pull %.2f..%.2f N, speed at most %.5f m/s; %d couplings, %d gaps of one step; "
              "K along the tether %.0f N/m; coupling behind the clock beyond the delay: %s" %
              (run.name, taut - 1000.0, v_impact, peak, impact_bound(v_impact), settled, self.allowed,
               min(late_pulls or [math.nan]), max(late_pulls or [math.nan]), max(late_speeds or [math.nan]),
               len(pulls), gaps.count(1.0), run.stiffness, lag_summary(run.lags)), file=sys.stderr)
        return v_impact, peak, late_pulls, late_speeds, gaps

    def check(self, run, reference_peak, v_impact, peak, late_pulls, late_speeds, gaps):
        self.assertLessEqual(peak, impact_bound(v_impact), run.name)
        self.assertLessEqual(peak, PEAK_MARGIN * reference_peak, run.name)
        self.assertGreater(len(late_pulls), WINDOW / TIME_STEP * 0.9, run.name)
        self.assertGreater(len(late_speeds), WINDOW * 0.9 / run.period, run.name)
        self.assertLessEqual(max(abs(pull - THRUST) for pull in late_pulls), SETTLED_PULL, run.name)
        self.assertLess(max(late_speeds), SETTLED_SPEED, run.name)
        # Once per physics step: stamps on the step grid, in order, none twice; a message or two the test's
        # own subscriber dropped under load is a gap of several steps, no more than 1% of them.
        self.assertTrue(all(g >= 1.0 and g == int(g) for g in gaps), run.name)
        self.assertGreaterEqual(gaps.count(1.0), 0.99 * len(gaps), run.name)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "external_coupling", ExternalCoupling)
