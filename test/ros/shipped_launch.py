#!/usr/bin/env python3
"""rostest (test/ros/shipped_launch.test): every launch file in launch/ runs as a user starts it, without a
failure, a deprecation or an over-tension warning (issue 26, item 15; the scenarios have the same check in
test_core, ShippedFiles.EveryScenarioRunsWithoutFailuresOrWarnings).

Each file is started with roslaunch against this master for a while, with what it needs to do its work:
the demos (tms_demo.launch too) bring their own simulated ROV (rviz off: no display here); tether.launch
and tethers.launch get vehicle poses from this test, a few metres out from each spool; replay.launch
replays test/data/straight_excursion.bag, and ends by itself. A launch file missing from LAUNCHES fails the
test, so a new one cannot go unchecked.

What fails a launch file, from its output (roslaunch prints every node's log with output="screen") and from
/diagnostics while it runs: an ERROR or FATAL log other than the node saying the machine is too slow (a
skip ahead: the sanitizer build runs at a fraction of the speed; test/ros/overload.test checks that
path), a process that died, a Python traceback, "deprecated", and the diagnostics' over-tension, outrun
and simulation-failure warnings.
"""
import os
import re
import signal
import subprocess
import tempfile
import threading
import time
import unittest

import rospkg
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseStamped

PACKAGE = rospkg.RosPack().get_path("rov_tether")
BAG = os.path.join(PACKAGE, "test", "data", "straight_excursion.bag")  # 50 s of poses (scripts/make_test_bags.py)

# [s] how long each runs. The pillar demo's vehicle circles the pillar and passes the wreck in 44 s (its
# waypoints): the whole path, where a wrap would pull hardest. The demo dives out and turns in 26 s.
LAUNCHES = {
    "demo.launch": (["rviz:=false"], 30.0, None),
    "pillar_demo.launch": (["rviz:=false"], 48.0, None),
    "tether.launch": ([], 12.0, {"/rov_pose": (0.0, 0.0, 0.0)}),
    "tethers.launch": ([], 12.0, {"/rov%d/pose" % k: (4.0 * k, 0.0, 0.0) for k in range(8)}),
    "replay.launch": (["bag:=" + BAG, "rate:=5", "output:=replay_out.bag"], 60.0, None),  # ends by itself
    "tms_demo.launch": (["rviz:=false"], 30.0, None),  # the cage lowered 9 m, the ROV 12 m out
}
# An ERROR the node logs when the machine cannot keep up: a property of the machine, not of the launch file.
MACHINE_TOO_SLOW = re.compile(r"fell [0-9.]+ s behind real time|skipped ahead")
BAD_OUTPUT = [re.compile(p) for p in (r"\[ERROR\]", r"\[FATAL\]", r"has died", r"Traceback", r"(?i)deprecated")]
BAD_DIAGNOSTICS = re.compile(r"over-tension|outruns the winch|held at its stall pull|simulation failure|(?i:deprecated)")


class ShippedLaunchFiles(unittest.TestCase):
    def test_every_launch_file_runs_cleanly(self):
        launch_dir = os.path.join(PACKAGE, "launch")
        shipped = sorted(f for f in os.listdir(launch_dir) if f.endswith(".launch"))
        self.assertEqual(sorted(LAUNCHES), shipped, "every shipped launch file has an entry in LAUNCHES")
        diagnostics = []
        rospy.Subscriber("/diagnostics", DiagnosticArray,
                         lambda m: diagnostics.extend(s for s in m.status if s.name.startswith("tether_node")))
        failures = []
        for name in shipped:
            args, seconds, poses = LAUNCHES[name]
            del diagnostics[:]
            started = time.time()
            output = self.run_launch(name, args, seconds, poses)
            ran = time.time() - started
            bad = [line for line in output.splitlines()
                   if any(p.search(line) for p in BAD_OUTPUT) and not MACHINE_TOO_SLOW.search(line)]
            bad_diagnostics = sorted({s.message for s in list(diagnostics)
                                      if BAD_DIAGNOSTICS.search(s.message) or
                                      (s.level == DiagnosticStatus.ERROR and not MACHINE_TOO_SLOW.search(s.message)
                                       and "fell behind" not in s.message)})
            slow = sum(1 for line in output.splitlines() if MACHINE_TOO_SLOW.search(line))
            print("[ measured ] %s: ran %.0f s, %d diagnostics, %d output lines flagged, %d diagnostics flagged, "
                  "%d skip-ahead reports (machine too slow)"
                  % (name, ran, len(diagnostics), len(bad), len(bad_diagnostics), slow))
            self.assertGreater(len(diagnostics), 0, "%s: the node published no diagnostics:\n%s" % (name, output))
            if bad or bad_diagnostics:
                failures.append("%s:\n  %s" % (name, "\n  ".join(bad[:10] + bad_diagnostics[:10])))
        self.assertEqual(failures, [], "\n".join(failures))

    def run_launch(self, name, args, seconds, poses):
        """roslaunch rov_tether NAME ARGS for `seconds` (or until it ends), publishing `poses`; its output."""
        scratch = tempfile.mkdtemp(prefix="shipped_launch_")
        process = subprocess.Popen(["roslaunch", "rov_tether", name] + args, cwd=scratch,
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                   env=dict(os.environ, PWD=scratch), start_new_session=True)
        lines = []
        reader = threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True)
        reader.start()
        publishers = {topic: rospy.Publisher(topic, PoseStamped, queue_size=10) for topic in (poses or {})}
        end = time.time() + seconds
        while time.time() < end and process.poll() is None:
            for topic, spool in (poses or {}).items():
                msg = PoseStamped()
                msg.header.stamp = rospy.Time.now()
                msg.header.frame_id = "world"
                msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = spool[0] + 3.0, spool[1], -1.0
                msg.pose.orientation.w = 1.0
                publishers[topic].publish(msg)
            time.sleep(0.05)
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGINT)  # as Ctrl-C in the terminal
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
        for publisher in publishers.values():
            publisher.unregister()
        if rospy.has_param("/use_sim_time"):
            rospy.delete_param("/use_sim_time")  # replay.launch's: the next launch file runs on wall time
        reader.join(timeout=10)
        return "".join(lines)


if __name__ == "__main__":
    rospy.init_node("shipped_launch")
    rostest.rosrun("rov_tether", "shipped_launch", ShippedLaunchFiles)
