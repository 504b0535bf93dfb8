#!/usr/bin/env python3
"""rostest (test/ros/launch_params.test): launch files start their nodes from a clean private namespace.

On a master that is still running, tethers.launch leaves ~tethers and the per-tether maps behind, and an
overrides file leaves its keys. The test puts exactly those on the master (what `tethers.launch` and
`tether.launch overrides:=config/demo.yaml` load), plus a misspelt key, then starts a plain
`roslaunch rov_tether tether.launch` against the same master. With clear_params="true" the node must
simulate one tether (publishing ~state, not ~t0/state), with default.yaml's cable, and report no typo.

An overrides file wins over the launch's own frame arguments (`world_frame` included), as its name says, and an
argument given on the command line wins over the file (the pose topic too).
A key given twice in a file the launch loads stops the node, naming the file, the key and its lines.

A second launch checks that tether_node's start-up INFO line reaches a piped stdout while the node runs
(stdout is line-buffered), not only at exit.
"""
import glob
import os
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import unittest

import rospkg
import rospy
import rostest
import yaml

from rov_tether.msg import TetherState

NODE = "/tether_node"
TIMEOUT = 30.0  # [s] start-up of roslaunch and the node; under 3 s on an idle machine


class Output:
    """Collects the lines of one pipe in a thread."""

    def __init__(self, pipe):
        self.lines = []
        self.thread = threading.Thread(target=self._read, args=(pipe,), daemon=True)
        self.thread.start()

    def _read(self, pipe):
        for line in iter(pipe.readline, ""):
            self.lines.append(line)

    def text(self):
        return "".join(self.lines)


def wait_for(condition, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.05)
    return condition()


class LaunchParams(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("launch_params_test")
        cls.package = rospkg.RosPack().get_path("rov_tether")

    def load(self, name):
        with open(os.path.join(self.package, "config", name)) as f:
            return yaml.safe_load(f)

    def scratch_file(self, name, text):
        """A file `name` holding `text` in a directory of its own, removed after the test; its path."""
        scratch = tempfile.mkdtemp(prefix="launch_params_")
        self.addCleanup(shutil.rmtree, scratch, True)
        path = os.path.join(scratch, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def run_tether_launch(self, launch_file="tether.launch", arguments=(), state_topic=NODE + "/state"):
        """Runs `roslaunch rov_tether tether.launch` (or `launch_file` with `arguments`) against this master with
        stdout and stderr piped, until the node publishes `state_topic`. Returns (the first state, the private
        parameters, the published topics, whether the start-up INFO line was on stdout while the node ran, all
        output)."""
        launch = subprocess.Popen(["roslaunch", "rov_tether", launch_file] + list(arguments), stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True, start_new_session=True)
        stdout, stderr = Output(launch.stdout), Output(launch.stderr)
        try:
            state = rospy.wait_for_message(state_topic, TetherState, timeout=TIMEOUT)
            # The INFO line is logged in the node's constructor, before the first ~state; 5 s is for the
            # reader thread on a loaded machine.
            started = wait_for(lambda: "m cable in" in stdout.text(), 5.0)
            self.assertIsNone(launch.poll(), "the node is still running")
            topics = [name for name, _ in rospy.get_published_topics()]
            parameters = rospy.get_param(NODE)
        finally:
            os.killpg(launch.pid, signal.SIGINT)
            try:
                launch.wait(timeout=30.0)
            except subprocess.TimeoutExpired:
                os.killpg(launch.pid, signal.SIGKILL)
                launch.wait()
            stdout.thread.join(5.0)
            stderr.thread.join(5.0)
        return state, parameters, topics, started, stdout.text() + stderr.text()

    def test_1_tether_launch_after_tethers_launch_starts_one_tether(self):
        # What earlier launches left in ~: tethers.launch's list and maps, demo.yaml's overrides, a typo.
        for key, value in self.load("eight_tethers.yaml").items():
            rospy.set_param(NODE + "/" + key, value)
        for key, value in self.load("demo.yaml").items():
            rospy.set_param(NODE + "/" + key, value)
        rospy.set_param(NODE + "/iteratoins", 3)
        self.assertTrue(rospy.has_param(NODE + "/tethers"))

        state, parameters, topics, _, output = self.run_tether_launch()
        self.assertNotIn(NODE + "/t0/state", topics, "eight tethers were started")
        self.assertNotIn("tethers", parameters)
        self.assertNotIn("iteratoins", parameters)
        # default.yaml's cable and node.yaml's attachment, not demo.yaml's 20 m cable and 0.3 m offset.
        self.assertEqual(state.cable_length, self.load("default.yaml")["cable_length"])
        self.assertEqual(parameters["cable_length"], self.load("default.yaml")["cable_length"])
        self.assertEqual(parameters["attachment_offset"], self.load("node.yaml")["attachment_offset"])
        self.assertNotIn("unknown parameters", output, "a leftover key was reported as a typo")

    def test_2_startup_line_reaches_a_piped_stdout_while_the_node_runs(self):
        _, _, _, started, output = self.run_tether_launch()
        self.assertTrue(started, "start-up INFO line on the piped stdout while the node runs:\n" + output)

    def test_3_an_overrides_file_sets_the_frames(self):
        # Item 2 of issue 26: tether.launch set world_frame from its argument after loading the overrides,
        # so the file's world_frame was silently replaced by "world".
        overrides = self.scratch_file("mine.yaml", "world_frame: map\nrov_frame: base_link\ncable_length: 30.0\n")
        dumped = subprocess.run(["roslaunch", "--dump-params", "rov_tether", "tether.launch",
                                 "overrides:=" + overrides], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, timeout=TIMEOUT)
        self.assertEqual(dumped.returncode, 0, dumped.stderr)
        parameters = yaml.safe_load(dumped.stdout)
        self.assertEqual(parameters[NODE + "/world_frame"], "map")
        self.assertEqual(parameters[NODE + "/rov_frame"], "base_link")
        self.assertEqual(parameters[NODE + "/cable_length"], 30.0)
        # Without an overrides file, the arguments set the frames.
        dumped = subprocess.run(["roslaunch", "--dump-params", "rov_tether", "tether.launch", "world_frame:=odom"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=TIMEOUT)
        self.assertEqual(yaml.safe_load(dumped.stdout)[NODE + "/world_frame"], "odom", dumped.stderr)

    def test_3b_a_pose_topic_argument_wins_over_the_overrides_file(self):
        # tether.launch applied its pose_topic argument as a remap of rov_pose, which an overrides file's pose_topic
        # (the live stack's topic) bypassed: `replay.launch pose_topic:=/rov_pose overrides:=live.yaml` listened to
        # the live topic and never got the bag's poses. The argument is now the parameter, like the frames'.
        overrides = self.scratch_file("live.yaml", "pose_topic: /live_stack/pose\n")
        for arguments, expected in ((["pose_topic:=/from_arg/pose"], "/from_arg/pose"), ([], "/live_stack/pose")):
            dumped = subprocess.run(["roslaunch", "--dump-params", "rov_tether", "tether.launch",
                                     "overrides:=" + overrides] + arguments, stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True, timeout=TIMEOUT)
            self.assertEqual(dumped.returncode, 0, dumped.stderr)
            self.assertEqual(yaml.safe_load(dumped.stdout)[NODE + "/pose_topic"], expected, arguments)
        dumped = subprocess.run(["roslaunch", "--dump-params", "rov_tether", "replay.launch", "bag:=x.bag",
                                 "pose_topic:=/rov_pose", "overrides:=" + overrides], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, timeout=TIMEOUT)
        self.assertEqual(dumped.returncode, 0, dumped.stderr)
        self.assertEqual(yaml.safe_load(dumped.stdout)[NODE + "/pose_topic"], "/rov_pose")

    def test_4_a_key_given_twice_in_a_loaded_file_stops_the_node(self):
        # roslaunch keeps the last of a repeated key without a word; tether.launch lists the files it loaded in
        # ~param_files and the node refuses to start, naming the file, the key and its lines.
        overrides = self.scratch_file("twice.yaml", "cable_length: 30.0\niterations: 3\ncable_length: 40.0\n")
        launch = subprocess.run(["roslaunch", "rov_tether", "tether.launch", "overrides:=" + overrides],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT + 30.0)
        self.assertIn("param_files: " + overrides + ": duplicate key 'cable_length' (lines 1 and 3)", launch.stdout)
        self.assertIn("REQUIRED process [tether_node", launch.stdout, "the launch ends with the node")
        # A relative path, from where roslaunch starts (a shell's cd sets PWD too): roslaunch reads it from
        # there, and so does the node, which itself runs in ROS_HOME.
        scratch = os.path.dirname(overrides)
        launch = subprocess.run(["roslaunch", "rov_tether", "tether.launch", "overrides:=twice.yaml"], cwd=scratch,
                                env=dict(os.environ, PWD=scratch), stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, timeout=TIMEOUT + 30.0)
        self.assertIn("param_files: " + overrides + ": duplicate key 'cable_length' (lines 1 and 3)", launch.stdout)

    def test_5_rosrun_finds_each_helper_node_once(self):
        # The package is the repository root and holds its build directory: rosrun found the source, the devel
        # relay, catkin's install copy and its configure scratch copy of each Python node, and asked which
        # (without a terminal: "exec: : not found"). Only a devel space's relay is executable now; with one
        # build (the sanitizer stage of scripts/test.sh adds a second, whose relays rosrun also finds), rosrun
        # runs it.
        devels = sorted(glob.glob(os.path.join(self.package, "*", "devel", "lib", "rov_tether")))
        for script in ("simulated_rov.py", "vehicle_sim.py", "tether_summary.py", "replay_bag.py"):
            executables = sorted(os.path.join(folder, script) for folder, _, files in
                                 os.walk(self.package, followlinks=True)
                                 if script in files and os.access(os.path.join(folder, script), os.X_OK))
            self.assertEqual(executables, [os.path.join(d, script) for d in devels])
            if len(devels) != 1:
                continue
            run = subprocess.Popen(["rosrun", "rov_tether", script, "__name:=rosrun_check"], stdin=subprocess.DEVNULL,
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                   start_new_session=True)
            output = Output(run.stdout)
            # The node registers with the master once rosrun has started it (replay_bag.py then stops: no ~bag).
            wait_for(lambda: "rosrun_check" in "".join(rosnode_names()) or run.poll() is not None, 15.0)
            for stop in (signal.SIGINT, signal.SIGKILL):  # SIGINT during rospy's start-up can go unheard
                try:
                    os.killpg(run.pid, stop)
                    run.wait(timeout=10.0)
                    break
                except ProcessLookupError:
                    break
                except subprocess.TimeoutExpired:
                    continue
            output.thread.join(5.0)
            self.assertNotIn("non-unique executable", output.text(), script)
            self.assertNotIn("not found", output.text(), script)
            self.assertNotIn("Couldn't find executable", output.text(), script)

    def test_6_a_tethers_map_that_tethers_does_not_list_is_reported(self):
        # Several tethers: a map that `tethers` does not list makes no tether, and the shared keys beside the maps
        # (a typo here) were not checked at all; both were ignored without a word. The node warns of both, as it
        # warns of unknown keys with one tether.
        tethers = self.scratch_file("two.yaml", "tethers: [a]\na: {pose_topic: rov_a/pose}\n"
                                                "b: {pose_topic: rov_b/pose, spool_position: [4, 0, 0]}\niteratons: 3\n")
        _, _, topics, _, output = self.run_tether_launch("tethers.launch", ["tethers:=" + tethers],
                                                         NODE + "/a/state")
        self.assertNotIn(NODE + "/b/state", topics)
        self.assertIn("ignoring unknown parameters in " + NODE + " (typos?): b (a map of parameters that `tethers` "
                      "does not list: add it there to simulate it as a tether), iteratons (did you mean iterations?)",
                      output)


def rosnode_names():
    """The nodes registered with the master."""
    import rosnode
    return rosnode.get_node_names()

if __name__ == "__main__":
    rostest.rosrun("rov_tether", "launch_params", LaunchParams)
