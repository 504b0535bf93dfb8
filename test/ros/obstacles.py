#!/usr/bin/env python3
"""rostest (test/ros/obstacles.test): tether_node with obstacles (test/ros/obstacles.yaml).

- ~obstacles arrives latched, one marker per primitive of the right type (a capsule as a cylinder and two
  spheres, a plane as a thin cube), and republished where its tf frame puts an obstacle that follows one;
- an obstacle whose frame never comes keeps its pose, with a warning naming the obstacle and the frame;
- the vehicle circles the pillar once, counter-clockwise seen from above, and comes back to where it
  started: the tether, caught on the pillar, is then wound once around its axis, so ~topology reports
  wrap_turns for the pillar of +1 (the turns the path made) within 0.1, and /diagnostics warns naming the
  pillar for the wrap (|turns| >= wrap_warning_turns 0.5), and for a snag exactly when the capstan ratio
  ~topology reports for the pillar is above snag_ratio; the contact angle ~topology reports is the one the
  tangents from the spool and the vehicle give, and the capstan ratio e^(friction x angle) within 10%;
- the contact points are in ~markers (namespace contacts), on the pillar's surface;
- a bad obstacle entry stops the node at start with the documented error (ROS_FATAL naming the entry and
  the field), as any bad parameter does.
"""
import math
import os
import subprocess
import sys
import threading
import unittest

import rospkg
import rospy
import rostest
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseStamped, TransformStamped
from rosgraph_msgs.msg import Log
from visualization_msgs.msg import Marker, MarkerArray

from rov_tether.msg import Topology

PACKAGE = rospkg.RosPack().get_path("rov_tether")
sys.path.insert(0, os.path.join(PACKAGE, "scripts"))
import simulated_rov  # noqa: E402  (scripts/ is not a Python package)

NODE = "/tether_node"
TIMEOUT = 30.0  # [s] start-up of the node and its first messages
PILLAR = (4.0, 0.0)  # [m] its axis, test/ros/obstacles.yaml
PILLAR_RADIUS = 0.5  # [m]
CIRCLE_RADIUS = 2.0  # [m] the vehicle's circle around the axis: 1.5 m clear of the pillar
SPEED = 0.8  # [m/s] along the circle, within max_winch_speed (1 m/s), so the winch keeps up
DEPTH = -1.0  # [m] the vehicle's and the spool's
TURNS = 1  # counter-clockwise seen from above (+z): positive wrap turns
BUOY_AT = (-6.0, 5.0, -2.0)  # [m] where the test's tf puts buoy_frame; the buoy is 0.5 m above its origin
CABLE_RADIUS = 0.01  # [m] half of default.yaml's diameter
# A contact point is recorded on the segment's axis after the push that clears it, one cable radius off the
# pillar's surface; a later segment's push in the same step may move a shared particle by its depth, at
# most one step's motion of the cable: the vehicle's SPEED x time_step (0.005 s) = 4 mm.
SURFACE_TOLERANCE = SPEED * 0.005  # [m]


def circle_waypoints(turns, start_time):
    """[t, x, y, z] every 10 degrees: from (2, 0) (west of the pillar, 2 m from the spool) `turns` times
    around the pillar's axis at CIRCLE_RADIUS, counter-clockwise for turns > 0, at SPEED."""
    steps = int(36 * abs(turns))
    leg = 2 * math.pi * CIRCLE_RADIUS / 36 / SPEED  # [s] per 10 degrees
    points = []
    for k in range(steps + 1):
        angle = math.pi + math.copysign(2 * math.pi * k / 36, turns)
        points.append([start_time + k * leg, PILLAR[0] + CIRCLE_RADIUS * math.cos(angle),
                       PILLAR[1] + CIRCLE_RADIUS * math.sin(angle), DEPTH])
    return points


def sibling_node():
    """The tether_node of the workspace this test runs in: the first devel space on CMAKE_PREFIX_PATH (rosrun
    would be ambiguous beside a second, sanitizer build of the package, and exits 127 there)."""
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        path = os.path.join(prefix, "lib", "rov_tether", "tether_node")
        if os.access(path, os.X_OK):
            return path
    raise RuntimeError("no tether_node under CMAKE_PREFIX_PATH")


class Obstacles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("obstacles_test")
        cls.lock = threading.Lock()
        cls.obstacle_arrays = []
        cls.topology = None
        cls.statuses = []
        cls.contacts = None
        cls.logs = []
        rospy.Subscriber(NODE + "/obstacles", MarkerArray, lambda m: cls.keep("obstacle_arrays", m, True))
        rospy.Subscriber(NODE + "/topology", Topology, lambda m: cls.keep("topology", m))
        rospy.Subscriber("/diagnostics", DiagnosticArray, cls.on_diagnostics, queue_size=50)
        rospy.Subscriber(NODE + "/markers", MarkerArray, cls.on_markers, queue_size=2)
        rospy.Subscriber("/rosout", Log, lambda m: cls.keep("logs", m, True), queue_size=100)
        cls.pose_pub = rospy.Publisher("/rov_pose", PoseStamped, queue_size=10)
        cls.tf = tf2_ros.TransformBroadcaster()

    @classmethod
    def keep(cls, name, msg, append=False):
        with cls.lock:
            if append:
                getattr(cls, name).append(msg)
            else:
                setattr(cls, name, msg)

    @classmethod
    def on_diagnostics(cls, msg):
        for status in msg.status:
            if status.name.endswith(": tether"):
                cls.keep("statuses", status, True)

    @classmethod
    def on_markers(cls, msg):
        for marker in msg.markers:
            if marker.ns == "contacts":
                cls.keep("contacts", marker)

    def wait_for(self, what, timeout=TIMEOUT):
        end = rospy.Time.now() + rospy.Duration(timeout)
        while not rospy.is_shutdown() and rospy.Time.now() < end:
            with self.lock:
                if what():
                    return True
            rospy.sleep(0.05)
        return False

    def publish(self, position, stamp):
        msg = PoseStamped()
        msg.header.stamp = stamp
        msg.header.frame_id = "world"
        msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = position
        msg.pose.orientation.w = 1.0
        self.pose_pub.publish(msg)
        buoy = TransformStamped()
        buoy.header.stamp = stamp
        buoy.header.frame_id = "world"
        buoy.child_frame_id = "buoy_frame"
        buoy.transform.translation.x, buoy.transform.translation.y, buoy.transform.translation.z = BUOY_AT
        buoy.transform.rotation.w = 1.0
        self.tf.sendTransform(buoy)

    def drive(self, waypoints, hold):
        """Publishes the vehicle along `waypoints` at 20 Hz (simulated_rov.py's path, no loop), then holds
        it at the end for `hold` seconds."""
        dive = simulated_rov.Dive(waypoints, loop=False)
        rate = rospy.Rate(20)
        start = rospy.Time.now()
        end = waypoints[-1][0] + hold
        while not rospy.is_shutdown():
            now = rospy.Time.now()
            t = (now - start).to_sec()
            if t > end:
                return
            position, _ = dive.pose(t)
            self.publish(position, now)
            rate.sleep()

    def pillar_wrap(self):
        with self.lock:
            msg = self.topology
        if msg is None:
            return None
        values = [e.value for e in msg.entries if e.object == "pillar" and e.kind == "wrap_turns"]
        self.assertEqual(len(values), 1, "one wrap_turns line for the pillar: %s" % msg.entries)
        return values[0]

    def test_1_obstacles_latched_with_their_marker_types(self):
        # Subscribed before the node published: the latched message arrives even so, once.
        self.assertTrue(self.wait_for(lambda: self.obstacle_arrays), "no ~obstacles")
        markers = self.obstacle_arrays[0].markers
        shapes = [m for m in markers if m.ns == "obstacles"]
        names = {m.text for m in markers if m.ns == "obstacle_names"}
        self.assertEqual(names, {"pillar", "rock", "crate", "riser", "seabed", "buoy", "ghost"})
        # In the order of the list: pillar, rock, crate, riser (cylinder + two spheres), seabed, buoy, ghost.
        types = [m.type for m in shapes]
        self.assertEqual(types, [Marker.CYLINDER, Marker.SPHERE, Marker.CUBE, Marker.CYLINDER, Marker.SPHERE,
                                 Marker.SPHERE, Marker.CUBE, Marker.SPHERE, Marker.SPHERE])
        pillar = shapes[0]
        self.assertAlmostEqual(pillar.scale.x, 2 * PILLAR_RADIUS)
        self.assertAlmostEqual(pillar.scale.z, 12.0)
        self.assertAlmostEqual(pillar.pose.position.x, PILLAR[0])
        # The riser lies along y (rolled 90 degrees): its end spheres 1.5 m either side of its centre.
        ends = sorted(m.pose.position.y for m in shapes[4:6])
        self.assertAlmostEqual(ends[0], -1.5, places=5)
        self.assertAlmostEqual(ends[1], 1.5, places=5)
        # The seabed: a thin slab just below z = -30.
        seabed = shapes[6]
        self.assertLess(seabed.scale.z, 0.1)
        self.assertGreater(seabed.scale.x, 50.0)
        self.assertLess(seabed.pose.position.z, -30.0)

    def test_2_frame_moving_obstacle_follows_its_frame_and_a_missing_frame_warns(self):
        # The buoy's frame comes with the poses: the node moves it and republishes ~obstacles.
        stamp = rospy.Time.now()
        self.publish((2.0, 0.0, DEPTH), stamp)

        def buoy_moved():
            for array in self.obstacle_arrays:
                shapes = [m for m in array.markers if m.ns == "obstacles"]
                if len(shapes) == 9 and abs(shapes[7].pose.position.x - BUOY_AT[0]) < 1e-6:
                    return shapes[7]
            return None

        end = rospy.Time.now() + rospy.Duration(TIMEOUT)
        while not buoy_moved() and rospy.Time.now() < end:
            self.publish((2.0, 0.0, DEPTH), rospy.Time.now())
            rospy.sleep(0.05)
        buoy = buoy_moved()
        self.assertIsNotNone(buoy, "~obstacles never showed the buoy at its frame")
        self.assertAlmostEqual(buoy.pose.position.y, BUOY_AT[1], places=6)
        self.assertAlmostEqual(buoy.pose.position.z, BUOY_AT[2] + 0.5, places=6)  # 0.5 m above the frame
        # The ghost's frame never comes: it stays at its position, and the log says which obstacle and frame.
        ghost = [m for m in self.obstacle_arrays[-1].markers if m.ns == "obstacles"][8]
        self.assertAlmostEqual(ghost.pose.position.x, -20.0)
        self.assertTrue(self.wait_for(lambda: any("ghost" in log.msg and "no_such_frame" in log.msg
                                                  for log in self.logs)), "no warning about ghost's frame")

    def test_3_circling_the_pillar_winds_the_tether_once_around_it(self):
        self.drive([[0.0, 2.0, 0.0, DEPTH], [2.0, 2.0, 0.0, DEPTH]], hold=0.0)  # settle at the start
        self.assertTrue(self.wait_for(lambda: self.topology is not None), "no ~topology")
        before = self.pillar_wrap()
        print("[ measured ] before the circle: wrap_turns around the pillar %.3f" % before, file=sys.stderr)
        self.assertLess(abs(before), 0.1)  # the tether runs straight from the spool to the vehicle
        self.drive(circle_waypoints(TURNS, 0.0), hold=3.0)
        # Once back where it started, with the physics (0.1 s behind) past the circle's end.
        wrap = self.pillar_wrap()
        print("[ measured ] after %d turn(s) counter-clockwise: wrap_turns around the pillar %.3f"
              % (TURNS, wrap), file=sys.stderr)
        self.assertAlmostEqual(wrap, TURNS, delta=0.1)
        with self.lock:
            entries = list(self.topology.entries)
        ratios = [e.value for e in entries if e.object == "pillar" and e.kind == "capstan_ratio"]
        print("[ measured ] capstan ratio on the pillar: %s" % ratios, file=sys.stderr)
        angles = [e.value for e in entries if e.object == "pillar" and e.kind == "contact_angle"]
        # Wound round, the tether touches the pillar from the tangent point of the line from the spool (4 m
        # west of the axis) on the south side, round the east and north, to the tangent point of the line
        # to the vehicle (2 m west): it turns through pi + asin(r / 4) + asin(r / 2), r the pillar's radius
        # plus the cable's (the neutrally buoyant cable lies level; a string, bending_stiffness 0 in
        # obstacles.yaml: at the default EI the cable left the pillar early, 2.63 rad). The ratio is
        # e^(friction x angle),
        # friction 0.5 (the obstacle default). 10% on the ratio is 0.19 rad on the angle: the cable's
        # discretisation (0.1 m segments, each turning 0.2 rad on the pillar) and the push that leaves it
        # one cable radius off the surface.
        self.assertEqual(len(ratios), 1)
        self.assertEqual(len(angles), 1)
        r = PILLAR_RADIUS + CABLE_RADIUS
        theta = math.pi + math.asin(r / PILLAR[0]) + math.asin(r / (PILLAR[0] - 2.0))
        print("[ measured ] contact angle %.3f rad against %.3f rad from the tangents; capstan ratio %.3f "
              "against e^(0.5 x %.3f) = %.3f" % (angles[0], theta, ratios[0], theta, math.exp(0.5 * theta)),
              file=sys.stderr)
        self.assertAlmostEqual(ratios[0], math.exp(0.5 * angles[0]), delta=1e-6 * ratios[0])
        self.assertAlmostEqual(ratios[0] / math.exp(0.5 * theta), 1.0, delta=0.1)
        # /diagnostics (1 Hz): WARN naming the pillar for the wrap, and the snag exactly when the ratio is over
        # snag_ratio (3). The vehicle holds still, so the next report has the same topology.
        count = len(self.statuses)
        self.assertTrue(self.wait_for(lambda: len(self.statuses) > count + 1), "no /diagnostics")
        last = self.statuses[-1]
        print("[ measured ] diagnostics: %s" % last.message, file=sys.stderr)
        self.assertEqual(last.level, DiagnosticStatus.WARN)
        self.assertIn("tether wrapped 1.00 turns around pillar", last.message)
        self.assertEqual("tether snagged on pillar" in last.message, ratios[0] > 3.0)
        # Contact points in ~markers, on the pillar's surface.
        self.assertTrue(self.wait_for(lambda: self.contacts is not None and self.contacts.points),
                        "no contact points in ~markers")
        with self.lock:
            points = list(self.contacts.points)
        gaps = [math.hypot(p.x - PILLAR[0], p.y - PILLAR[1]) - PILLAR_RADIUS for p in points]
        print("[ measured ] %d contact points, %.4f to %.4f m from the pillar's surface"
              % (len(points), min(gaps), max(gaps)), file=sys.stderr)
        self.assertLess(max(abs(g - CABLE_RADIUS) for g in gaps), SURFACE_TOLERANCE)

    def test_4_a_bad_obstacle_entry_stops_the_node_naming_it(self):
        name = "bad_obstacles_node"
        rospy.set_param("/%s/obstacles" % name, [
            {"name": "pillar", "type": "cylinder", "position": [4.0, 0.0, -5.0], "radius": 0.5}])  # no length
        node = subprocess.run([sibling_node(), "__name:=" + name], capture_output=True, text=True, timeout=TIMEOUT)
        output = node.stdout + node.stderr
        print("[ measured ] exit %d: %s" % (node.returncode, output.strip().splitlines()[-1:]), file=sys.stderr)
        self.assertEqual(node.returncode, 1)
        self.assertIn("tether_node: invalid parameters in /%s: obstacles[0]: obstacle 'pillar' (cylinder): "
                      "length must be > 0 m" % name, output)
        self.assertIn("FATAL", output)

    def test_5_a_bad_tether_name_stops_the_node_naming_it(self):
        # One rule for a tether's name, the runner's (1-64 letters, digits, '_' or '-'), checked with the
        # obstacles' names before the world is built; the node's tethers also live under ~<name>/, so the name
        # must be a ROS name. Either is refused at start, naming the entry (issue 21).
        for bad, reason in (("a/b", "expected 1-64 letters, digits, '_' or '-'"), ("rov-1", "not a ROS name")):
            name = "bad_tether_name_node"
            rospy.set_param("/%s/tethers" % name, ["t0", bad])
            node = subprocess.run([sibling_node(), "__name:=" + name], capture_output=True, text=True,
                                  timeout=TIMEOUT)
            output = node.stdout + node.stderr
            print("[ measured ] exit %d: %s" % (node.returncode, output.strip().splitlines()[-1:]), file=sys.stderr)
            self.assertEqual(node.returncode, 1)
            self.assertIn("tether_node: parameter 'tethers': entry 1 '%s': %s" % (bad, reason), output)
            rospy.delete_param("/%s" % name)


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "obstacles", Obstacles)
