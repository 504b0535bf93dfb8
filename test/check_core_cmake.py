#!/usr/bin/env python3
"""The ROS-free core built with plain CMake and used from outside the package (issue 23; docs/core.md), run by
scripts/test.sh once, with no ROS master (JUnit XML with --gtest_output=xml:FILE, as rosunit writes it):

- `cmake -S core` configures, builds and installs the core, geometry, scenario, spec, camera and study
  libraries, rov_tether_run and the package config without catkin (find_package(catkin) disabled, no ROS
  variable in the environment), and no installed binary needs a ROS library;
- a program outside the package (test/consumer/) finds the installed core with find_package(rov_tether_core),
  links rov_tether::study and hangs the S = 8 catenary: equal horizontal tension in every segment and the
  chain's weight held at the supports, within 1% (it exits non-zero otherwise);
- the installed runner runs a scenario with a mesh obstacle and a camera, so both modules it loads beside
  itself (rov_tether_mesh, rov_tether_camera) are found in the install prefix;
- the Python module imports from the build directory and from the prefix (PYTHONPATH) and hangs the same
  catenary.

Built at -O0 without debug information: about a minute and a half on two cores, the whole core set.
"""
import csv
import os
import pathlib
import subprocess
import tempfile
import textwrap
import unittest

import rosunit

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Nothing of ROS: Debian's ROS lives in /usr, so what keeps it out is the environment (no ROS_* or
# CMAKE_PREFIX_PATH) and find_package(catkin) disabled.
ENV = {"PATH": "/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp"), "LANG": "C.UTF-8"}
ROS_LIBRARIES = ("libroscpp", "librosconsole", "libcpp_common", "librostime", "libroslib", "libcatkin")


def run(args, **kwargs):
    """Runs `args` in ENV; the output (stdout and stderr) is returned, and shown when it fails."""
    done = subprocess.run([str(a) for a in args], env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          **kwargs)
    if done.returncode != 0:
        raise AssertionError("%s exited %d:\n%s" % (" ".join(map(str, args)), done.returncode, done.stdout[-4000:]))
    return done.stdout


class CoreWithPlainCMake(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.TemporaryDirectory(prefix="rov_tether_core_")
        work = pathlib.Path(cls.work.name)
        cls.prefix = work / "prefix"
        cls.build = work / "build"
        cls.build_error = None
        try:
            jobs = str(os.cpu_count() or 2)
            run(["cmake", "-S", ROOT / "core", "-B", work / "build", "-DCMAKE_BUILD_TYPE=Debug",
                 "-DCMAKE_CXX_FLAGS_DEBUG=-O0", "-DCMAKE_INSTALL_PREFIX=%s" % cls.prefix,
                 "-DCMAKE_DISABLE_FIND_PACKAGE_catkin=ON"])
            run(["cmake", "--build", work / "build", "-j", jobs])
            run(["cmake", "--install", work / "build"])
        except AssertionError as error:
            cls.build_error = str(error)

    @classmethod
    def tearDownClass(cls):
        cls.work.cleanup()

    def setUp(self):
        if self.build_error:
            self.fail("the core did not build and install with plain CMake: " + self.build_error)

    def test_the_core_installs_without_catkin_and_needs_no_ros_library(self):
        config = self.prefix / "lib" / "cmake" / "rov_tether_core"
        for name in ("rov_tether_coreConfig.cmake", "rov_tether_coreConfigVersion.cmake", "rov_tether_coreTargets.cmake"):
            self.assertTrue((config / name).is_file(), name)
        for part in ("core", "geometry", "mesh", "scenario", "spec", "scenario_yaml", "camera", "study"):
            self.assertTrue((self.prefix / "lib" / ("librov_tether_%s.so" % part)).is_file(), part)
        self.assertTrue((self.prefix / "include" / "rov_tether" / "core" / "tether.hpp").is_file())
        self.assertFalse((self.prefix / "include" / "rov_tether" / "ros").exists(), "the ROS layer's headers")
        binaries = sorted((self.prefix / "lib").glob("*.so")) + sorted((self.prefix / "bin").iterdir())
        for binary in binaries:
            needed = run(["ldd", binary])
            self.assertNotIn("not found", needed, binary.name)
            for library in ROS_LIBRARIES:
                self.assertNotIn(library, needed, "%s needs %s" % (binary.name, library))

    def test_a_program_outside_the_package_links_the_installed_core(self):
        with tempfile.TemporaryDirectory() as build:
            run(["cmake", "-S", ROOT / "test" / "consumer", "-B", build, "-DCMAKE_PREFIX_PATH=%s" % self.prefix,
                 "-DCMAKE_DISABLE_FIND_PACKAGE_catkin=ON"])
            run(["cmake", "--build", build])
            consumer = pathlib.Path(build) / "consumer"
            self.assertNotIn("libroscpp", run(["ldd", consumer]))
            printed = run([consumer])  # exits 1 when the statics are off by 1% or more (test/consumer/main.cpp)
            self.assertIn("segments 20", printed)

    def test_the_installed_runner_loads_its_mesh_and_camera_modules_from_the_prefix(self):
        scenario = textwrap.dedent("""\
            description: "A short dive past the wreck with a camera: both of the runner's modules"
            params: {cable_length: 20.0, segment_length: 0.5, initial_deployed_length: 8.0}
            spool: [0.0, 0.0, 0.0]
            vehicle: [[0.0, 6.0, 0.0, -2.0], [2.0, 7.0, 0.0, -2.0]]
            duration: 2.0
            output_rate: 5.0
            obstacles:
              - {name: wreck, type: mesh, file: %s, position: [0.0, 30.0, -10.0]}
            cameras:
              - {name: forward, position: [0.5, 0.0, 0.0], orientation: [0.0, 0.0, 180.0], rate: 1.0, width: 64,
                 height: 48, K: [40.0, 0.0, 31.5, 0.0, 40.0, 23.5, 0.0, 0.0, 1.0]}
            """ % (ROOT / "meshes" / "wreck.stl"))
        with tempfile.TemporaryDirectory() as work:
            path = pathlib.Path(work) / "scenario.yaml"
            path.write_text(scenario)
            run([self.prefix / "bin" / "rov_tether_run", path, "--out", pathlib.Path(work) / "out"])
            with open(pathlib.Path(work) / "out" / "state.csv") as state:
                rows = list(csv.DictReader(state))
            self.assertEqual(len(rows), 11)  # 0 to 2 s at 5 Hz
            frames = (pathlib.Path(work) / "out" / "cameras" / "forward" / "index.csv").read_text().splitlines()
            self.assertEqual(len(frames), 1 + 3)  # a header, then frames at 0, 1 and 2 s

    def test_the_python_module_imports_from_the_build_and_from_the_prefix(self):
        # The S = 8 catenary's weight, held at the supports' segments as in test/consumer: the module steps the
        # same core. Run in ENV with PYTHONPATH alone added, from an empty directory.
        program = textwrap.dedent("""\
            import math, sys
            import rov_tether
            world = rov_tether.World({"params": {"cable_length": 10.0, "initial_deployed_length": 10.0,
                                                 "segment_length": 0.5, "weight_in_water": 1.0, "noise": 0.0,
                                                 "winch_mode": "locked"},
                                      "spool": [0.0, 0.0, 0.0], "vehicle": [[0.0, 8.0, 0.0, 0.0]]})
            world.advance_to(30.0)
            tether = world.tethers[0]
            p, t = tether.positions, tether.segment_tension
            vertical = lambda k: t[k] * abs(p[k + 1][2] - p[k][2]) / math.dist(p[k + 1], p[k])
            held = vertical(0) + vertical(len(t) - 1)
            print(rov_tether._core.__file__, held)
            sys.exit(0 if abs(held - 9.5) < 0.095 else 1)
            """)
        for where in (self.build / "python", self.prefix / "lib" / "python3" / "dist-packages"):
            with tempfile.TemporaryDirectory() as empty:
                env = dict(ENV, PYTHONPATH=str(where))
                done = subprocess.run(["/usr/bin/python3", "-c", program], env=env, cwd=empty, capture_output=True,
                                      text=True)
                self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
                self.assertIn(str(where), done.stdout)


if __name__ == "__main__":
    rosunit.unitrun("rov_tether", "check_core_cmake", CoreWithPlainCMake)
