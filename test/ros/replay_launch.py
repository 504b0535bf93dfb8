#!/usr/bin/env python3
"""rostest (test/ros/replay_launch.test): `roslaunch rov_tether replay.launch` as the README shows it.

1. Run from a scratch directory with a relative `bag:=` path to test/data/straight_excursion.bag, at 5x:
   roslaunch ends by itself with exit code 0, every process "finished cleanly" (no "REQUIRED process ...
   has died"), and the default output is $ROS_HOME/replay/straight_excursion.tether.bag, not next to the
   bag in the source tree. The recorded bag holds every pose of the dive and ~state up to its end.
2. A bag that does not exist: the launch ends by itself, naming the resolved path.
3. A mavros bag (PoseStamped in `map` on /mavros/local_position/pose, no tf) replays with the defaults
   through `rosrun rov_tether replay.sh`: exit code 0, the vehicle attached (issue 26, items 1 and 3).
4. The same bag with `world_frame_from_pose: false`: every pose refused; replay.sh exits 1 and says that
   no pose was taken and how many were refused (it used to exit 0 with 428 states, none attached).
5. A bag of nav_msgs/Odometry (robot_localization) replays: exit code 0, the vehicle attached (item 4),
   recorded into a directory given as `output` under the default name.
   This Python has no nav_msgs module: the class is generated from the installed .msg files.
6. Bad arguments (a rate that is no number or not > 0, a file that is not a bag, an output that is the bag
   itself once rosbag adds .bag) are refused by name, replay.sh exits 1 and the launch ends by itself.
"""
import os
import shutil
import subprocess
import tempfile
import unittest

import genmsg
import genmsg.msg_loader
import genpy.dynamic
import rosbag
import rospkg
import rospy
import rostest
import yaml
from geometry_msgs.msg import PoseStamped

PACKAGE = rospkg.RosPack().get_path("rov_tether")
DATA = os.path.join(PACKAGE, "test", "data")
BAG = "straight_excursion.bag"  # 50 s of poses at 20 Hz (scripts/make_test_bags.py)
RATE = 5.0  # playback speed-up
TIMEOUT = 180.0  # [s] for one replay; 50 s at 5x takes about 15 s


class ReplayLaunch(unittest.TestCase):
    def setUp(self):
        self.scratch = tempfile.mkdtemp(prefix="replay_launch_")
        # Deeper than ROS_HOME (where roslaunch runs its nodes), so the relative path means nothing there.
        self.cwd = os.path.join(self.scratch, "dives", "today")
        self.ros_home = os.path.join(self.scratch, "ros_home")
        os.makedirs(self.cwd)

    def tearDown(self):
        shutil.rmtree(self.scratch, ignore_errors=True)

    def roslaunch(self, *args, command=("roslaunch", "rov_tether", "replay.launch")):
        """roslaunch rov_tether replay.launch ARGS from self.cwd, as a shell would start it."""
        env = dict(os.environ, ROS_HOME=self.ros_home, PWD=self.cwd)
        done = subprocess.run(list(command) + list(args), cwd=self.cwd, env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT)
        return done.returncode, done.stdout

    @staticmethod
    def odometry_class():
        """nav_msgs/Odometry generated from the installed message definitions (same md5 as the C++ one)."""
        search = {package: ["/usr/share/%s/msg" % package] for package in ("nav_msgs", "geometry_msgs", "std_msgs")}
        context = genmsg.MsgContext.create_default()
        spec = genmsg.msg_loader.load_msg_by_type(context, "nav_msgs/Odometry", search)
        genmsg.msg_loader.load_depends(context, spec, search)
        text = genmsg.compute_full_text(context, spec)
        return genpy.dynamic.generate_dynamic("nav_msgs/Odometry", text)["nav_msgs/Odometry"]

    def write_mavros_bag(self):
        """10 s of mavros local position at 20 Hz: PoseStamped in `map`, out from 1.5 to 4.5 m along x."""
        path = os.path.join(self.cwd, "mavros_dive.bag")
        with rosbag.Bag(path, "w") as bag:
            for k in range(201):
                msg = PoseStamped()
                msg.header.stamp = rospy.Time.from_sec(1000.0 + 0.05 * k)
                msg.header.frame_id = "map"
                msg.pose.position.x, msg.pose.position.z = 1.5 + 0.015 * k, -1.0
                msg.pose.orientation.w = 1.0
                bag.write("/mavros/local_position/pose", msg, msg.header.stamp)
        return path

    def test_1_relative_bag_replays_records_outside_the_source_tree_and_ends_cleanly(self):
        data_before = sorted(os.listdir(DATA))
        relative = os.path.relpath(os.path.join(DATA, BAG), self.cwd)
        self.assertFalse(os.path.isabs(relative))
        code, output = self.roslaunch("bag:=" + relative, "rate:=%g" % RATE)

        self.assertEqual(code, 0, output)
        self.assertNotIn("REQUIRED process", output)
        self.assertNotIn("has died", output)
        self.assertIn("all processes on machine have died, roslaunch will exit", output)  # it ended by itself
        # Its last line says what was played and what the node made of it: a clean dive, nothing refused.
        self.assertRegex(output, r"replay: done: \d+ poses of /rov_pose played; by its last /diagnostics the node "
                                 r"took \d+ and refused 0; recorded ")
        self.assertEqual(sorted(os.listdir(DATA)), data_before, "nothing written into test/data")
        recorded = os.path.join(self.ros_home, "replay", "straight_excursion.tether.bag")
        self.assertTrue(os.path.isfile(recorded), output)

        with rosbag.Bag(os.path.join(DATA, BAG)) as bag:
            played = [m.header.stamp.to_sec() for _, m, _ in bag.read_messages(["/rov_pose"])]
        with rosbag.Bag(recorded) as bag:
            poses = [m.header.stamp.to_sec() for _, m, _ in bag.read_messages(["/rov_pose"])]
            states = [m.header.stamp.to_sec() for _, m, _ in bag.read_messages(["/tether_node/state"])]
        self.assertEqual(len(poses), len(played), "the recorder was subscribed before the first pose")
        # The last /clock rosbag play publishes may be one tick (100 Hz wall: RATE / 100 s of bag time) before
        # the last pose; the physics timer (physics_rate) runs interpolation_delay behind that clock, and
        # ~state is published on a grid of 1 / state_rate. So the last state is at most their sum before the
        # last pose.
        with open(os.path.join(PACKAGE, "config", "node.yaml")) as f:
            node = yaml.safe_load(f)
        lag = RATE / 100.0 + 1.0 / node["physics_rate"] + node["interpolation_delay"] + 1.0 / node["state_rate"]
        print("[ measured ] %d poses and %d states recorded; last state %.3f s before the last pose (bound %.3f s)"
              % (len(poses), len(states), played[-1] - states[-1], lag))
        self.assertGreaterEqual(states[-1], played[-1] - lag)

    def test_2_missing_bag_is_named(self):
        code, output = self.roslaunch("bag:=no_such_dive.bag")
        print("[ measured ] roslaunch exit code %d for a missing bag (roslaunch exits 0 whatever its nodes do)"
              % code)
        self.assertIn("no bag at %s" % os.path.join(self.cwd, "no_such_dive.bag"), output)
        self.assertIn("all processes on machine have died, roslaunch will exit", output)
        self.assertFalse(os.path.exists(os.path.join(self.ros_home, "replay")), "nothing recorded")


    def test_3_a_mavros_bag_in_map_replays(self):
        self.write_mavros_bag()
        code, output = self.roslaunch("bag:=mavros_dive.bag", "pose_topic:=/mavros/local_position/pose",
                                      "rate:=%g" % RATE, "output:=out.bag",
                                      command=("rosrun", "rov_tether", "replay.sh"))
        self.assertEqual(code, 0, output)
        self.assertIn("taking world as map", output)
        with rosbag.Bag(os.path.join(self.cwd, "out.bag")) as bag:
            attached = [m.vehicle_attached for _, m, _ in bag.read_messages(["/tether_node/state"])]
        print("[ measured ] %d states, %d with the vehicle attached" % (len(attached), sum(attached)))
        self.assertGreater(sum(attached), 0.5 * len(attached), "the vehicle is attached for most of the dive")

    def test_4_a_replay_that_takes_no_pose_fails_and_says_why(self):
        self.write_mavros_bag()
        overrides = os.path.join(self.cwd, "strict.yaml")
        with open(overrides, "w") as f:
            f.write("world_frame_from_pose: false\n")
        code, output = self.roslaunch("bag:=mavros_dive.bag", "pose_topic:=/mavros/local_position/pose",
                                      "rate:=%g" % RATE, "overrides:=" + overrides,
                                      command=("rosrun", "rov_tether", "replay.sh"))
        self.assertEqual(code, 1, output)
        self.assertIn("no pose was taken: 201 poses of /mavros/local_position/pose played", output)
        self.assertNotIn("replay: done", output)
        self.assertIn("set world_frame to 'map'", output)  # the node's warning says what to do

    def test_5_an_odometry_bag_replays(self):
        odometry = self.odometry_class()
        with rosbag.Bag(os.path.join(self.cwd, "ekf_dive.bag"), "w") as bag:
            for k in range(201):
                msg = odometry()
                msg.header.stamp = rospy.Time.from_sec(1000.0 + 0.05 * k)
                msg.header.frame_id = "world"
                msg.child_frame_id = "base_link"
                msg.pose.pose.position.x, msg.pose.pose.position.z = 1.5 + 0.015 * k, -1.0
                msg.pose.pose.orientation.w = 1.0
                bag.write("/odometry/filtered", msg, msg.header.stamp)
        # Recorded into a directory: the default name inside it (it was recorded as results.bag beside it).
        os.makedirs(os.path.join(self.cwd, "results"))
        code, output = self.roslaunch("bag:=ekf_dive.bag", "pose_topic:=/odometry/filtered", "rate:=%g" % RATE,
                                      "output:=results", command=("rosrun", "rov_tether", "replay.sh"))
        self.assertEqual(code, 0, output)
        with rosbag.Bag(os.path.join(self.cwd, "results", "ekf_dive.tether.bag")) as bag:
            attached = [m.vehicle_attached for _, m, _ in bag.read_messages(["/tether_node/state"])]
        print("[ measured ] Odometry: %d states, %d with the vehicle attached" % (len(attached), sum(attached)))
        self.assertGreater(sum(attached), 0.5 * len(attached), "the vehicle is attached for most of the dive")

    def test_6_bad_arguments_are_refused_and_the_launch_ends(self):
        # Each is refused naming what is wrong, replay.sh exits 1, and the launch ends by itself (the test's
        # timeout would stop one that hung). Before: rate:=fast crashed the player before it could stop the node
        # (the launch never ended); rate:=0 was handed to rosbag play, which failed, and the replay blamed the
        # node; a file that is not a bag ended in a traceback and "ended without a result"; output:=<the bag
        # without .bag> passed the overwrite check, and rosbag record, adding .bag, recorded over the dive.
        shutil.copy(os.path.join(DATA, BAG), self.cwd)
        size = os.path.getsize(os.path.join(self.cwd, BAG))
        with open(os.path.join(self.cwd, "broken.bag"), "w") as f:
            f.write("not a bag\n")
        for args, said in [(("bag:=" + BAG, "rate:=fast"), "rate:=fast: must be a number > 0"),
                           (("bag:=" + BAG, "rate:=0"), "rate:=0: must be a number > 0"),
                           (("bag:=broken.bag",), "broken.bag cannot be read as a bag"),
                           (("bag:=" + BAG, "output:=" + BAG[:-len(".bag")]),
                            "would overwrite the bag being played")]:
            code, output = self.roslaunch(*args, command=("rosrun", "rov_tether", "replay.sh"))
            self.assertEqual(code, 1, output)
            self.assertIn(said, output)
            self.assertNotIn("Traceback", output)
        self.assertEqual(os.path.getsize(os.path.join(self.cwd, BAG)), size, "the dive's bag is untouched")


if __name__ == "__main__":
    rostest.rosrun("rov_tether", "replay_launch", ReplayLaunch)
