#!/usr/bin/env python3
"""Checks of what the demo prints (issue 26, item 17), with no build and no ROS master (run by
scripts/test.sh; JUnit XML with --gtest_output=xml:FILE):

- scripts/demo.sh's filter, run exactly as demo.sh runs it, on roslaunch's real output of the demo
  (test/data/roslaunch_demo_output.txt: `roslaunch rov_tether demo.launch rviz:=false summary_duration:=4`
  captured byte for byte, escapes included, its PARAMETERS list cut short): no terminal escape, no line of
  roslaunch's SUMMARY block (CLEAR PARAMETERS, PARAMETERS, NODES and their lists) and no start-up or
  shut-down chatter get through; every line of the nodes does, and so does the end of a node that crashes;
- with several tethers, each summary reads its own tether's /diagnostics status, not the last one whose name
  ends in "tether";
- the summary line (scripts/tether_summary.py) before /diagnostics has measured the real-time factor says so
  instead of printing "physics nanx real time" (the pillar demo's first line) or "0x" (the demo's);
- demo.sh describes the cable's colours as the README and tensionColor do (light blue, lighter stripes),
  with the demo's own full scale;
- the shipped rviz configs show the colour legend (~legend) and draw tf frames without their names, which
  covered the spool and the cable's label (issue 26, item 16).
"""
import importlib.util
import math
import os
import pathlib
import re
import subprocess
import types
import unittest

import yaml

import rosunit

ROOT = pathlib.Path(__file__).resolve().parent.parent
SAMPLE = ROOT / "test" / "data" / "roslaunch_demo_output.txt"

# roslaunch's end of a node that crashed (roslaunch/pmon.py and launch.py write these, in red): a required
# one between two rules of '=', then a node that is not required.
CRASH = ("\x1b[31m" + "=" * 80 + "REQUIRED process [tether_node-2] has died!\n"
         "process has died [pid 23586, exit code -11, cmd /opt/rov_tether/tether_node __name:=tether_node].\n"
         "log file: /root/.ros/log/run/tether_node-2*.log\n"
         "Initiating shutdown!\n" + "=" * 80 + "\x1b[0m\n"
         "\x1b[31m[simulated_rov-3] process has died [pid 23590, exit code 1, cmd simulated_rov.py].\x1b[0m\n")


def demo_filter():
    """The command demo.sh pipes roslaunch's output through (the lines after `roslaunch ... |`)."""
    script = (ROOT / "scripts" / "demo.sh").read_text()
    match = re.search(r"^roslaunch rov_tether demo\.launch[^\n]*\|\n((?:[ \t]+[^\n]*\n)+)", script, re.M)
    assert match, "demo.sh: no roslaunch pipeline found"
    return match.group(1).strip().rstrip("\\")


def run_filter(text):
    env = dict(os.environ, ROOT=str(ROOT))
    return subprocess.run(["bash", "-c", demo_filter()], input=text, capture_output=True, text=True, env=env,
                          check=True).stdout


def load_summary():
    spec = importlib.util.spec_from_file_location("tether_summary", ROOT / "scripts" / "tether_summary.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class DemoOutput(unittest.TestCase):
    def test_only_what_the_nodes_say_gets_through(self):
        sample = SAMPLE.read_text()
        shown = run_filter(sample)
        lines = shown.splitlines()
        self.assertNotIn("\x1b", shown, "a terminal escape got through")
        self.assertNotIn("\x07", shown, "a terminal escape got through")
        for chatter in ["CLEAR PARAMETERS", "PARAMETERS", "NODES", "SUMMARY", " * /", "(rov_tether/",
                        "logging to", "log directory", "Ctrl-C", "roslaunch server", "master", "pid",
                        "run_id", "core service", "killing", "shutting down", "has died", "cleanly",
                        "log file", "Initiating shutdown", "===="]:
            self.assertFalse([l for l in lines if chatter in l], "%r got through:\n%s" % (chatter, shown))
        self.assertNotIn("done", lines)
        self.assertFalse([l for l in lines if not l.strip()], "blank lines got through")
        # Every line a node wrote is there, in order.
        said = [l for l in (re.sub(r"\x1b\[[0-9;]*m", "", s) for s in sample.splitlines())
                if re.match(r"(\[ (INFO|WARN)\]|t +\d|waiting for)", l)]
        self.assertEqual(len(said), 7)
        self.assertEqual(lines, said)

    def test_a_crashed_node_still_shows(self):
        shown = run_filter(SAMPLE.read_text().replace("\x1b[31m" + "=" * 80, CRASH + "\x1b[31m" + "=" * 80, 1))
        self.assertIn("REQUIRED process [tether_node-2] has died!", shown)
        self.assertIn("exit code -11", shown)
        self.assertIn("log file: /root/.ros/log/run/tether_node-2*.log", shown)
        self.assertIn("[simulated_rov-3] process has died [pid 23590, exit code 1", shown)
        self.assertNotIn("tether_summary-4", shown)  # the summary's end is the demo's end

    def test_the_summary_says_when_the_real_time_factor_is_not_measured_yet(self):
        summary = load_summary()
        state = types.SimpleNamespace(deployed_length=2.0, cable_length=20.0, tension_vehicle=-0.09,
                                      max_tension=0.44, winch_mode="brake", winch_speed=0.0)
        for rtf in [float("nan"), math.inf, 0.0]:  # 0: the demo's first line, before the first pose
            line = summary.summary_line(0.0, state, rtf, "")
            self.assertNotIn("nan", line.lower())
            self.assertNotIn("inf", line.lower())
            self.assertIn("physics  not yet measured |", line)
            self.assertNotIn(" 0x", line)
        measured = summary.summary_line(1.0, state, 419.4, "tether simulated")
        self.assertIn("| physics    419x real time | tether simulated", measured)
        # The columns stay where they were: the fields after it start at the same place.
        self.assertEqual(line.index(" | ", line.index("physics")), measured.index(" | ", measured.index("physics")))

    def test_each_summary_reads_its_own_tethers_diagnostics(self):
        # Two tethers (tms_demo.launch): the statuses "tether_node: tether umbilical" and "tether_node: tether
        # tether". Matched by the name's end, the umbilical's summary showed the other tether's warning and
        # real-time factor. Each summary now takes the status its state topic names.
        # The status is named after the node's full name (namespace included), so a node in a namespace is
        # found too (an exact match on the topic's last parts missed it).
        summary = load_summary()
        self.assertIn("tether_node: tether umbilical", summary.diagnostics_name("/tether_node/umbilical/state"))
        self.assertIn("tether_node: tether", summary.diagnostics_name("/tether_node/state"))
        self.assertIn("ns/tether_node: tether", summary.diagnostics_name("/ns/tether_node/state"))
        self.assertIn("ns/tether_node: tether umbilical", summary.diagnostics_name("/ns/tether_node/umbilical/state"))
        self.assertNotIn("tether_node: tether tether", summary.diagnostics_name("/tether_node/umbilical/state"))
        statuses = [types.SimpleNamespace(name="tether_node: tether umbilical", message="tether simulated",
                                          values=[types.SimpleNamespace(key="physics real-time factor",
                                                                        value="65.8")]),
                    types.SimpleNamespace(name="tether_node: tether tether", message="thrust held at thrust_limit",
                                          values=[types.SimpleNamespace(key="physics real-time factor",
                                                                        value="137")])]
        summary.on_diagnostics(types.SimpleNamespace(status=statuses),
                               summary.diagnostics_name("/tether_node/umbilical/state"))
        self.assertEqual((summary.latest["diag"], summary.latest["rtf"]), ("tether simulated", 65.8))

    def test_demo_describes_the_colours_rviz_shows(self):
        script = (ROOT / "scripts" / "demo.sh").read_text()
        readme = (ROOT / "README.md").read_text()
        self.assertIn("light blue 0 N to red at `tension_full_scale`) with lighter stripes", readme)
        self.assertIn("light blue 0 N", script)
        self.assertIn("lighter stripes", script)
        self.assertNotIn("darker", script)
        self.assertIn("tension_full_scale", script)  # red at the demo's own full scale, not a fixed 50 N

    def test_rviz_configs_show_the_legend_and_no_tf_names(self):
        configs = sorted((ROOT / "config").glob("*.rviz"))
        self.assertTrue(configs)
        for config in configs:
            displays = yaml.safe_load(config.read_text())["Visualization Manager"]["Displays"]
            # /tether_node/legend, or a tether's of several (/tether_node/<name>/legend: tms_demo.rviz)
            legends = [d for d in displays if d["Class"] == "rviz/Image"
                       and re.fullmatch(r"/tether_node/(\w+/)?legend", d["Image Topic"])]
            self.assertEqual(len(legends), 1, "%s: no Image display of a tether's legend" % config.name)
            self.assertTrue(legends[0]["Enabled"], config.name)
            for tf in (d for d in displays if d["Class"] == "rviz/TF"):
                self.assertFalse(tf["Show Names"], "%s: tf names cover the spool and the label" % config.name)


if __name__ == "__main__":
    rosunit.unitrun("rov_tether", "check_demo_output", DemoOutput)
