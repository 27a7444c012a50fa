# The fleet layer's Python package (docs/fleet.md), for catkin_python_setup() in CMakeLists.txt; not for pip.
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["tread_wear_fleet"], package_dir={"": "python"}))
