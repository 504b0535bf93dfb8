# catkin_python_setup() (CMakeLists.txt): the Python package rov_tether (python/rov_tether/), beside the
# message modules catkin generates into it. Not for pip: the compiled part is built by CMake.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["rov_tether"], package_dir={"": "python"}))
