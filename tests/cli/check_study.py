#!/usr/bin/python3
"""Smoke test of `pbd study --quick`. Usage: check_study.py PBD_EXECUTABLE OUT_DIR"""
import json
import os
import subprocess
import sys
import time

REQUIRED = ["scene", "solver", "threads", "iterations", "substeps", "steps", "precision", "ms_per_step",
            "ms_per_step_min", "particles", "constraints", "colors", "rms_violation", "max_violation", "ref_error",
            "state_hash"]
ALSO = ["repeats", "ns_per_projection", "violations", "ref_error_max", "trajectory_error", "energy_drift",
        "repeatable"]


def fail(message):
    print("check_study.py: FAIL:", message)
    sys.exit(1)


def main(pbd, out):
    os.makedirs(out, exist_ok=True)
    report = os.path.join(out, "study.json")
    start = time.time()
    run = subprocess.run([pbd, "study", "--quick", "--json", report, "--plots", out], capture_output=True, text=True)
    seconds = time.time() - start
    if run.returncode != 0:
        fail(f"pbd study --quick exited with {run.returncode}:\n{run.stderr}")
    # Reported, not asserted: timings belong to benchmarks, and this test also runs under the sanitizers.
    print(f"pbd study --quick took {seconds:.1f} s")
    if "left)" not in run.stderr:
        fail("no progress lines with the time left on stderr")
    with open(report) as f:
        doc = json.load(f)
    for key in ("command", "date", "machine", "git_commit", "options"):
        if key not in doc["study"]:
            fail(f"study has no {key}")
    records = doc["records"]
    if not records:
        fail("no records")
    scenes = {r["scene"] for r in records}
    for r in records:
        for key in REQUIRED + ALSO:
            if key not in r:
                fail(f"record {r.get('scene')}/{r.get('solver')} has no {key}")
        for key in ("ms_per_step", "ms_per_step_min", "ref_error", "rms_violation"):
            if not (isinstance(r[key], (int, float)) and r[key] >= 0):
                fail(f"record {r['scene']}/{r['solver']}: {key} = {r[key]!r}")
        if not r["repeatable"]:
            fail(f"record {r['scene']}/{r['solver']}/{r['threads']}: runs ended in different states")
        if r["ms_per_step_min"] > r["ms_per_step"]:
            fail(f"record {r['scene']}/{r['solver']}: min above median")
    # Determinism: the colored (and Jacobi) solver ends in the same bits on 1 and 2 threads.
    for solver in ("colored", "jacobi"):
        by_key = {}
        for r in records:
            if r["solver"] == solver:
                by_key.setdefault((r["scene"], r["iterations"], r["substeps"]), {})[r["threads"]] = r["state_hash"]
        if not by_key:
            fail(f"no {solver} records")
        for key, hashes in by_key.items():
            if sorted(hashes) != [1, 2]:
                fail(f"{solver} {key}: threads {sorted(hashes)}, expected 1 and 2")
            if len(set(hashes.values())) != 1:
                fail(f"{solver} {key}: state hashes differ across threads: {hashes}")
    if len(doc["references"]) != len(scenes):
        fail("expected one reference per scene")
    for name in ("speed_error.png", "thread_scaling.png", "ns_per_projection.png"):
        if not os.path.getsize(os.path.join(out, name)):
            fail(f"plot {name} missing")
    # Bad options: status 2 and a message that lists the valid values.
    for args, expected in ((["--solvers", "serial,gauss"], "serial, serial-colored, colored, jacobi, block"),
                           (["--scene", "no-such-scene"], "cloth100"),
                           (["--threads", "0"], "out of range")):
        bad = subprocess.run([pbd, "study", "--quick"] + args, capture_output=True, text=True)
        if bad.returncode != 2 or expected not in bad.stderr:
            fail(f"{args}: status {bad.returncode}, stderr {bad.stderr!r}")
    print(f"ok: {len(records)} records over {len(scenes)} scenes, every field present, colored/jacobi hashes equal on 1 "
          "and 2 threads")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
