#!/usr/bin/env python3
"""SIGINT and SIGTERM during `pbd run --frames DIR --stats FILE`, sent after 1, 3 and 6 frames are on disk (and at
a few offsets within a frame, so that some land during a write): pbd exits with 128 + the signal's number, saying
so; every frame present is complete and finite and the .pvd lists every one; the statistics have one complete row
per step whose frame was written (frames 0..n, rows 1..n); no temporary remains. Then SIGKILL: nothing can run, so
what it leaves is checked after the next run into the same folder, which removes the temporaries of dead processes.

The run is polled for its frames, never timed by a fixed sleep, so that the slower sanitizer builds pass as well.

Usage: check_signals.py PBD OUT_DIR"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_outputs import FRAME, Invalid, check_frames, check_stats  # noqa: E402

STEM = "signals"
WAIT = 300  # s: only a hang is this slow, even under ASan on a loaded machine


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def default_signals():  # a caller that ignores SIGINT (a shell's background job) would make pbd ignore it too
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def frames_on_disk(folder):
    try:
        return sum(1 for name in os.listdir(folder) if FRAME.match(name))
    except FileNotFoundError:
        return 0


def start(pbd, scene, folder, stats, fmt):
    shutil.rmtree(folder, ignore_errors=True)
    cmd = [pbd, "run", scene, "--steps", "100000000", "--frames", folder, "--format", fmt, "--stats", stats]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=default_signals)


def wait_for_frames(p, folder, count):
    deadline = time.monotonic() + WAIT
    while frames_on_disk(folder) < count:
        if p.poll() is not None:
            fail(f"pbd exited ({p.returncode}) before {count} frames: {p.stderr.read()}")
        if time.monotonic() > deadline:
            p.kill()
            fail(f"no {count} frames in {WAIT} s")
        time.sleep(0.005)


def interrupt(pbd, scene, out, sig, fmt, frames, offset):
    folder = os.path.join(out, f"{sig.name}_{fmt}_{frames}")
    stats = folder + ".csv"
    p = start(pbd, scene, folder, stats, fmt)
    wait_for_frames(p, folder, frames)
    time.sleep(offset)
    p.send_signal(sig)
    try:
        summary, err = p.communicate(timeout=WAIT)
    except subprocess.TimeoutExpired:
        p.kill()
        fail(f"{sig.name}: pbd did not stop within {WAIT} s")
    where = f"{sig.name} after {frames} frames (+{offset} s), {fmt}"
    if p.returncode != 128 + sig.value or f"stopped by {sig.name}" not in err:
        fail(f"{where}: status {p.returncode} (expected {128 + sig.value}), stderr {err!r}")
    # The summary of the steps taken, as a whole run prints it.
    for line in ("time per step:", "errors (RMS at the final frame | averaged over the", "wrote ", "state hash: "):
        if line not in summary:
            fail(f"{where}: no {line!r} in the summary on stdout: {summary!r}")
    try:
        steps = check_frames(folder, STEM, fmt)
        rows = check_stats(stats)
    except Invalid as e:
        fail(f"{where}: {e}")
    if steps != list(range(len(rows) + 1)):
        fail(f"{where}: frames of steps {steps[:3]}...{steps[-3:]} but statistics of steps 1..{len(rows)}")
    return len(steps)


def killed(pbd, scene, out):
    """SIGKILL: no handler runs. A frame is written as an unnamed file (O_TMPFILE), so the kill leaves at most a
    complete temporary of a dead process, which the next run into the folder removes."""
    folder = os.path.join(out, "SIGKILL")
    stats = folder + ".csv"
    p = start(pbd, scene, folder, stats, "obj")
    wait_for_frames(p, folder, 3)
    p.kill()
    p.communicate(timeout=WAIT)
    dead = os.fork()  # a pid that no process has any more
    if dead == 0:
        os._exit(0)
    os.waitpid(dead, 0)
    with open(os.path.join(folder, f"{STEM}_00001.obj.{dead}.0.tmp"), "w") as f:  # as a kill mid-rename leaves
        f.write("v 0 0 0\n")
    r = subprocess.run([pbd, "run", scene, "--steps", "1", "--frames", folder], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"the run after SIGKILL: status {r.returncode}: {r.stderr}")
    left = [name for name in os.listdir(folder) if not FRAME.match(name)]
    if left:
        fail(f"SIGKILL, then a run into the same folder: {left} remain")
    try:
        check_frames(folder, STEM, "obj")
    except Invalid as e:
        fail(f"SIGKILL: {e}")


def main(pbd, out):
    os.makedirs(out, exist_ok=True)
    # A 100x100 cloth (10,000 particles): frames of about 1 MB, long enough to be interrupted while written.
    scene = os.path.join(out, "signals.json")
    with open(scene, "w") as f:
        json.dump({"name": STEM, "dt": 0.01, "substeps": 1, "iterations": 2,
                   "bodies": [{"type": "cloth", "resolution": 100, "stretch": {}}]}, f)
    written = 0
    for sig in (signal.SIGINT, signal.SIGTERM):
        for frames, offset, fmt in ((1, 0.0, "vtu"), (3, 0.003, "obj"), (6, 0.011, "vtu")):
            written += interrupt(pbd, scene, out, sig, fmt, frames, offset)
    killed(pbd, scene, out)
    print(f"ok: SIGINT and SIGTERM at 3 points each ({written} frames checked), SIGKILL then a run")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
