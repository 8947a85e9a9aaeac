"""The Python package gyrosid (python/gyrosid) with its pybind11 extension, built by the project's CMake.

    pip install --no-build-isolation .          # Debian 12: python3-pip python3-setuptools python3-wheel

Offline and with Debian's own tools: setuptools drives the build, CMake builds the one target `_gyrosid`
(the toolkit library and the bindings; no tests, no benchmarks) in build/python-package/, and the module is
installed beside python/gyrosid/__init__.py, its type stubs (_gyrosid.pyi) and py.typed. With
GYROSID_CMAKE_BUILD_DIR=<an existing build folder> the module is taken from that build (its target brought up
to date) instead of configuring a second one - what the test Python.PipInstall does.
"""
import glob
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))
SCRATCH = os.path.join("build", "setuptools")  # setuptools' own build and egg-info folders, out of the sources


def project_version():
    """The version of CMakeLists.txt's project(), the one version of gyrosid."""
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        match = re.search(r"project\(gyrosid VERSION ([0-9.]+)", f.read())
    if not match:
        sys.exit("setup.py: CMakeLists.txt: no `project(gyrosid VERSION x.y.z` found")
    return match.group(1)


class CMakeBuild(build_ext):
    """Builds the extension by CMake's target `_gyrosid` and copies the module where setuptools installs from."""

    def build_extension(self, ext):
        build_dir = os.environ.get("GYROSID_CMAKE_BUILD_DIR")
        if not build_dir:
            build_dir = os.path.join(ROOT, "build", "python-package")
            configure = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DGYROSID_BUILD_TESTS=OFF",
                         "-DGYROSID_BUILD_BENCHMARKS=OFF", "-DPython3_EXECUTABLE=" + sys.executable]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
                subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", build_dir, "--target", "_gyrosid", "--parallel"], check=True)
        built = glob.glob(os.path.join(build_dir, "python", "gyrosid", "_gyrosid*.so"))
        if len(built) != 1:
            sys.exit("setup.py: expected one _gyrosid module in %s/python/gyrosid, found %s" % (build_dir, built))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built[0], target)


os.makedirs(os.path.join(ROOT, SCRATCH), exist_ok=True)
setup(
    version=project_version(),
    packages=["gyrosid"],
    package_dir={"": "python"},
    package_data={"gyrosid": ["py.typed", "_gyrosid.pyi"]},
    ext_modules=[Extension("gyrosid._gyrosid", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": SCRATCH}, "egg_info": {"egg_base": SCRATCH}},
    zip_safe=False,
)
