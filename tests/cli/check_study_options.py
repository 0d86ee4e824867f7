#!/usr/bin/env python3
"""`pbd study` refuses what it would otherwise ignore or misreport (issue 48), each a usage error naming the option:

1. An option given an empty value (`--budgets ''`, `--shard ''`, ...; and `pbd study merge`'s): to the study an
   empty value is the option not given, so its default ran in silence.
2. `--threads` above what the machine runs: its points would be reported as timed on threads that never ran.
   `--estimate` runs nothing and may plan for another machine (scripts/slurm-study checks the nodes' options on the
   machine that submits them).
3. A scene file that is not a regular file (a FIFO would block the study's first read), refused before anything runs.

Usage: check_study_options.py PBD OUT_DIR"""
import os
import re
import subprocess
import sys

ERROR_LINE = re.compile(r"pbd: error: \S.*\n")
# Options of `pbd study` that take a value, with a valid one (what they are given besides the empty one).
VALUE_OPTIONS = ["--scene", "--solvers", "--threads", "--budgets", "--split", "--precision", "--reference",
                 "--reference-solver", "--variants", "--format", "--json", "--plots", "--shard", "--commit",
                 "--plot-script", "--python"]


def fail(msg):
    print(f"check_study_options.py: FAIL: {msg}")
    sys.exit(1)


def run(pbd, args, expect):
    # A timeout: what used to block (a FIFO) must be refused at once.
    r = subprocess.run([pbd] + args, capture_output=True, text=True, timeout=120)
    if r.returncode != expect:
        fail(f"pbd {' '.join(args)}: status {r.returncode} (expected {expect})\nstderr: {r.stderr}")
    return r


def usage_error(pbd, args, words):
    r = run(pbd, args, expect=2)
    if not ERROR_LINE.fullmatch(r.stderr) or any(w not in r.stderr for w in words):
        fail(f"pbd {' '.join(args)}: expected one line 'pbd: error: ...' with {words}, got {r.stderr!r}")


def machine_threads():
    """The CPUs this process may run on: oneTBB's max_allowed_parallelism by default."""
    return len(os.sched_getaffinity(0))


def main(pbd, out):
    os.makedirs(out, exist_ok=True)
    for option in VALUE_OPTIONS:
        usage_error(pbd, ["study", option, ""], [f"{option}: the value is empty"])
    for option in ("--json", "--plots", "--format"):
        usage_error(pbd, ["study", "merge", "a.json", option, ""], [f"{option}: the value is empty"])
    usage_error(pbd, ["study", "merge", ""], ["reports: the value is empty"])

    most = machine_threads()
    study = ["study", "--scene", "rope", "--variants", "plain", "--solvers", "colored"]
    for threads in (str(most + 1), f"1,{most + 1}", "1000"):
        usage_error(pbd, study + ["--threads", threads],
                    [f"--threads: {threads.split(',')[-1]} is more than the {most} threads this machine runs"])
    run(pbd, study + ["--threads", f"1,{most + 1}", "--estimate"], expect=0)

    fifo = os.path.join(out, "scene-fifo.json")
    if os.path.exists(fifo):
        os.remove(fifo)
    os.mkfifo(fifo)
    usage_error(pbd, ["study", "--scene", fifo, "--estimate"], [fifo, "is not a regular file"])
    print("ok: empty option values refused, --threads above the machine refused (not with --estimate), a FIFO scene "
          "refused before it is read")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(*sys.argv[1:])
