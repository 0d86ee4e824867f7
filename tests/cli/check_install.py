#!/usr/bin/python3
"""Test of the installed pbd: it works from any folder, with no source tree.

Usage: check_install.py CMAKE BUILD_DIR SOURCE_DIR WORK_DIR [--sanitized]

1. `cmake --install BUILD_DIR` into a temporary prefix, then the prefix is moved: nothing may depend on where it was
   installed.
2. No installed file (the program, the libraries, the Python module, the CMake package, the data; debug sections left
   out) holds the source tree's path or the build tree's.
3. From an empty folder, with no PBD_* variable set and python3 on PATH: `pbd list`, `pbd run cloth --steps 5` and
   `pbd study --quick --plots DIR` work; every plot exists as PNG; the report's commit is "unknown" (none given).
   Under the sanitizers the study runs one scene only (the whole quick study is already test study_quick's).
4. A copy of the program alone (no share/pbd beside it): `pbd list` fails with status 2 and names the folder it
   tried.
"""
import json
import os
import shutil
import subprocess
import sys

PLOTS = ["speed_error", "convergence", "thread_scaling", "ns_per_projection"]


def fail(message):
    print("check_install.py: FAIL:", message)
    sys.exit(1)


def run(args, cwd, env, expect=0):
    r = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True)
    if r.returncode != expect:
        fail(f"{' '.join(args)}: status {r.returncode} (expected {expect})\nstdout: {r.stdout}\nstderr: {r.stderr}")
    return r


def install(cmake, build, work):
    """Installs into WORK/staging, then moves it to WORK/moved/prefix; returns the moved prefix."""
    staging, prefix = os.path.join(work, "staging"), os.path.join(work, "moved", "prefix")
    run([cmake, "--install", build, "--prefix", staging], work, os.environ)
    os.makedirs(os.path.dirname(prefix))
    os.rename(staging, prefix)
    return prefix


def contents_to_scan(file, work, sanitized):
    """The file's bytes; for an object file, program or archive, without its debug sections: a build with debug
    information (the sanitizer presets are RelWithDebInfo) names its source files there for the debugger, which is
    no path the program uses. Under the sanitizers, binaries are not scanned at all (None): ASan names each object's
    source file as its module and UBSan names it in every check's report location, in data sections that GCC's
    -ffile-prefix-map does not rewrite. The Release run of this test scans them."""
    with open(file, "rb") as f:
        data = f.read()
    if not (data.startswith(b"\x7fELF") or data.startswith(b"!<arch>")):
        return data
    if sanitized:
        return None
    stripped = os.path.join(work, "stripped")
    run(["objcopy", "--strip-debug", file, stripped], work, os.environ)
    with open(stripped, "rb") as f:
        data = f.read()
    os.remove(stripped)
    return data


def check_no_tree_paths(prefix, trees, work, sanitized):
    paths = {p.encode() for tree in trees for p in (tree, os.path.realpath(tree))}
    for folder, _, files in os.walk(prefix):
        for name in files:
            data = contents_to_scan(os.path.join(folder, name), work, sanitized)
            if data is None:
                continue
            for path in paths:
                if path in data:
                    fail(f"{os.path.join(folder, name)} holds the path {path.decode()}")


def clean_env():
    """The environment without pbd's variables, with the interpreter running this test (it has matplotlib) first
    on PATH as python3."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PBD_")}
    env["PATH"] = os.path.dirname(sys.executable) + os.pathsep + env.get("PATH", "")
    return env


def check_commands(pbd, empty, env, study_args):
    if os.listdir(empty):
        fail(f"{empty} is not empty")
    listed = run([pbd, "list"], empty, env).stdout
    for name in ("cloth", "rope", "cloth30"):
        if not any(line.split()[:1] == [name] for line in listed.splitlines()):
            fail(f"pbd list does not list {name}:\n{listed}")
    ran = run([pbd, "run", "cloth", "--steps", "5"], empty, env).stdout
    if "state hash" not in ran:
        fail(f"pbd run cloth --steps 5 printed no state hash:\n{ran}")
    run([pbd, "study", "--quick", "--plots", "plots"] + study_args, empty, env)
    # ns_per_projection plots the cloth<N> family: a study of one scene (sanitizers) has none to plot.
    for plot in PLOTS if not study_args else [p for p in PLOTS if p != "ns_per_projection"]:
        if not os.path.isfile(os.path.join(empty, "plots", plot + ".png")):
            fail(f"pbd study --quick --plots wrote no {plot}.png")
    with open(os.path.join(empty, "plots", "study.json")) as f:
        commit = json.load(f)["study"]["git_commit"]
    if commit != "unknown":
        fail(f"the report's commit is {commit!r}; with none given it must be 'unknown'")


def check_lonely_program(pbd, work, env):
    lonely = os.path.join(work, "lonely", "bin")
    os.makedirs(lonely)
    shutil.copy2(pbd, lonely)
    err = run([os.path.join(lonely, "pbd"), "list"], lonely, env, expect=2).stderr
    tried = os.path.join(work, "lonely", "share", "pbd", "scenes")
    if tried not in err or "PBD_SCENE_DIR" not in err:
        fail(f"pbd list without scenes must name {tried} and PBD_SCENE_DIR:\n{err}")


def main():
    cmake, build, source, work = sys.argv[1:5]
    sanitized = "--sanitized" in sys.argv[5:]
    study_args = ["--scene", "rope"] if sanitized else []
    work = os.path.realpath(work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    prefix = install(cmake, build, work)
    pbd = os.path.join(prefix, "bin", "pbd")
    check_no_tree_paths(prefix, [source, build, os.path.join(work, "staging")], work, sanitized)
    empty = os.path.join(work, "empty")
    os.makedirs(empty)
    env = clean_env()
    check_commands(pbd, empty, env, study_args)
    check_lonely_program(pbd, work, env)
    print("check_install.py: OK: the installed pbd ran list, run and study --quick --plots from", empty)


if __name__ == "__main__":
    main()
