#!/usr/bin/python3
"""Test of the installed pbd, from its Debian package: it works from any folder, with no source tree.

Usage: check_install.py CMAKE BUILD_DIR SOURCE_DIR WORK_DIR [--sanitized]

1. `cpack` (beside CMAKE) makes the Debian package of BUILD_DIR (gzip: faster than the release's xz), named
   pbd_<version>_<arch>.deb with the version of pbd/version.hpp. `dpkg-deb -f` shows its name, version, architecture,
   maintainer, Depends (the shared libraries dpkg-shlibdeps found, the -dev packages of the CMake package's
   dependencies, python3, numpy, matplotlib) and Recommends (tetgen); `dpkg-deb -c` lists the program, scenes, plot
   script, headers, libraries, CMake package, licence and Python module under /usr, and nothing elsewhere.
2. `dpkg -x` unpacks it into WORK/root, a folder the files never were in: nothing may depend on where they go.
3. No unpacked file (the program, the libraries, the Python module, the CMake package, the data; debug sections left
   out) holds the source tree's path, the build tree's or cpack's staging folder's.
4. From an empty folder, with no PBD_* variable set and python3 on PATH: `pbd list`, `pbd run cloth --steps 5` and
   `pbd study --quick --scene rope,cloth12,cloth30 --plots DIR` work; every plot exists as PNG; the report's commit
   is "unknown" (none given). Three scenes: where files go does not depend on how many (the whole quick study is
   test study_quick's), and ns_per_projection plots two sizes of the cloth<N> family at least.
5. From the same folder, /usr/bin/python3 with PYTHONPATH at the unpacked dist-packages imports pbd from there and
   steps a world, and the scenes are at <module dir>/../../../share/pbd/scenes, where pbd.load_scene looks (the
   sanitizer builds have no module).
6. A copy of the program alone (no share/pbd beside it): `pbd list` fails with status 2 and names the folder it
   tried.
"""
import glob
import json
import os
import re
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


def version_of(build):
    """PBD_VERSION_STRING of the build tree's pbd/version.hpp: the version the program and the package carry."""
    with open(os.path.join(build, "generated", "include", "pbd", "version.hpp")) as f:
        match = re.search(r'#define PBD_VERSION_STRING "([^"]+)"', f.read())
    if not match:
        fail(f"{build}/generated/include/pbd/version.hpp has no PBD_VERSION_STRING")
    return match.group(1)


def make_package(cmake, build, work, version):
    """Runs cpack in BUILD into WORK/package; returns the .deb's path."""
    out = os.path.join(work, "package")
    cpack = os.path.join(os.path.dirname(cmake), "cpack")
    run([cpack, "--config", os.path.join(build, "CPackConfig.cmake"), "-B", out,
         "-D", "CPACK_DEBIAN_COMPRESSION_TYPE=gzip"], build, os.environ)
    arch = run(["dpkg", "--print-architecture"], work, os.environ).stdout.strip()
    debs = glob.glob(os.path.join(out, "*.deb"))
    expected = os.path.join(out, f"pbd_{version}_{arch}.deb")
    if debs != [expected]:
        fail(f"cpack made {debs}, not [{expected}]")
    return expected


def check_control(deb, version, work, with_module):
    """The control fields of the package."""
    def field(name):
        return run(["dpkg-deb", "-f", deb, name], work, os.environ).stdout.strip()
    arch = run(["dpkg", "--print-architecture"], work, os.environ).stdout.strip()
    for name, value in (("Package", "pbd"), ("Version", version), ("Architecture", arch), ("Recommends", "tetgen")):
        if field(name) != value:
            fail(f"{deb}: {name} is {field(name)!r}, not {value!r}")
    if not re.fullmatch(r".+ <[^<>@ ]+@[^<> ]+>", field("Maintainer")):
        fail(f"{deb}: Maintainer {field('Maintainer')!r} is not 'Name <address>'")
    depends = {d.split()[0] for d in field("Depends").replace("|", ",").split(",") if d.strip()}
    wanted = {"libc6", "libstdc++6", "libtbb12", "libmetis5", "libeigen3-dev", "libtbb-dev", "libmetis-dev",
              "nlohmann-json3-dev", "python3", "python3-numpy", "python3-matplotlib"}
    if wanted - depends:
        fail(f"{deb}: Depends lacks {sorted(wanted - depends)}: {field('Depends')}")
    if with_module and not re.search(r"python3 \(>= 3\.\d+~\), python3 \(<< 3\.\d+\)", field("Depends")):
        fail(f"{deb}: Depends does not bound python3 to the module's minor version: {field('Depends')}")


def check_listing(deb, work, with_module):
    """`dpkg-deb -c`: the files a user of each part needs, all under /usr."""
    listing = run(["dpkg-deb", "-c", deb], work, os.environ).stdout
    paths = [line.split()[-1] for line in listing.splitlines()]
    outside = [p for p in paths if p != "./" and not (p + "/").startswith("./usr/")]
    if outside:
        fail(f"{deb} holds files outside /usr: {outside}")
    wanted = ["./usr/bin/pbd", "./usr/share/pbd/plot_study.py", "./usr/share/pbd/scenes/cloth.json",
              "./usr/share/pbd/scenes/meshes/pig.obj", "./usr/include/pbd/world.hpp", "./usr/include/pbd/version.hpp",
              "./usr/lib/libpbd_engine.a", "./usr/lib/libpbd_io.a", "./usr/lib/libpbd_graph_coloring.a",
              "./usr/lib/cmake/pbd/pbdConfig.cmake", "./usr/lib/cmake/pbd/pbdConfigVersion.cmake",
              "./usr/lib/cmake/pbd/pbdTargets.cmake", "./usr/lib/cmake/pbd/FindMETIS.cmake",
              "./usr/share/doc/pbd/copyright"]
    missing = [p for p in wanted if p not in paths]
    if missing:
        fail(f"{deb} lacks {missing}")
    modules = [p for p in paths if re.fullmatch(r"\./usr/lib/python3/dist-packages/pbd\.cpython-[^/]+\.so", p)]
    if with_module and len(modules) != 1:
        fail(f"{deb} holds {modules} as the Python module, not one ./usr/lib/python3/dist-packages/pbd.cpython-*.so")


def unpack(deb, work):
    """`dpkg -x` into WORK/root; returns the unpacked /usr."""
    root = os.path.join(work, "root")
    run(["dpkg", "-x", deb, root], work, os.environ)
    return os.path.join(root, "usr")


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


def check_commands(pbd, empty, env):
    if os.listdir(empty):
        fail(f"{empty} is not empty")
    listed = run([pbd, "list"], empty, env).stdout
    for name in ("cloth", "rope", "cloth30"):
        if not any(line.split()[:1] == [name] for line in listed.splitlines()):
            fail(f"pbd list does not list {name}:\n{listed}")
    ran = run([pbd, "run", "cloth", "--steps", "5"], empty, env).stdout
    if "state hash" not in ran:
        fail(f"pbd run cloth --steps 5 printed no state hash:\n{ran}")
    run([pbd, "study", "--quick", "--scene", "rope,cloth12,cloth30", "--plots", "plots"], empty, env)
    for plot in PLOTS:
        if not os.path.isfile(os.path.join(empty, "plots", plot + ".png")):
            fail(f"pbd study --quick --plots wrote no {plot}.png")
    with open(os.path.join(empty, "plots", "study.json")) as f:
        commit = json.load(f)["study"]["git_commit"]
    if commit != "unknown":
        fail(f"the report's commit is {commit!r}; with none given it must be 'unknown'")


def check_python(usr, empty, env, source):
    """/usr/bin/python3 imports the unpacked module and steps a world; the scenes are where pbd.load_scene looks."""
    site = os.path.join(usr, "lib", "python3", "dist-packages")
    code = """
import os, sys
import pbd
site = os.path.realpath(os.path.dirname(pbd.__file__))
if site != os.path.realpath(sys.argv[1]):
    sys.exit(f"pbd was imported from {pbd.__file__}, not from {sys.argv[1]}")
world = pbd.World()
i = world.add_particle((0.0, 0.0, 1.0), 1.0)
for _ in range(30):
    world.step()
if not world.positions()[i, 2] < 0.9:
    sys.exit("a particle dropped from 1 m did not fall")
scene = os.path.join(site, "..", "..", "..", "share", "pbd", "scenes", "cloth.json")
if not os.path.isfile(scene):
    sys.exit(f"no {scene}: pbd.load_scene would not find the scenes")
if not os.path.isfile(os.path.join(site, "pbd.pyi")):
    sys.exit(f"pbd.pyi is not beside the module in {site}")
"""
    run(["/usr/bin/python3", "-c", code, site], empty, dict(env, PYTHONPATH=site))


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
    work = os.path.realpath(work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    version = version_of(build)
    deb = make_package(cmake, build, work, version)
    check_control(deb, version, work, with_module=not sanitized)
    check_listing(deb, work, with_module=not sanitized)
    usr = unpack(deb, work)
    pbd = os.path.join(usr, "bin", "pbd")
    check_no_tree_paths(usr, [source, build, os.path.join(work, "package")], work, sanitized)
    empty = os.path.join(work, "empty")
    os.makedirs(empty)
    env = clean_env()
    check_commands(pbd, empty, env)
    if not sanitized:
        check_python(usr, empty, env, source)
    check_lonely_program(pbd, work, env)
    print(f"check_install.py: OK: {os.path.basename(deb)} unpacked; pbd ran list, run and study --quick --plots"
          f"{'' if sanitized else ', python3 imported pbd,'} from {empty}")


if __name__ == "__main__":
    main()
