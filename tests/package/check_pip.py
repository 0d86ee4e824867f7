#!/usr/bin/python3
"""Test of `pip install .` (pyproject.toml, setup.py) in a virtual environment with no network, as README says.

Usage: check_pip.py SOURCE_DIR BUILD_DIR WORK_DIR VERSION

1. The source tree is copied to WORK/src (without build/ and .git), so that setuptools' build folders and egg-info
   do not land in the source tree.
2. `python3 -m venv --system-site-packages WORK/venv`, then `WORK/venv/bin/pip install --no-build-isolation
   --no-index WORK/src` (--no-index: the test fails rather than reach for PyPI): setup.py configures a fresh
   WORK/src/build/pip and builds the module there, as a user's install does. With ccache (scripts/deps installs it
   and scripts/build builds through it, CCACHE_BASEDIR at the source tree) the compiles are the release build's,
   at the same depth below their source tree, so they come from the cache: seconds, not the minutes of a cold build.
3. From an empty folder, the venv's python imports pbd from the venv (not from the build tree), steps a falling
   particle, and sees: the distribution's version equal to CMake's project version (VERSION), the scenes in
   sys.prefix/share/pbd/scenes, which is also <module dir>/../../../share/pbd (the two places pbd.load_scene looks
   after $PBD_DATA_DIR), and the type stubs beside the module.
"""
import os
import shutil
import subprocess
import sys

CHECK = r"""
import importlib.metadata, os, sys
import pbd
site = os.path.realpath(os.path.dirname(pbd.__file__))
if not site.startswith(os.path.realpath(sys.prefix) + os.sep):
    sys.exit(f"pbd was imported from {pbd.__file__}, not from the venv {sys.prefix}")
world = pbd.World()
i = world.add_particle((0.0, 0.0, 1.0), 1.0)
for _ in range(30):
    world.step()
z = float(world.positions()[i, 2])
if not z < 0.9:
    sys.exit(f"a particle dropped from 1 m is at z = {z} after 0.5 s")
version = importlib.metadata.version("pbd")
if version != sys.argv[1]:
    sys.exit(f"the installed distribution's version is {version}, CMake's is {sys.argv[1]}")
scenes = os.path.join(sys.prefix, "share", "pbd", "scenes")
for name in ("cloth.json", os.path.join("meshes", "pig.obj")):
    if not os.path.isfile(os.path.join(scenes, name)):
        sys.exit(f"{os.path.join(scenes, name)} was not installed")
beside = os.path.realpath(os.path.join(site, "..", "..", "..", "share", "pbd", "scenes"))
if beside != os.path.realpath(scenes):
    sys.exit(f"the scenes relative to the module ({beside}) are not those in sys.prefix ({scenes})")
if not os.path.isfile(os.path.join(site, "pbd.pyi")):
    sys.exit(f"pbd.pyi is not beside the module in {site}")
print(f"pbd {version} from {pbd.__file__}: z = {z:.3f} m after 0.5 s; scenes in {scenes}")
"""


def fail(message):
    print("check_pip.py: FAIL:", message)
    sys.exit(1)


def run(args, cwd, env):
    r = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{' '.join(args)}: status {r.returncode}\nstdout: {r.stdout}\nstderr: {r.stderr}")
    return r.stdout


def main():
    source, _build, work, version = sys.argv[1:5]
    work = os.path.realpath(work)
    shutil.rmtree(work, ignore_errors=True)
    src, venv, empty = (os.path.join(work, d) for d in ("src", "venv", "empty"))
    shutil.copytree(source, src, ignore=shutil.ignore_patterns("build", ".git", "__pycache__", "*.egg-info"))
    os.makedirs(empty)
    # The environment without pbd's and Python's path variables (the suite's PYTHONPATH names the build tree).
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PBD_", "PYTHON"))}
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv], work, env)
    pip_env = dict(env)
    out = run([os.path.join(venv, "bin", "pip"), "install", "--no-build-isolation", "--no-index", src], work, pip_env)
    if f"Successfully installed pbd-{version}" not in out:
        fail(f"pip did not install pbd-{version}:\n{out}")
    print(run([os.path.join(venv, "bin", "python"), "-c", CHECK, version], empty, env), end="")
    print("check_pip.py: OK: pip install . in a venv, offline")


if __name__ == "__main__":
    main()
