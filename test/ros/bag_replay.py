#!/usr/bin/env python3
"""rostest (test/ros/bag_replay.test): plays each recorded dive of test/data/ into tether_node with
`rosbag play --clock` and checks the ~state it published against bounds derived from the model and its
parameters (bounds(), reel_in_excess()), not from what it measured once."""
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


def bounds(p, v_max):
    """The bounds a replay must keep, derived from the model as it is (pbd with the passive strain brake)
    and its parameters `p` (the node's, read back from the parameter server), for a vehicle no faster than
    v_max [m/s]. Each is written out so it can be redone when the model changes (issue 12 replaces the
    strain-triggered brake by a tension brake; a new default solver changes the stiffness below):

    PBD's stiffness (docs/references.md, "Where methods fail"). A PBD constraint has no material
    stiffness: each of the n iterations of a step of length h restores a stretch e of a segment by moving
    its particles, of mass mu dL, so the constraint's multiplier grows by about mu dL e per iteration and
    its force by n mu dL e / h^2. Its equivalent axial stiffness is EA_pbd = n mu dL^2 / h^2 (400 N for
    default.yaml: 10 iterations, 0.1 kg/m, 0.1 m, 5 ms), the "EA" in T / EA for pbd.

    The brake. The passive winch holds the cable until the spool segment, read after the step's motion,
    is stretched beyond payout_threshold e_th (0.1), then pays out at up to max_winch_speed, faster than
    every recorded vehicle moves away. A constraint therefore holds at most T_c = EA_pbd e_th (40 N). A cut
    through the cable is crossed by c constraints: the segment's own and, with `bending`, the two (i, i+2)
    constraints spanning it (c = 3), and the tension read at the cut is their sum.

    - tension <= 1.5 c T_c + mu gamma v_max L: the brake tension of every constraint across a cut, 1.5 for
      the masses a constraint moves (the spool segment's rest ranges over 0.5 to 1.5 dL, so its particle's
      mass reaches 1.5 mu dL), plus the water's drag on the whole cable L towed at the vehicle's top speed
      (the paper's damping, gamma = -ln(drag) / 0.02 s: 7.9 N at 1.5 m/s for 10 m);
    - strain <= 4 e_th: red-black projection ends each sweep with one colour exact and the other carrying
      the stretch of both (2 e_th), 1.5 for the masses as above, and the step in which the brake gives
      (the pay-out, v_w h per step, takes the stretch away one step later): 2 x 1.5 + 1 = 4;
    - deployed >= distance / (1 + 1.5 e_th): the geometric length is at least the distance and at most the
      deployed length times (1 + the mean strain); while the brake holds, half the segments carry 2 e_th
      and half none, a mean of e_th, 1.5 for the masses;
    - deployed <= (1 + s) distance + E + v_w dt (`longest`, per state): the passive winch reels in at
      max_winch_speed v_w while more than (1 + reel_in_slack s) x distance is out and stops paying out at
      that limit (unless pulled over e_th); E is what a vehicle closing in faster than v_w / (1 + s) leaves
      out on top, E(t + dt) = max(0, E + (1 + s)(d(t) - d(t + dt)) - v_w dt) over the recorded distances,
      starting from max(initial_deployed_length, d) - (1 + s) d when the vehicle attaches.
    """
    if p["solver"] != "pbd" or p["winch_mode"] != "passive":
        raise AssertionError("these bounds are derived for pbd with the passive winch; redo them for solver %s, "
                             "winch_mode %s (see bounds())" % (p["solver"], p["winch_mode"]))
    h = p["time_step"] / p["substeps"]
    ea_pbd = p["iterations"] * p["mass_per_length"] * p["segment_length"] ** 2 / h ** 2
    crossing = 3 if p["bending"] else 1
    gamma = -math.log(p["drag"]) / 0.02
    drag = p["mass_per_length"] * gamma * v_max * p["cable_length"]
    e_th = p["payout_threshold"]
    return {
        "ea_pbd": ea_pbd,
        "tension": 1.5 * crossing * ea_pbd * e_th + drag,
        "strain": 4.0 * e_th,
        "shortest": 1.0 / (1.0 + 1.5 * e_th),
    }


def reel_in_excess(poses, p):
    """E(t) at each good pose's time (see bounds()): [(t, E)]."""
    good = [q for q in poses if all(math.isfinite(v) for v in q[1:])]
    s, v_w = p["reel_in_slack"], p["max_winch_speed"]
    d0 = math.dist((0, 0, 0), good[0][1:])
    excess = max(0.0, max(p["initial_deployed_length"], d0) - (1 + s) * d0)
    result = [(good[0][0], excess)]
    for a, b in zip(good, good[1:]):
        closing = math.dist((0, 0, 0), a[1:]) - math.dist((0, 0, 0), b[1:])
        excess = max(0.0, excess + (1 + s) * closing - v_w * (b[0] - a[0]))
        result.append((b[0], excess))
    return result

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
        # The node's own parameters (tether.launch loads default.yaml, bag_replay.yaml pins the solver).
        names = ["solver", "winch_mode", "iterations", "mass_per_length", "segment_length", "time_step", "substeps",
                 "bending", "drag", "payout_threshold", "cable_length", "max_winch_speed", "reel_in_slack",
                 "initial_deployed_length"]
        rospy.wait_for_service("/tether_node/get_tension", timeout=60.0)
        cls.params = {n: rospy.get_param("/tether_node/" + n) for n in names}

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
        """The bounds of bounds() every replay must keep; prints what it measured against them. Ratios are
        deployed length over the spool-vehicle distance, from 1 s after the vehicle attached."""
        p = self.params
        good = [q for q in poses if all(math.isfinite(v) for v in q[1:])]
        steps = [(math.dist(a[1:], b[1:]), b[0] - a[0]) for a, b in zip(good, good[1:])]
        v_max = max(d / dt for d, dt in steps if d <= 1.0)  # the vehicle's top speed, jumps left out
        dt_pose = max(dt for _, dt in steps)
        limit = bounds(p, v_max)
        excess = reel_in_excess(poses, p)
        start = states[0].header.stamp.to_sec() + 1.0
        attached = [s for s in states if s.header.stamp.to_sec() >= start and s.vehicle_attached]
        ratios = [(s.deployed_length / self.distance_at(poses, s.header.stamp.to_sec()), s) for s in attached]
        # deployed - (1 + s) d against E at the last pose before the state, plus what the distance may
        # close between two poses (the physics interpolates between them) and one step of the winch.
        s_ = p["reel_in_slack"]
        overshoot = []
        for s in attached:
            t = s.header.stamp.to_sec()
            e = max(x for tx, x in excess if tx <= t) if any(tx <= t for tx, _ in excess) else excess[0][1]
            allowed = e + (1 + s_) * v_max * dt_pose + p["max_winch_speed"] * p["time_step"]
            overshoot.append((s.deployed_length - (1 + s_) * self.distance_at(poses, t)) - allowed)
        worst_tension = max(s.max_tension for s in states)
        worst_strain = max(s.max_strain for s in states)
        print("[ measured ] %-18s %4d states, vehicle up to %.2f m/s: max tension %6.2f N (bound %.0f N), max strain "
              "%.4f (bound %.2f), deployed/distance >= %.3f (bound %.3f), beyond the reel-in limit by at most "
              "%+.3f m of what the winch rule allows, max deployed %.2f m"
              % (name, len(states), v_max, worst_tension, limit["tension"], worst_strain, limit["strain"],
                 min(r for r, _ in ratios), limit["shortest"], max(overshoot), max(s.deployed_length for s in states)),
              file=sys.stderr)
        for s in states:
            self.assertTrue(math.isfinite(s.max_tension) and math.isfinite(s.deployed_length))
            self.assertLessEqual(s.deployed_length, p["cable_length"] + 1e-9)
        self.assertLess(worst_tension, limit["tension"])
        self.assertLess(worst_strain, limit["strain"])
        self.assertGreater(min(r for r, _ in ratios), limit["shortest"])
        self.assertLessEqual(max(overshoot), 0.0)
        return [r for r, s in ratios if s.tension_spool > 1.0]

    def test_1_straight_excursion_pays_out_and_reels_in(self):
        states, poses, _ = self.replay("straight_excursion")
        taut = self.check_common("straight_excursion", states, poses)
        self.assertGreater(len(taut), 100)  # it was pulled taut (spool tension > 1 N), so the brake was tested
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
