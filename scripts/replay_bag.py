#!/usr/bin/env python3
"""Plays a recorded dive into tether_node and records the tether's state next to the poses; started by
launch/replay.launch (see README, "Replaying your own dives", and docs/node.md).

1. Resolves ~bag: `~` is the home directory, a relative path is relative to the directory roslaunch was
   started in (roslaunch runs its nodes in ROS_HOME; its own working directory is read from /proc, else
   ~caller_cwd, the launch's $PWD, is used). A missing bag is a clear error.
2. With ~record, starts `rosbag record -O OUTPUT` on ~topics. OUTPUT is ~output resolved the same way, or,
   when empty, $ROS_HOME/replay/<bag name>.tether.bag (ROS_HOME defaults to ~/.ros), never the source tree.
3. Checks that the bag holds ~pose_topic as geometry_msgs/PoseStamped or nav_msgs/Odometry (the node takes
   either), naming the bag's topics when not. Waits until the recorder and ~tether_node subscribe, then
   runs `rosbag play --clock -d 1 -r ~rate BAG` (quiet: no progress line).
4. When the bag has played and the node has gone quiet, stops the recorder (the bag is closed) and asks
   ~tether_node to shut down (SIGINT), so every process of the launch ends and roslaunch exits by itself.

5. A replay in which the node took no pose (every ~state without a vehicle attached) is a failure: the
   node's count of refused poses is read from /diagnostics and said, with where the reasons are. A replay
   that ends well says the poses played and the node's counts of poses taken and refused (a warning when
   it refused some).

Exits 1, after stopping the rest, when the bag is missing or holds no poses, no pose was taken, the node
or a rosbag process fails. roslaunch itself exits 0 whatever its nodes do: `rosrun rov_tether replay.sh
ARGS` runs replay.launch and exits with this script's code, which it writes into ~result_file.
"""
import math
import os
import signal
import subprocess
import sys
import time
import xmlrpc.client

import rosgraph
import rospkg
import rosbag
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from rov_tether.msg import TetherState

STARTUP_TIMEOUT = 60.0  # [s] for the recorder and the node to subscribe (a few seconds on a busy machine)
QUIET = 0.5  # [s] without a new ~state after the bag ends: the node has published its last state
QUIET_TIMEOUT = 10.0  # [s] the longest wait for that quiet
STOP_TIMEOUT = 30.0  # [s] for rosbag record to close its bag after SIGINT
INTERRUPT_GRACE = 2.0  # [s] between roslaunch stopping the node and this process on Ctrl-C (well under 1 s)
POSE_TYPES = ("geometry_msgs/PoseStamped", "nav_msgs/Odometry")  # what tether_node takes on its pose topic


class Interrupted(Exception):
    """Ctrl-C during the replay."""


def resolve(path, caller_cwd):
    """Absolute path of a path given on roslaunch's command line."""
    path = os.path.expanduser(path)
    if os.path.isabs(path):
        return os.path.normpath(path)
    if not caller_cwd:
        raise ValueError("'%s' is relative and the caller's directory is unknown ($PWD is not set): "
                         "give an absolute path" % path)
    return os.path.normpath(os.path.join(caller_cwd, path))


def caller_directory():
    """The directory roslaunch was started in: the working directory of roslaunch, this node's parent
    (roslaunch starts nodes in ROS_HOME but stays where it was started), else ~caller_cwd ($PWD)."""
    try:
        with open("/proc/%d/cmdline" % os.getppid(), "rb") as f:
            if b"roslaunch" in f.read():
                return os.readlink("/proc/%d/cwd" % os.getppid())
    except OSError:
        pass
    return rospy.get_param("~caller_cwd", "")


def default_output(bag):
    """$ROS_HOME/replay/<bag name without .bag>.tether.bag"""
    name = os.path.basename(bag)
    if name.endswith(".bag"):
        name = name[:-len(".bag")]
    return os.path.join(rospkg.get_ros_home(), "replay", name + ".tether.bag")


class Replay:
    def __init__(self):
        self.caller_cwd = caller_directory()
        self.bag_arg = rospy.get_param("~bag", "")
        self.rate_arg = rospy.get_param("~rate", 1.0)  # checked in run(), so finish() runs after a refusal
        self.record = bool(rospy.get_param("~record", True))
        self.output_arg = rospy.get_param("~output", "")
        self.result_file = rospy.get_param("~result_file", "")  # the exit code goes here too (replay.sh)
        self.node = rospy.resolve_name(rospy.get_param("~tether_node", "/tether_node"))
        self.pose_topic = rospy.resolve_name(rospy.get_param("~pose_topic", "/rov_pose"))
        self.topics = [self.pose_topic, self.node + "/state", self.node + "/wrench"]
        self.master = rosgraph.Master(rospy.get_name())
        self.recorder_name = rospy.get_name() + "_recorder"  # in the namespace of this node, as rosbag is
        self.last_state = time.monotonic()
        self.states = 0
        self.attached_states = 0
        self.diagnostics = {}  # the node's last /diagnostics values, by key
        self.children = []

    def subscribed(self, node, topics):
        """True when node subscribes to every topic in topics (as the master sees it)."""
        _, subscriptions, _ = self.master.getSystemState()
        subscribers = dict(subscriptions)
        return all(node in subscribers.get(topic, []) for topic in topics)

    def node_alive(self):
        try:
            self.master.lookupNode(self.node)
            return True
        except rosgraph.MasterError:
            return False

    def wait_until(self, condition, timeout, what):
        end = time.monotonic() + timeout
        while not condition():
            if rospy.is_shutdown():
                raise RuntimeError("shut down while waiting for %s" % what)
            if time.monotonic() > end:
                raise RuntimeError("%s did not happen within %.0f s" % (what, timeout))
            time.sleep(0.05)

    def on_state(self, state):
        self.last_state = time.monotonic()
        self.states += 1
        self.attached_states += 1 if state.vehicle_attached else 0

    def on_diagnostics(self, array):
        node = self.node.rsplit("/", 1)[-1]
        for status in array.status:
            if node in status.name:
                self.diagnostics.update({value.key: value.value for value in status.values})

    def check_bag(self, bag):
        """The number of poses the bag holds on ~pose_topic; an error naming what it holds instead."""
        try:
            with rosbag.Bag(bag) as recorded:
                topics = recorded.get_type_and_topic_info().topics
        except (rosbag.ROSBagException, OSError) as e:
            raise RuntimeError("%s cannot be read as a bag (%s; an unindexed bag: rosbag reindex)" % (bag, e))
        if self.pose_topic not in topics:
            raise RuntimeError("%s holds no %s; its topics: %s (set pose_topic:=...)" % (
                bag, self.pose_topic, ", ".join("%s (%s)" % (name, info.msg_type)
                                                 for name, info in sorted(topics.items())) or "none"))
        info = topics[self.pose_topic]
        if info.msg_type not in POSE_TYPES:
            raise RuntimeError("%s in %s is %s: tether_node takes %s" % (self.pose_topic, bag, info.msg_type,
                                                                        " or ".join(POSE_TYPES)))
        return info.message_count

    def check_poses_taken(self, poses):
        """Raises when the node took none of the `poses` played."""
        if self.attached_states > 0:
            return
        raise RuntimeError(
            "no pose was taken: %d poses of %s played, the node refused %s (poses taken: %s); %d states, none "
            "with the vehicle attached. tether_node's warnings above say why (frame: set world_frame:=<the "
            "poses' frame>; stamps; numbers)" % (
                poses, self.pose_topic, self.diagnostics.get("rejected poses", "an unknown number"),
                self.diagnostics.get("poses taken", "unknown"), self.states))

    @staticmethod
    def rate_of(value):
        """~rate as a number > 0 (rosbag play fails on 0, and plays everything at once below it)."""
        try:
            rate = float(value)
        except (TypeError, ValueError):
            rate = float("nan")
        if not math.isfinite(rate) or rate <= 0.0:
            raise ValueError("rate:=%s: must be a number > 0 (the playback's speed-up)" % value)
        return rate

    def run(self):
        self.rate = self.rate_of(self.rate_arg)
        if not self.bag_arg:
            raise ValueError("no bag given: bag:=<the dive's bag>")
        bag = resolve(self.bag_arg, self.caller_cwd)
        if not os.path.isfile(bag):
            raise RuntimeError("no bag at %s (bag:=%s, relative paths are relative to %s)"
                               % (bag, self.bag_arg, self.caller_cwd or "nothing: $PWD is not set"))
        output = resolve(self.output_arg, self.caller_cwd) if self.output_arg else default_output(bag)
        if self.output_arg and (os.path.isdir(output) or self.output_arg.endswith("/")):
            output = os.path.join(output, os.path.basename(default_output(bag)))  # a directory: the name in it
        if not output.endswith(".bag"):
            output += ".bag"  # as rosbag record -O names it
        if os.path.realpath(output) == os.path.realpath(bag):
            raise RuntimeError("output:=%s would overwrite the bag being played" % self.output_arg)
        poses = self.check_bag(bag)
        rospy.Subscriber(self.node + "/state", TetherState, self.on_state, queue_size=100)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=10)
        if self.record:
            os.makedirs(os.path.dirname(output), exist_ok=True)
            recorder = subprocess.Popen(["rosbag", "record", "-O", output,
                                         "__name:=" + self.recorder_name.rsplit("/", 1)[-1]]
                                        + self.topics)
            self.children.append(recorder)
            self.wait_until(lambda: recorder.poll() is not None or self.subscribed(self.recorder_name, self.topics),
                            STARTUP_TIMEOUT, "the recorder subscribing to " + ", ".join(self.topics))
            if recorder.poll() is not None:
                raise RuntimeError("rosbag record exited with code %d" % recorder.returncode)
        self.wait_until(lambda: self.subscribed(self.node, [self.pose_topic]), STARTUP_TIMEOUT,
                        "%s subscribing to %s" % (self.node, self.pose_topic))
        rospy.loginfo("replay: playing %s at %gx%s", bag, self.rate, ", recording into " + output if self.record
                      else "")
        player = subprocess.Popen(["rosbag", "play", "--quiet", "--clock", "-d", "1", "-r", str(self.rate), bag])
        self.children.append(player)
        while player.poll() is None and self.node_alive():
            time.sleep(0.2)
        if player.poll() is None:
            # The node has gone. On Ctrl-C roslaunch stops its nodes one after the other, so this process may
            # hear of it a moment later: wait for that before calling it a failure.
            end = time.monotonic() + INTERRUPT_GRACE
            while not rospy.is_shutdown() and time.monotonic() < end:
                time.sleep(0.05)
        if rospy.is_shutdown():  # Ctrl-C: the player and the recorder (which closed its bag) have stopped
            raise Interrupted("interrupted during the replay; the recording ends there")
        if player.poll() is None:
            raise RuntimeError("%s stopped during the replay" % self.node)
        if player.returncode != 0:
            raise RuntimeError("rosbag play exited with code %d" % player.returncode)
        # /clock stops with the bag, so the node publishes its last state at once; wait for it to arrive.
        self.wait_until(lambda: time.monotonic() - self.last_state > QUIET, QUIET_TIMEOUT,
                        "%s/state going quiet" % self.node)
        if self.record:
            self.stop(recorder)
            if recorder.returncode not in (0, -signal.SIGINT):
                raise RuntimeError("rosbag record exited with code %d" % recorder.returncode)
        self.check_poses_taken(poses)
        self.say_done(poses, output if self.record else None)

    def say_done(self, poses, output):
        """The replay's last line: what was played, and what the node took and refused by its last /diagnostics
        (published on the bag's clock, so up to a second of it before the end); a warning when it refused some."""
        recorded = ("; recorded " + output) if output else ""
        if "rejected poses" not in self.diagnostics:
            rospy.logwarn("replay: done: %d poses of %s played; no /diagnostics from the node came, so what it took "
                          "and refused is not known%s", poses, self.pose_topic, recorded)
            return
        refused = self.diagnostics["rejected poses"]
        line = "replay: done: %d poses of %s played; by its last /diagnostics the node took %s and refused %s%s" % (
            poses, self.pose_topic, self.diagnostics.get("poses taken", "?"), refused, recorded)
        if refused == "0":
            rospy.loginfo(line)
        else:
            rospy.logwarn(line + " (tether_node's warnings above say why)")

    @staticmethod
    def stop(process):
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()

    def finish(self):
        """Stops what is left and the tether node, so the launch ends."""
        for child in self.children:
            self.stop(child)
        # A node that has not registered yet (a slow start, say under a sanitizer, and a bag missing at
        # once) is waited for, or it would be left running and the launch would never end.
        end = time.monotonic() + STARTUP_TIMEOUT
        while not rospy.is_shutdown() and not self.node_alive() and time.monotonic() < end:
            time.sleep(0.1)
        if rospy.is_shutdown() or not self.node_alive():
            return  # roslaunch is stopping everything, or the node has gone
        try:
            # SIGINT, as Ctrl-C would: roscpp shuts down quietly (rosnode kill would log two warnings).
            pid = xmlrpc.client.ServerProxy(self.master.lookupNode(self.node)).getPid(rospy.get_name())[2]
            os.kill(pid, signal.SIGINT)
        except (rosgraph.MasterError, OSError, xmlrpc.client.Error) as e:
            rospy.logwarn("replay: could not stop %s (%s); stop the launch with Ctrl-C", self.node, e)


def main():
    rospy.init_node("replay")
    replay = Replay()
    code = 0
    try:
        replay.run()
    except Interrupted as e:
        rospy.logwarn("replay: %s", e)
        code = 1
    except (RuntimeError, ValueError) as e:
        rospy.logfatal("replay: %s", e)
        code = 1
    except Exception as e:  # anything unforeseen still ends the launch and says so
        rospy.logfatal("replay: failed: %s: %s", type(e).__name__, e)
        code = 1
    finally:
        replay.finish()
        if replay.result_file:
            with open(replay.result_file, "w") as f:
                f.write("%d\n" % code)
    sys.exit(code)


if __name__ == "__main__":
    main()
