"""`pip install .`: builds the Python module pbd with CMake and installs it with the built-in scenes.

pyproject.toml names setuptools as the build backend; Debian's python3-setuptools and python3-wheel provide it, so
no network is needed (README, "Install"):

    python3 -m venv --system-site-packages venv && venv/bin/pip install --no-build-isolation .

The module is the CMake target pbd_python, built in build/pip (Release, without the tests, benchmarks and the
program; kept between installs, so a second install compiles only what changed) for the interpreter running pip.
With ccache on PATH the compiler runs through it, with CCACHE_BASEDIR at this folder, so that objects the
release preset's build made through ccache are reused. PBD_CMAKE_BUILD_DIR=<an existing build tree> builds the
target there instead (the test python_pip_install uses build/release, which the suite has built already).

The scenes go to <sys.prefix>/share/pbd/scenes, where pbd.load_scene finds them; python/pbd.pyi, the type stubs,
goes beside the module.
"""
import importlib.machinery
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = Path(__file__).resolve().parent


def project_version():
    """The version in project(pbd VERSION ...) of CMakeLists.txt: the one place it is written."""
    match = re.search(r"project\(pbd\s+VERSION\s+([0-9]+\.[0-9]+\.[0-9]+)", (HERE / "CMakeLists.txt").read_text())
    if not match:
        raise RuntimeError(f"{HERE / 'CMakeLists.txt'}: no project(pbd VERSION X.Y.Z)")
    return match.group(1)


def scene_files():
    """data_files entries: scenes/ and its subfolders under share/pbd/scenes, paths relative to this folder."""
    entries = []
    for folder, _, files in sorted(os.walk(HERE / "scenes")):
        rel = Path(folder).relative_to(HERE)
        if files:
            entries.append((str(Path("share/pbd") / rel), sorted(str(rel / f) for f in files)))
    return entries


def run(args, **kwargs):
    print("pbd setup.py:", " ".join(str(a) for a in args), flush=True)
    subprocess.run([str(a) for a in args], check=True, **kwargs)


class CMakeBuild(build_ext):
    """Builds the extension with CMake instead of setuptools' compiler calls."""

    def build_extension(self, ext):
        suffix = importlib.machinery.EXTENSION_SUFFIXES[0]  # e.g. .cpython-311-x86_64-linux-gnu.so
        given = os.environ.get("PBD_CMAKE_BUILD_DIR")
        build_dir = Path(given).resolve() if given else HERE / "build" / "pip"
        env = dict(os.environ)
        if not given:
            self.configure(build_dir, env)
        jobs = ["-j", str(self.parallel)] if self.parallel else []
        run(["cmake", "--build", build_dir, "--target", "pbd_python", *jobs], env=env)
        built = build_dir / "python" / f"pbd{suffix}"
        if not built.is_file():
            raise RuntimeError(f"{built} was not built: {build_dir} builds the module for another Python than "
                               f"{sys.executable} (suffix {suffix}); remove it, or set PBD_CMAKE_BUILD_DIR")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)
        shutil.copyfile(HERE / "python" / "pbd.pyi", target.parent / "pbd.pyi")

    def configure(self, build_dir, env):
        args = ["cmake", "-S", HERE, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DPBD_BUILD_TESTS=OFF",
                "-DPBD_BUILD_BENCHMARKS=OFF", "-DPBD_BUILD_CLI=OFF", "-DPBD_BUILD_PYTHON=ON",
                f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja"):
            args += ["-G", "Ninja"]
        if shutil.which("ccache") and "CMAKE_CXX_COMPILER_LAUNCHER" not in env:
            args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        if "ccache" in env.get("CMAKE_CXX_COMPILER_LAUNCHER", "ccache"):
            env.setdefault("CCACHE_BASEDIR", str(HERE))  # paths in the hash relative: build/pip hits build/release
        if not (build_dir / "CMakeCache.txt").is_file():
            run(args, env=env)


setup(
    version=project_version(),
    packages=[],    # one extension module and data: no setuptools package discovery in a tree of C++ folders
    py_modules=[],
    ext_modules=[Extension("pbd", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    data_files=scene_files(),
)
