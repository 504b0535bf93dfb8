#!/usr/bin/env python3
"""The Python package in catkin's install space (issue 23), run by scripts/test.sh once, with no ROS master
(JUnit XML with --gtest_output=xml:FILE, as rosunit writes it): the catkin build (ROV_TETHER_CATKIN_BUILD, default
catkin_build) installed with DESTDIR into a scratch directory holds rov_tether/__init__.py (catkin_python_setup),
the compiled modules _core and _camera, and the message modules in one package; with the environment a catkin
install's setup.bash gives (PYTHONPATH, LD_LIBRARY_PATH) and nothing else, Python imports the messages and
steps a World from there. DESTDIR keeps everything, catkin's setup.py install included, out of the system.
"""
import os
import pathlib
import subprocess
import tempfile
import textwrap
import unittest

import rosunit

ROOT = pathlib.Path(__file__).resolve().parent.parent
BUILD = pathlib.Path(os.environ.get("ROV_TETHER_CATKIN_BUILD", str(ROOT / "catkin_build")))


class CatkinInstall(unittest.TestCase):
    def test_the_install_space_holds_the_python_package_and_it_steps_a_world(self):
        cache = (BUILD / "CMakeCache.txt").read_text()
        prefix = next(line.split("=", 1)[1] for line in cache.splitlines() if line.startswith("CMAKE_INSTALL_PREFIX:"))
        with tempfile.TemporaryDirectory() as stage:
            env = {"PATH": "/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp"), "DESTDIR": stage}
            done = subprocess.run(["cmake", "--install", str(BUILD)], env=env, capture_output=True, text=True)
            self.assertEqual(done.returncode, 0, done.stdout[-3000:] + done.stderr[-3000:])
            root = pathlib.Path(stage + prefix)
            package = root / "lib" / "python3" / "dist-packages" / "rov_tether"
            for part in ("__init__.py", "msg/__init__.py", "srv/__init__.py"):
                self.assertTrue((package / part).is_file(), part)
            for module in ("_core", "_camera"):
                self.assertEqual(len(list(package.glob(module + ".cpython-*.so"))), 1, module)
            program = textwrap.dedent("""\
                import rov_tether, rov_tether.msg
                world = rov_tether.World({"spool": [0.0, 0.0, 0.0], "params": {"initial_deployed_length": 2.0}})
                world.advance_to(1.0)
                print(rov_tether._core.__file__, rov_tether.msg.TetherState.__name__, world.tethers[0].deployed_length)
                """)
            run_env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(root / "lib" / "python3" / "dist-packages"),
                       "LD_LIBRARY_PATH": str(root / "lib")}
            done = subprocess.run(["/usr/bin/python3", "-c", program], env=run_env, cwd=stage, capture_output=True,
                                  text=True)
            self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
            self.assertIn(str(package), done.stdout)
            self.assertIn("TetherState 2.0", done.stdout)


if __name__ == "__main__":
    rosunit.unitrun("rov_tether", "check_catkin_install", CatkinInstall)
