#!/usr/bin/env python3
"""The command line's promises, tried as a new user would: `pbd run` prints the final state hash and checks it
(--expect-hash), writes per-step statistics (--stats) and the fibers that broke (--breaks), says how many threads really run; an unknown subcommand is
named; a write that fails anywhere (stdout, --json, --stats, frames) ends with status 2 and a message, leaving no
half-written file; a scene's name cannot send files outside the frame folder; a scene over the size limits is
refused before anything is built; a value beyond float's range names the file and the key; a run whose state goes
non-finite stops before writing it and leaves complete outputs; outputs that cannot be written are refused before
the first step; a FIFO named like a frame is refused, not waited on.

Usage: check_run.py PBD OUT_DIR [--sanitized]"""
import errno
import json
import os
import tempfile
import re
import resource
import signal
import stat
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_outputs import Invalid, check_frames, check_stats  # noqa: E402


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def run(pbd, args, expect=0, stdout=subprocess.PIPE, preexec=None, cwd=None):
    r = subprocess.run([pbd] + args, stdout=stdout, stderr=subprocess.PIPE, text=True, preexec_fn=preexec, cwd=cwd)
    if r.returncode != expect:
        fail(f"pbd {' '.join(args)}: status {r.returncode} (expected {expect})\nstderr: {r.stderr}")
    return r


def expect_error(pbd, args, words, **kw):
    r = run(pbd, args, expect=2, **kw)
    for w in words:
        if w not in r.stderr:
            fail(f"pbd {' '.join(args)}: {w!r} not in the error: {r.stderr!r}")
    return r


def state_hash(out):
    m = re.search(r"^state hash: ([0-9a-f]{16})$", out, re.M)
    if not m:
        fail(f"no 'state hash: <16 hex digits>' line in:\n{out}")
    return m.group(1)


def write_scene(path, **keys):
    scene = {"name": "t", "dt": 0.01, "bodies": [{"type": "rope", "particles": 5, "stretch": {}}]}
    scene.update(keys)
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def check_hash_and_stats(pbd, out):
    hashes = {threads: state_hash(run(pbd, ["run", "cloth", "--steps", "5", "--threads", str(threads)]).stdout)
              for threads in (1, 2)}
    if hashes[1] != hashes[2]:
        fail(f"colored solver: state hash {hashes[1]} on 1 thread, {hashes[2]} on 2")
    run(pbd, ["run", "cloth", "--steps", "5", "--expect-hash", hashes[1]])
    wrong = "0123456789abcdef" if hashes[1] != "0123456789abcdef" else "fedcba9876543210"
    expect_error(pbd, ["run", "cloth", "--steps", "5", "--expect-hash", wrong], ["--expect-hash", hashes[1], wrong])
    bad = subprocess.run([pbd, "run", "cloth", "--expect-hash", "12ab"], capture_output=True, text=True)
    if bad.returncode == 0 or "16 lowercase hex digits" not in bad.stderr:
        fail(f"--expect-hash 12ab: status {bad.returncode}, stderr {bad.stderr!r}")

    csv = os.path.join(out, "stats.csv")
    run(pbd, ["run", "cloth", "--steps", "4", "--stats", csv])
    with open(csv) as f:
        lines = f.read().splitlines()
    header = lines[0].split(",")
    for column in ("step", "seconds", "seconds_integrate", "seconds_collisions", "seconds_solve",
                   "seconds_hierarchy", "sweeps"):
        if column not in header:
            fail(f"--stats: no column {column} in {header}")
    rows = [dict(zip(header, line.split(","))) for line in lines[1:]]
    if [int(r["step"]) for r in rows] != [1, 2, 3, 4]:
        fail(f"--stats: steps {[r['step'] for r in rows]}, expected 1..4")
    for r in rows:  # cloth.json: 10 substeps of 4 iterations, no hierarchy
        if int(r["substeps"]) != 10 or int(r["sweeps"]) != 40 or float(r["seconds"]) <= 0 \
                or float(r["seconds_hierarchy"]) != 0:
            fail(f"--stats: row {r}")
    run(pbd, ["run", "cloth", "--steps", "2", "--hierarchy", "--stats", csv])
    with open(csv) as f:
        lines = f.read().splitlines()
    rows = [dict(zip(lines[0].split(","), line.split(","))) for line in lines[1:]]
    for r in rows:  # the coarse-to-fine passes are part of the solve
        if not 0 < float(r["seconds_hierarchy"]) < float(r["seconds_solve"]):
            fail(f"--stats --hierarchy: row {r}")
    expect_error(pbd, ["run", "cloth", "--stats", "/no/such/folder/s.csv"], ["--stats", "/no/such/folder"])


def check_threads(pbd):
    r = run(pbd, ["run", "rope", "--steps", "2", "--threads", "1000"])
    cores = len(os.sched_getaffinity(0))
    # oneTBB runs at most the machine's cores (os.cpu_count()); the header must say what really runs.
    m = re.search(r"on (\d+) threads", r.stdout)
    if not m or int(m.group(1)) > max(cores, os.cpu_count() or 1) or int(m.group(1)) == 1000:
        fail(f"--threads 1000: header {r.stdout.splitlines()[:2]}")
    if f"running on {m.group(1)}" not in r.stderr:
        fail(f"--threads 1000: no note of the threads that run: {r.stderr!r}")


def check_write_errors(pbd, out):
    expect_error(pbd, ["frobnicate"], ["unknown subcommand 'frobnicate'", "study, color, run, list"])
    with open("/dev/full", "w") as full:
        expect_error(pbd, ["run", "rope", "--steps", "2"], ["cannot write to standard output"], stdout=full)
        expect_error(pbd, ["list"], ["standard output"], stdout=full)
    expect_error(pbd, ["color", "rope", "--json", "/dev/full"], ["--json: /dev/full", "No space left"])
    expect_error(pbd, ["run", "rope", "--steps", "2", "--stats", "/dev/full"], ["/dev/full", "No space left"])
    if not stat.S_ISCHR(os.stat("/dev/full").st_mode):
        fail("/dev/full is no longer a device: a writer replaced it")

    # A disk that fills while frames are written: a file size limit of 4 KiB (the cloth's frames are ~30 KiB).
    frames = os.path.join(out, "frames_full")
    def small_files():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
    expect_error(pbd, ["run", "cloth", "--steps", "2", "--frames", frames], ["cloth_00000", "write failed"],
                 preexec=small_files)
    left = os.listdir(frames)
    if left:
        fail(f"a failed frame write left {left} in {frames}")

    # The scene's name names the frames: it cannot be a path.
    scene = write_scene(os.path.join(out, "escape.json"), name="../../escaped")
    expect_error(pbd, ["run", scene, "--frames", os.path.join(out, "a", "b")], ["escape.json: /name", "plain file name"])
    if os.path.exists(os.path.join(out, "escaped_00000.obj")) or os.path.exists(os.path.join(out, "a")):
        fail("a scene named ../../escaped wrote files")


def check_scene_errors(pbd, out, sanitized):
    scene = write_scene(os.path.join(out, "gravity.json"), gravity=[0, 0, 1e308])
    expect_error(pbd, ["run", scene], ["gravity.json: /gravity/2", "beyond the range of float"])

    cloth = {"type": "cloth", "resolution": 4096, "stretch": {}}
    scene = write_scene(os.path.join(out, "huge.json"), bodies=[cloth] * 4)
    def one_gib():  # used to take 3.4 GB and 31 s before the refusal; now nothing is built
        resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
    expect_error(pbd, ["run", scene], ["huge.json: /bodies/2/resolution", "limit of 50000000 particles"],
                 preexec=None if sanitized else one_gib)

    with open(os.path.join(out, "open.obj"), "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n")
    scene = write_scene(os.path.join(out, "open.json"),
                        bodies=[{"type": "mesh", "obj": "open.obj", "volume": {}}])
    expect_error(pbd, ["run", scene], ["open.json: /bodies/0/obj", "open.obj", "edge (1, 3)", "from 1"])


def check_breaks(pbd, out):
    """--breaks: the ligament's fibers that broke, one CSV row each, the same rows on 1 and 2 threads; each at the
    scene's rupture strain (14%) and at the tension its curve gives there (within 2%); a bad curve names its key."""
    rows = {}
    for threads in (1, 2):
        csv = os.path.join(out, f"breaks{threads}.csv")
        r = run(pbd, ["run", "ligament", "--threads", str(threads), "--breaks", csv])
        if "fibers broken: " not in r.stdout:
            fail(f"--breaks: no 'fibers broken' line in {r.stdout}")
        with open(csv) as f:
            lines = f.read().splitlines()
        if lines[0] != ("step,time_s,type,index,set,particle_a,particle_b,particle_c,particle_d,strain,force,"
                        "force_unit"):
            fail(f"--breaks: header {lines[0]}")
        rows[threads] = lines[1:]
    if rows[1] != rows[2] or len(rows[1]) < 7:
        fail(f"--breaks: {len(rows[1])} rows on 1 thread, {len(rows[2])} on 2, or they differ")
    k, toe, yield_, hard = 100.0, 0.03, 0.08, 20.0
    for line in rows[1]:
        cells = line.split(",")
        if cells[2] != "fiber" or cells[7:9] != ["", ""] or cells[11] != "N":
            fail(f"--breaks: row {line}: not a fiber's (type fiber, two particles, force in N)")
        strain, force = (float(v) for v in cells[9:11])
        expected = k * (yield_ - toe / 2) + k * hard / (k + hard) * (strain - yield_)
        if not (0.14 <= strain <= 0.1414 and abs(force - expected) <= 0.02 * expected):
            fail(f"--breaks: row {line}: strain or force off the curve ({expected:.4g} N)")
    expect_error(pbd, ["run", "ligament", "--breaks", "/no/such/folder/b.csv"], ["--breaks", "/no/such/folder"])
    bad = {"name": "bad-curve", "dt": 0.01, "bodies": [{"type": "particles", "positions": [[0, 0, 0], [1, 0, 0]],
           "fibers": {"particles": [[0, 1]], "material": {"stiffness": 10, "toe_strain": 0.2, "yield_strain": 0.1}}}]}
    path = os.path.join(out, "bad-curve.json")
    with open(path, "w") as f:
        json.dump(bad, f)
    expect_error(pbd, ["run", path], ["bad-curve.json: /bodies/0/fibers/material/yield_strain",
                                      "yield_strain must be at least toe_strain"])


def check_nonfinite(pbd, out):
    """Gravity of 1e19 m/s² (the largest a scene takes is 1.8e19: g·h² and its square stay in float's range) pulls a
    particle on a very soft link away from its pin until the link's squared length overflows float, after about 140
    steps. The run stops at the first non-finite state, before writing anything of it, naming the step and the
    particle; every frame before it is finite and listed in the .pvd (it used to list 16 of them, and 886 frames
    after it held nan), the statistics hold every step before it (they used to be lost)."""
    scene = write_scene(os.path.join(out, "blowup.json"), gravity=[0, 0, -1e19],
                        bodies=[{"type": "particles", "positions": [[0, 0, 0], [1, 0, 0]], "pinned": [0],
                                 "stretch": {"pairs": [[0, 1]], "compliance": 1e6}}])
    for fmt in ("vtu", "obj"):
        frames, stats = os.path.join(out, "blowup_" + fmt), os.path.join(out, f"blowup_{fmt}.csv")
        r = expect_error(pbd, ["run", scene, "--steps", "1000", "--frames", frames, "--format", fmt,
                               "--stats", stats], ["particle", "non-finite"])
        try:
            steps, rows = check_frames(frames, "t", fmt), check_stats(stats)
        except Invalid as e:
            fail(f"non-finite run, {fmt}: {e}")
        if len(steps) <= 20 or steps != list(range(len(rows) + 1)):
            fail(f"non-finite run, {fmt}: frames {steps[:3]}..{steps[-3:]}, statistics of steps 1..{len(rows)}")
        # The error names the step (its words are the engine's or run's, whichever check sees it first).
        if "step" not in r.stderr or not re.search(rf"\b{len(rows) + 1}\b", r.stderr):
            fail(f"non-finite run, {fmt}: the error does not name step {len(rows) + 1}: {r.stderr!r}")


def refused_at_once(pbd, args, words):
    """`pbd run rope` for 10^8 steps (minutes) with `args`, which must be refused before the first step."""
    try:
        r = subprocess.run([pbd, "run", "rope", "--steps", "100000000"] + args, capture_output=True, text=True,
                           timeout=120)
    except subprocess.TimeoutExpired:
        fail(f"{args}: not refused before the run")
    if r.returncode != 2 or not all(w in r.stderr for w in words):
        fail(f"{args}: status {r.returncode}, stderr {r.stderr!r} (expected 2 and {words})")


def read_only_folder(out):
    """A folder on a read-only file system (a read-only bind mount, as root), else None."""
    src, ro = os.path.join(out, "ro_src"), os.path.join(out, "ro")
    os.makedirs(src, exist_ok=True)
    os.makedirs(ro, exist_ok=True)
    subprocess.run(["mount", "--bind", "-o", "ro", src, ro], capture_output=True)
    try:  # os.path.ismount does not see a bind mount of the same file system: try a write instead
        open(os.path.join(ro, "probe"), "w").close()
    except OSError as e:
        if e.errno == errno.EROFS:
            return ro
    return None


def check_early_refusals(pbd, out):
    """--stats, --breaks and --frames that cannot be written are refused before the first step, not after the run:
    a folder, /dev/full, /sys (no file can be created there, even by root), a read-only file system."""
    for flag in ("--stats", "--breaks"):
        refused_at_once(pbd, [flag, out], [out, "folder"])
        refused_at_once(pbd, [flag, "/dev/full"], ["/dev/full", "No space left"])
        if os.path.isdir("/sys/kernel"):
            refused_at_once(pbd, [flag, "/sys/kernel/pbd.csv"], ["/sys/kernel/pbd.csv", "cannot open"])
    if os.path.isdir("/sys/kernel"):
        refused_at_once(pbd, ["--frames", "/sys/kernel"], ["/sys/kernel/rope.probe", "cannot"])
    ro = read_only_folder(out)
    if ro:
        try:
            refused_at_once(pbd, ["--stats", os.path.join(ro, "s.csv")], ["s.csv", "Read-only file system"])
            refused_at_once(pbd, ["--frames", ro], ["rope.probe", "Read-only file system"])
        finally:
            subprocess.run(["umount", ro])


def check_frame_fifo(pbd, out):
    """A FIFO that took a frame's name is refused by name; waiting for a reader would block forever."""
    for fmt, taken in (("obj", "rope_00001.obj"), ("vtu", "rope_00001.vtu"), ("vtu", "rope.pvd")):
        frames = tempfile.mkdtemp(dir=out, prefix="fifo_")
        os.mkfifo(os.path.join(frames, taken))
        try:
            r = subprocess.run([pbd, "run", "rope", "--steps", "3", "--frames", frames, "--format", fmt],
                               capture_output=True, text=True, timeout=120)
        except subprocess.TimeoutExpired:
            fail(f"a FIFO named {taken} in --frames: pbd blocked on it")
        if r.returncode != 2 or taken not in r.stderr or "not a regular file" not in r.stderr:
            fail(f"a FIFO named {taken}: status {r.returncode}, stderr {r.stderr!r}")
        if not stat.S_ISFIFO(os.stat(os.path.join(frames, taken)).st_mode):
            fail(f"the FIFO {taken} was replaced")
        if any(name.endswith(".tmp") for name in os.listdir(frames)):
            fail(f"a FIFO named {taken}: temporaries left: {os.listdir(frames)}")


def main(pbd, out, sanitized):
    os.makedirs(out, exist_ok=True)
    check_breaks(pbd, out)
    check_hash_and_stats(pbd, out)
    check_threads(pbd)
    check_write_errors(pbd, out)
    check_scene_errors(pbd, out, sanitized)
    check_nonfinite(pbd, out)
    check_early_refusals(pbd, out)
    check_frame_fifo(pbd, out)
    print("ok: --breaks, state hash and --expect-hash, --stats, --threads, write errors, scene names, size limits, "
          "float range, OBJ volume errors, a non-finite state, early refusals, FIFOs among the frames")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], "--sanitized" in sys.argv[3:])
