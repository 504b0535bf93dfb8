#!/usr/bin/env python3
"""Checks of the repository itself, with no build and no ROS master (run by scripts/test.sh; JUnit XML with
--gtest_output=xml:FILE, as rosunit writes it):

- every rostest launch file test/ros/*.test is registered in CMakeLists.txt (add_rostest or
  add_rostest_gtest), so `catkin run_tests` runs what scripts/test.sh runs;
- every node of launch/*.launch has clear_params="true", so parameters an earlier launch left on a running
  master do not leak into it (the rostest launch_params.test shows the effect for tether.launch);
- no build output is tracked, and git ignores what the build and the scripts write (build*.log and
  catkin_build*.log were once committed, with this machine's paths, and rewritten by demo.sh);
- every repository file the README, the docs, the code and the scenarios cite by path exists (REFERENCES.md
  was cited some fifty times but was never in the repository), and LICENSE holds the license package.xml
  names;
- every gtest case (`Suite.Case`) the README and the docs cite exists, and every suite docs/tests.md's table
  names is a gtest suite or a Python TestCase class (the table named suites `PythonApi` and `PythonCamera` of
  pytest files that hold module-level functions).
"""
import pathlib
import re
import subprocess
import unittest
import xml.etree.ElementTree as ET

import yaml

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

    def test_every_tether_node_checks_the_files_it_loads(self):
        # roslaunch keeps the last of a key given twice in a YAML file without a word; tether_node reads the files
        # listed in its param_files again and refuses one. A file a launch loads but does not list goes unchecked.
        checked = 0
        for launch in sorted((ROOT / "launch").glob("*.launch")):
            for node in ET.parse(launch).getroot().iter("node"):
                if node.get("type") != "tether_node":
                    continue
                loads = [r.get("file") for r in node.iter("rosparam") if r.get("command") == "load"]
                listed = [r for r in node.iter("rosparam") if r.get("param") == "param_files"]
                where = "%s: node %s" % (launch.relative_to(ROOT), node.get("name"))
                self.assertEqual(len(listed), 1, where + ": no param_files")
                self.assertEqual(listed[0].get("subst_value"), "true", where)
                self.assertEqual(yaml.safe_load(listed[0].text), loads, where)
                checked += 1
        self.assertGreaterEqual(checked, 4)


    def test_no_build_output_is_tracked_and_build_output_is_ignored(self):
        tracked = subprocess.run(["git", "-C", str(ROOT), "ls-files"], check=True, capture_output=True,
                                 text=True).stdout.split()
        self.assertTrue(tracked, "not a git checkout")
        built = [f for f in tracked if re.match(r"(build|catkin_build)[^/]*(/|\.log$)", f)]
        self.assertEqual(built, [], "build output is tracked")
        written = ["catkin_build.build.log", "catkin_build.cmake.log", "build.log", "catkin_build/x",
                   "catkin_build_sanitize/x", "out/x", "scripts/__pycache__/x.pyc"]
        ignored = subprocess.run(["git", "-C", str(ROOT), "check-ignore", "--no-index"] + written,
                                 capture_output=True, text=True).stdout.split()
        self.assertEqual(sorted(ignored), sorted(written), "not ignored by .gitignore")

    def test_every_test_the_docs_name_exists(self):
        # docs/tests.md named suites `PythonApi` and `PythonCamera` that never existed (the pytest files hold
        # module-level functions). A `Suite.Case` the docs cite is a gtest case; a suite docs/tests.md's table
        # names is a gtest suite (an INSTANTIATE_TEST_SUITE_P prefix included) or a Python TestCase class.
        # Entries with a path or a dot (`test/python/...py`, `camera.test`) name files, which the check of cited
        # files covers.
        cases, suites = set(), set()
        for source in sorted((ROOT / "test").rglob("*.cpp")):
            text = source.read_text(errors="replace")
            for suite, case in re.findall(r"\bTEST(?:_F|_P)?\(\s*(\w+),\s*(\w+)\s*\)", text):
                cases.add("%s.%s" % (suite, case))
                suites.add(suite)
            suites.update(re.findall(r"\bINSTANTIATE_TEST_SUITE_P\(\s*(\w+),", text))
        for source in sorted((ROOT / "test").rglob("*.py")):
            suites.update(re.findall(r"^class (\w+)\(unittest\.TestCase\)", source.read_text(), re.M))
        self.assertGreater(len(cases), 300, "the gtest cases were not found")
        unknown = set()
        for source in [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md")):
            text = source.read_text()
            for cited in re.findall(r"`([A-Z]\w*)\.([A-Z]\w*|\*)`", text):
                known = cited[0] in suites if cited[1] == "*" else "%s.%s" % cited in cases
                if not known:
                    unknown.add("%s cites %s.%s" % (source.relative_to(ROOT), *cited))
        table = (ROOT / "docs" / "tests.md").read_text()
        for row in re.findall(r"^\| (.*?) \|", table, re.M):
            for name in re.findall(r"`([A-Za-z]\w*)`", row):
                if name[0].isupper() and name not in suites:
                    unknown.add("docs/tests.md's table names the suite %s" % name)
        self.assertEqual(sorted(unknown), [])

    def test_every_cited_file_exists_and_the_license_is_package_xmls(self):
        sources = [ROOT / "README.md", ROOT / "package.xml", ROOT / "CMakeLists.txt"]
        for folder, pattern in [("docs", "*.md"), ("include", "*.hpp"), ("src", "*.cpp"), ("test", "*.cpp"),
                                ("test", "*.py"), ("scenarios", "*.yaml"), ("config", "*.yaml"), ("scripts", "*.py"),
                                ("scripts", "*.sh"), ("launch", "*.launch"), ("cfg", "*.cfg")]:
            sources += sorted((ROOT / folder).rglob(pattern))
        cited = re.compile(r"(?<![\w/.$])((?:docs|config|scenarios|launch|scripts|test|cfg|include|src)/[\w./-]+\.\w+"
                           r"|REFERENCES\.md|LICENSE)")
        missing = set()
        for source in sources:
            if "fuzz/corpus" in str(source) or source.name == "check_repository.py":
                continue
            for path in cited.findall(source.read_text(errors="replace")):
                path = path.rstrip(".")
                placeholder = "*" in path or "NAME" in path  # a pattern or a usage text's NAME
                if not placeholder and not (ROOT / path).exists() and not (source.parent / path).exists():
                    missing.add("%s cites %s" % (source.relative_to(ROOT), path))
        self.assertEqual(sorted(missing), [])
        license_name = ET.parse(ROOT / "package.xml").getroot().findtext("license")
        self.assertEqual(license_name, "BSD-3-Clause")
        text = (ROOT / "LICENSE").read_text()
        self.assertIn("BSD 3-Clause License", text)
        self.assertIn("Neither the name of the copyright holder", text)  # the third clause


if __name__ == "__main__":
    rosunit.unitrun("rov_tether", "check_repository", Repository)
