#!/usr/bin/env python3
"""rostest (test/ros/bag_replay.test): plays each recorded dive of test/data/ into tether_node with
`rosbag play --clock` and checks the ~state it published (default.yaml's direct solver and brake
winch, with test/ros/bag_replay.yaml's faster winch). Bounds are derived in BOUNDS and tension_bound()."""
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

# The parameters the bounds are derived from are read back from the node (tether.launch loads default.yaml,
# then test/ros/bag_replay.yaml); the derivation holds for direct with the brake winch, and says so otherwise.
PARAMETERS = ["solver", "winch_mode", "brake_tension", "mass_per_length", "axial_stiffness", "drag", "cable_length"]
BOUNDS = {
    # [-] deployed / distance never below this: a brake pays out whatever pulls harder than it, so the cable
    # is never shorter than the distance beyond its elastic stretch (< 0.1%) and the node's pose timing
    # (0.05 s samples at up to 1.5 m/s, 3 m out: 2.5%)
    "shortest": 0.97,
}


def tension_bound(p, poses, longest):
    """[N] The most a brake winch lets the cable carry in a replay: the brake, plus the damping drag and the
    inertia of the whole deployed cable (longest [m]) moving with the vehicle at its fastest recorded speed
    and acceleration (sample to sample, from rest at the start and after a jump of more than 1 m, where the
    node re-lays the cable at rest; NaN poses excluded, the node refuses them). The cable is shorter than an
    axial wave travels in one sample (sqrt(EA / mu) 0.05 s = 50 m), so all of it takes each jerk. The damping
    rate is the paper's drag as a rate, -ln(drag) / 0.02 s (docs/model.md)."""
    if p["solver"] != "direct" or p["winch_mode"] != "brake":
        raise AssertionError("the bounds are derived for direct with the brake winch; redo them for solver %s, "
                             "winch_mode %s (see tension_bound())" % (p["solver"], p["winch_mode"]))
    good = [q for q in poses if all(math.isfinite(v) for v in q[1:])]
    velocities = [(good[0][0], [0.0, 0.0, 0.0])]
    for a, b in zip(good, good[1:]):
        jump = math.dist(a[1:], b[1:]) > 1.0
        if b[0] > a[0]:
            velocities.append((b[0], [0.0 if jump else (b[i] - a[i]) / (b[0] - a[0]) for i in (1, 2, 3)]))
    speed = max(math.hypot(*v) for _, v in velocities)
    acceleration = max(math.dist(u, v) / (tv - tu) for (tu, u), (tv, v) in zip(velocities, velocities[1:]) if tv > tu)
    damping = -math.log(p["drag"]) / 0.02
    return p["brake_tension"] + p["mass_per_length"] * longest * (damping * speed + acceleration)


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
        rospy.wait_for_service("/tether_node/get_tension", timeout=60.0)
        cls.params = {n: rospy.get_param("/tether_node/" + n) for n in PARAMETERS}

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
        # Wait (wall clock) for the physics to reach the end of the bag. The last /clock rosbag play publishes
        # may be one tick (100 Hz wall: rate / 100 s of bag time) before the end; the physics timer
        # (physics_rate) runs interpolation_delay behind that clock; ~state comes on a grid of 1 / state_rate;
        # and the state and physics timers due at the same tick fire in either order, so the last state may
        # read the physics of the tick before: one tick more (replay_launch.py's bound has no second tick:
        # its last state is compared with the last pose, here with the bag's end; a run here read 0.205 s).
        node = {n: rospy.get_param("/tether_node/" + n) for n in ("physics_rate", "interpolation_delay", "state_rate")}
        lag = (2.0 * rate / 100.0 + 1.0 / node["physics_rate"] + node["interpolation_delay"] +
               1.0 / node["state_rate"])
        deadline = time.time() + 20.0
        while time.time() < deadline:
            mine = [s for s in self.states if s.resets == self.expected_resets]
            if mine and mine[-1].header.stamp.to_sec() >= end - lag:
                break
            time.sleep(0.05)
        mine = [s for s in self.states if s.resets == self.expected_resets]
        self.assertTrue(mine, "no ~state during the replay of %s" % name)
        self.assertGreaterEqual(mine[-1].header.stamp.to_sec(), end - lag,
                                "the physics did not reach the end (bound %.3f s before it)" % lag)
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
        ratios = [s.deployed_length / self.distance_at(poses, s.header.stamp.to_sec()) for s in states
                  if s.header.stamp.to_sec() >= start and s.vehicle_attached]
        worst_tension = max(s.max_tension for s in states)
        worst_strain = max(s.max_strain for s in states)
        p = self.params
        bound = tension_bound(p, poses, max(s.deployed_length for s in states))
        print("[ measured ] %-18s %4d states: max tension %6.2f N (bound %5.1f N), max strain %.4f, "
              "deployed/distance >= %.3f, max deployed %.2f m"
              % (name, len(states), worst_tension, bound, worst_strain, min(ratios),
                 max(s.deployed_length for s in states)), file=sys.stderr)
        for s in states:
            self.assertTrue(math.isfinite(s.max_tension) and math.isfinite(s.deployed_length))
            self.assertLessEqual(s.deployed_length, p["cable_length"] + 1e-9)
            self.assertEqual(s.winch_mode, "brake")
        self.assertLess(worst_tension, bound)
        self.assertLess(worst_strain, bound / p["axial_stiffness"])  # a segment stretches by its T / EA
        self.assertGreater(min(ratios), BOUNDS["shortest"])

    def test_1_straight_excursion_pays_out_and_holds(self):
        states, poses, _ = self.replay("straight_excursion")
        self.check_common("straight_excursion", states, poses)
        self.assertGreater(max(s.deployed_length for s in states), 6.0)  # paid out to the 7.8 m excursion
        # A brake never reels in: the length paid out stays out on the way back.
        lengths = [s.deployed_length for s in states]
        self.assertGreaterEqual(min(b - a for a, b in zip(lengths, lengths[1:])), -1e-9)

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
        # The node restarts a replay at the first tick of the new clock (rosbag play sets its phase) and takes
        # or refuses the poses that came just before it by their arrival, so two replays do not start alike to
        # the bit, and a brake, which never reels in, keeps what each start paid out. They were asserted equal
        # to the bit: 4 runs in 5 here differed, by 1.6-24 mm, and 3 in 3 before the last change to the spool's
        # joint (docs/limitations.md). The stated tolerance: 1% of the largest deployed length.
        bound = 0.01 * max(a.values())
        print("[ measured ] two replays: %d and %d states, %d at common stamps, max |difference| %.3g m (bound "
              "%.3g m), physics real-time factor %.0f" % (len(a), len(b), len(common), max(differences), bound,
                                                          self.real_time_factor), file=sys.stderr)
        self.assertGreater(len(common), 0.95 * min(len(a), len(b)))
        self.assertLessEqual(max(differences), bound)
        # 5x replay keeps up: the physics reached each bag's end, and has headroom to spare.
        self.assertGreater(self.real_time_factor, 5.0)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "bag_replay", BagReplay)
