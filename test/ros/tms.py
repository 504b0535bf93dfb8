#!/usr/bin/env python3
"""rostest (test/ros/tms.test): a TMS in tether_node, config/tms_demo.yaml as the demo ships it, with the ROV
holding its start (no setpoints come). Checks what the node adds to the core's TMS (test/test_tms.cpp has the
physics):

- the tether's spool rides on the cage: tf world -> tether/tether_spool (the spool outlet the tether's
  physics uses) is the cage's frame world -> tms times spool_outlet_offset [0, 0, -1], to 1 mm (the two are
  published with the same physics stamp; 1 mm is the rounding of tf's float64 plus nothing), while the cage
  goes down: after WATCH seconds of the umbilical paying out at 0.3 m/s the cage is lower by at least half of
  what the winch paid out (the rest: its start-up at 0.1 m/s^2 and the interpolation delay);
- both winches publish their state on ~<name>/state: the umbilical's in speed mode paying out, the
  tether's in constant_tension;
- the node logged no error while watched.
"""
import math
import sys
import time
import unittest

import rospy
import rostest
import tf2_ros
from rosgraph_msgs.msg import Log

from rov_tether.msg import TetherState

WATCH = 10.0  # [s] of wall time watched after the first states
OUTLET = (0.0, 0.0, -1.0)  # config/tms_demo.yaml: tether/spool_outlet_offset


def rotate(q, v):
    """v rotated by the unit quaternion q (geometry_msgs Quaternion)."""
    x, y, z, w = q.x, q.y, q.z, q.w
    # v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    cx, cy, cz = y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0]
    return (v[0] + 2.0 * (w * cx + y * cz - z * cy), v[1] + 2.0 * (w * cy + z * cx - x * cz),
            v[2] + 2.0 * (w * cz + x * cy - y * cx))


class Tms(unittest.TestCase):
    def test_the_spool_rides_on_the_cage_and_both_winches_report(self):
        rospy.init_node("tms_test")
        states = {}
        logs = []
        for name in ("umbilical", "tether"):
            rospy.Subscriber("/tether_node/%s/state" % name, TetherState,
                             lambda m, name=name: states.__setitem__(name, m), queue_size=10)
        rospy.Subscriber("/rosout", Log, lambda m: logs.append(m), queue_size=1000)
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        deadline = time.time() + 60.0
        while len(states) < 2 and time.time() < deadline:
            time.sleep(0.1)
        self.assertEqual(len(states), 2, "no ~umbilical/state and ~tether/state within 60 s")
        start_length = states["umbilical"].deployed_length
        start_z = None
        worst = 0.0
        samples = 0
        end = time.time() + WATCH
        while time.time() < end:
            time.sleep(0.2)
            try:
                stamp = buffer.get_latest_common_time("tms", "tether/tether_spool")
                cage = buffer.lookup_transform("world", "tms", stamp).transform
                spool = buffer.lookup_transform("world", "tether/tether_spool", stamp).transform.translation
            except (tf2_ros.LookupException, tf2_ros.ExtrapolationException, tf2_ros.ConnectivityException,
                    tf2_ros.TransformException):
                continue
            offset = rotate(cage.rotation, OUTLET)
            expected = (cage.translation.x + offset[0], cage.translation.y + offset[1], cage.translation.z + offset[2])
            worst = max(worst, math.dist(expected, (spool.x, spool.y, spool.z)))
            start_z = cage.translation.z if start_z is None else start_z
            end_z = cage.translation.z
            samples += 1
        self.assertGreater(samples, 10, "too few tf samples of tms and tether/tether_spool")
        print("[ measured ] spool off the cage's outlet by at most %.2g m over %d samples; the cage went down "
              "%.2f m while the umbilical paid out %.2f m" % (worst, samples, start_z - end_z,
                                                             states["umbilical"].deployed_length - start_length))
        self.assertLess(worst, 1e-3)
        paid = states["umbilical"].deployed_length - start_length
        self.assertGreater(paid, 0.3 * WATCH * 0.5, "the umbilical's winch did not pay out")
        self.assertGreater(start_z - end_z, 0.5 * paid, "the cage did not go down with its umbilical")
        self.assertEqual(states["umbilical"].winch_mode, "speed")
        self.assertGreater(states["umbilical"].winch_speed, 0.25)
        self.assertEqual(states["tether"].winch_mode, "constant_tension")
        errors = [m.msg for m in logs if m.name == "/tether_node" and m.level >= Log.ERROR]
        self.assertEqual(errors, [])


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "tms", Tms, sys.argv)
