#!/usr/bin/env python3
"""Checks of the repository itself, with no build and no ROS master (run by scripts/test.sh; JUnit XML with
--gtest_output=xml:FILE, as rosunit writes it):

- every rostest launch file test/ros/*.test is registered in CMakeLists.txt (add_rostest or
  add_rostest_gtest), so `catkin run_tests` runs what scripts/test.sh runs;
- every node of launch/*.launch has clear_params="true", so parameters an earlier launch left on a running
  master do not leak into it (the rostest launch_params.test shows the effect for tether.launch).
"""
import pathlib
import re
import unittest
import xml.etree.ElementTree as ET

import rosunit

ROOT = pathlib.Path(__file__).resolve().parent.parent


class Repository(unittest.TestCase):
    def test_every_rostest_is_registered(self):
        cmake = (ROOT / "CMakeLists.txt").read_text()
        registered = set()
        for arguments in re.findall(r"add_rostest(?:_gtest)?\(([^)]*)\)", cmake):
            registered.update(a for a in arguments.split() if a.endswith(".test"))
        present = {str(p.relative_to(ROOT)) for p in (ROOT / "test" / "ros").glob("*.test")}
        self.assertTrue(present, "no rostest found")
        self.assertEqual(sorted(present - registered), [], "not registered in CMakeLists.txt")
        self.assertEqual(sorted(registered - present), [], "registered but missing")

    def test_every_launched_node_clears_its_parameters(self):
        launches = sorted((ROOT / "launch").glob("*.launch"))
        self.assertTrue(launches, "no launch file found")
        for launch in launches:
            for node in ET.parse(launch).getroot().iter("node"):
                self.assertEqual(node.get("clear_params"), "true",
                                 "%s: node %s" % (launch.relative_to(ROOT), node.get("name")))


if __name__ == "__main__":
    rosunit.unitrun("rov_tether", "check_repository", Repository)
