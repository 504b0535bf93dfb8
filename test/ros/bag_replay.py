#!/usr/bin/env python3
"""rostest (test/ros/bag_replay.test): plays each recorded dive of test/data/ into tether_node with
`rosbag play --clock` and checks the ~state it published. Bounds are stated in BOUNDS and the README."""
import math
import os
import subprocess
import sys
import time
import unittest

import rosbag
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray

from rov_tether.msg import TetherState

CABLE_LENGTH = 10.0  # [m] config/default.yaml
BOUNDS = {
    # [N] largest segment tension: the paper's pay-out rule lets the cable stretch past payout_threshold
    # before the brake breaks away (measured up to 127 N in the lawn-mower survey)
    "tension": 200.0,
    # [-] largest segment strain, same cause (measured up to 0.30)
    "strain": 0.4,
    # [-] deployed / distance never below this (measured >= 0.93): the winch pays out what is pulled
    "shortest": 0.9,
    # [-] deployed / distance while the spool tension exceeds 1 N (measured <= 1.205): the passive
    # winch keeps at most (1 + reel_in_slack) x distance out
    "taut_longest": 1.25,
}


class BagReplay(unittest.TestCase):
    states = []
    real_time_factor = float("nan")

    @classmethod
    def setUpClass(cls):
        rospy.init_node("bag_replay_test")
        cls.data_dir = rospy.get_param("~data_dir")
        rospy.Subscriber("/tether_node/state", TetherState, lambda m: cls.states.append(m), queue_size=1000)
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls.on_diagnostics, queue_size=10)
        cls.expected_resets = 0
        cls.first_replay = True

    @classmethod
    def on_diagnostics(cls, msg):
        for status in msg.status:
            for kv in status.values:
                if kv.key == "physics real-time factor":
                    cls.real_time_factor = float(kv.value)

    def replay(self, name, rate=5.0):
        """Plays test/data/NAME.bag; returns (states of this replay, poses [(t, x, y, z)], end time)."""
        path = os.path.join(self.data_dir, name + ".bag")
        with rosbag.Bag(path) as bag:
            poses = [(m.header.stamp.to_sec(), m.pose.position.x, m.pose.position.y, m.pose.position.z)
                     for _, m, _ in bag.read_messages(topics=["/rov_pose"])]
            end = bag.get_end_time()
        if not self.first_replay:
            BagReplay.expected_resets += 1  # time goes back to the bag's start: the node resets
        BagReplay.first_replay = False
        del self.states[:]
        subprocess.run(["rosbag", "play", "--clock", "-q", "-r", str(rate), path], check=True, timeout=300,
                       stdout=subprocess.DEVNULL)
        # Wait (wall clock) for the physics to reach the end of the bag: the clock stops there and the
        # node runs interpolation_delay (0.1 s) behind it.
        deadline = time.time() + 20.0
        while time.time() < deadline:
            mine = [s for s in self.states if s.resets == self.expected_resets]
            if mine and mine[-1].header.stamp.to_sec() >= end - 0.2:
                break
            time.sleep(0.05)
        mine = [s for s in self.states if s.resets == self.expected_resets]
        self.assertTrue(mine, "no ~state during the replay of %s" % name)
        self.assertGreaterEqual(mine[-1].header.stamp.to_sec(), end - 0.2, "the physics did not reach the end")
        return mine, poses, end

    @staticmethod
    def distance_at(poses, t):
        """Spool (origin) to vehicle distance at time t, from the recorded poses (NaN ones skipped)."""
        good = [p for p in poses if all(math.isfinite(v) for v in p[1:])]
        for a, b in zip(good, good[1:]):
            if a[0] <= t <= b[0] and math.dist(a[1:], b[1:]) > 1.0:  # a jump: held until its time
                return math.dist((0, 0, 0), (a if t < b[0] else b)[1:])
            if a[0] <= t <= b[0]:
                u = (t - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
                return math.dist((0, 0, 0), [a[i] + u * (b[i] - a[i]) for i in (1, 2, 3)])
        return math.dist((0, 0, 0), good[-1][1:])

    def check_common(self, name, states, poses):
        """Bounds every replay must keep; prints what it measured. Ratios are deployed length over the
        spool-vehicle distance, from 1 s after the vehicle attached (the first pose)."""
        start = states[0].header.stamp.to_sec() + 1.0
        ratios = [(s.deployed_length / self.distance_at(poses, s.header.stamp.to_sec()), s) for s in states
                  if s.header.stamp.to_sec() >= start and s.vehicle_attached]
        taut = [r for r, s in ratios if s.tension_spool > 1.0]
        worst_tension = max(s.max_tension for s in states)
        worst_strain = max(s.max_strain for s in states)
        print("[ measured ] %-18s %4d states: max tension %6.2f N, max strain %.4f, deployed/distance >= %.3f,"
              " taut (%4d states, spool tension > 1 N) <= %.3f, max deployed %.2f m"
              % (name, len(states), worst_tension, worst_strain, min(r for r, _ in ratios), len(taut),
                 max(taut or [0.0]), max(s.deployed_length for s in states)), file=sys.stderr)
        for s in states:
            self.assertTrue(math.isfinite(s.max_tension) and math.isfinite(s.deployed_length))
            self.assertLessEqual(s.deployed_length, CABLE_LENGTH + 1e-9)
        self.assertLess(worst_tension, BOUNDS["tension"])
        self.assertLess(worst_strain, BOUNDS["strain"])
        self.assertGreater(min(r for r, _ in ratios), BOUNDS["shortest"])
        self.assertLess(max(taut or [0.0]), BOUNDS["taut_longest"])
        return taut

    def test_1_straight_excursion_pays_out_and_reels_in(self):
        states, poses, _ = self.replay("straight_excursion")
        taut = self.check_common("straight_excursion", states, poses)
        self.assertGreater(len(taut), 100)  # it was pulled taut, so the taut bound was tested
        self.assertGreater(max(s.deployed_length for s in states), 6.0)
        self.assertLess(states[-1].deployed_length, 2.5)  # reeled in on the way back

    def test_2_lawnmower_survey(self):
        states, poses, _ = self.replay("lawnmower")
        self.check_common("lawnmower", states, poses)

    def test_3_hover_with_jitter(self):
        states, poses, _ = self.replay("hover_jitter")
        self.check_common("hover_jitter", states, poses)
        late = [s.deployed_length for s in states if s.header.stamp.to_sec() > states[0].header.stamp.to_sec() + 10]
        self.assertLess(max(late) - min(late), 0.5)  # station keeping: the winch does not hunt

    def test_4_pose_jump_is_survived(self):
        states, poses, _ = self.replay("pose_jump")
        self.check_common("pose_jump", states, poses)
        self.assertGreaterEqual(states[-1].jumps, 1)

    def test_5_nan_pose_is_survived(self):
        states, poses, end = self.replay("nan_pose")
        self.check_common("nan_pose", states, poses)
        self.assertTrue(any(s.header.stamp.to_sec() > end - 5.0 for s in states))

    def test_6_same_seed_same_series_at_5x(self):
        first, _, _ = self.replay("straight_excursion", rate=5.0)
        second, _, _ = self.replay("straight_excursion", rate=5.0)
        a = {s.header.stamp.to_nsec(): s.deployed_length for s in first}
        b = {s.header.stamp.to_nsec(): s.deployed_length for s in second}
        common = sorted(set(a) & set(b))
        differences = [abs(a[t] - b[t]) for t in common]
        print("[ measured ] two replays: %d and %d states, %d at common stamps, max |difference| %.3g m, "
              "physics real-time factor %.0f" % (len(a), len(b), len(common), max(differences),
                                                   self.real_time_factor), file=sys.stderr)
        self.assertGreater(len(common), 0.95 * min(len(a), len(b)))
        self.assertEqual(max(differences), 0.0)
        # 5x replay keeps up: the physics reached each bag's end, and has headroom to spare.
        self.assertGreater(self.real_time_factor, 5.0)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "bag_replay", BagReplay)
