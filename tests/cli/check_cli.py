#!/usr/bin/env python3
"""The command line's conventions, tried as a new user would (issue 47):

1. Every usage error (a bare `pbd`, an unknown option, a value out of range, a missing argument) exits with status 2
   and one line `pbd: error: ...` on stderr, as pbd's own errors do; --help on every subcommand and --version exit 0.
2. An option that does nothing without another one (or next to another one) is refused, naming both.
3. Every scene `pbd list` shows works in `pbd run`, `pbd color` and `pbd study --scene`.
4. The plot script and a Python with matplotlib are checked before a study's first point: a missing script (given,
   or share/pbd/plot_study.py beside a moved program), an interpreter that does not start or lacks matplotlib.
5. `pbd study --shard auto` reads a Slurm job array's index and count, and refuses outside a contiguous array.

Usage: check_cli.py PBD VERSION OUT_DIR [--sanitized]"""
import json
import os
import re
import shutil
import subprocess
import sys

ERROR_LINE = re.compile(r"pbd: error: \S.*\n")
# The variables of a Slurm job array: cleared for the tests that set them by hand.
SLURM = ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_MAX",
         "SLURM_ARRAY_TASK_STEP", "SLURM_ARRAY_JOB_ID"]
# A study of one small scene that takes about a second: for what must be seen to run (or not to start).
TINY = ["study", "--quick", "--scene", "rope", "--budgets", "2", "--threads", "1", "--solvers", "colored",
        "--variants", "plain"]


def fail(msg):
    print(f"check_cli.py: FAIL: {msg}")
    sys.exit(1)


def run(pbd, args, expect=0, env=None, cwd=None):
    r = subprocess.run([pbd] + args, capture_output=True, text=True, env=env, cwd=cwd)
    if r.returncode != expect:
        fail(f"pbd {' '.join(args)}: status {r.returncode} (expected {expect})\nstdout: {r.stdout[-2000:]}\n"
             f"stderr: {r.stderr}")
    return r


def usage_error(pbd, args, words=(), env=None, cwd=None):
    """Status 2 and exactly one line in pbd's style, holding every word."""
    r = run(pbd, args, expect=2, env=env, cwd=cwd)
    if not ERROR_LINE.fullmatch(r.stderr):
        fail(f"pbd {' '.join(args)}: stderr is not one line 'pbd: error: ...': {r.stderr!r}")
    for w in words:
        if w not in r.stderr:
            fail(f"pbd {' '.join(args)}: {w!r} not in the error: {r.stderr!r}")
    return r


def check_exit_codes(pbd, version):
    usage_error(pbd, [], ["a subcommand is required", "study, color, run, list"])
    usage_error(pbd, ["frobnicate"], ["unknown subcommand 'frobnicate'"])
    usage_error(pbd, ["--frobnicate"], ["--frobnicate"])
    usage_error(pbd, ["run", "cloth", "--steps", "0"], ["--steps", "see `pbd run --help`"])
    usage_error(pbd, ["run", "cloth", "--steps", "many"], ["--steps"])
    usage_error(pbd, ["run"], ["scene", "see `pbd run --help`"])
    usage_error(pbd, ["run", "cloth", "--solver", "gauss"], ["--solver", "gauss"])
    usage_error(pbd, ["run", "cloth", "--frobnicate"], ["--frobnicate"])
    usage_error(pbd, ["color"], ["scene"])
    usage_error(pbd, ["color", "cloth", "--algorithm", "best"], ["--algorithm"])
    usage_error(pbd, ["list", "extra"], ["extra"])
    usage_error(pbd, ["study", "--threads"], ["--threads"])
    usage_error(pbd, ["study", "--steps", "0"], ["--steps"])
    usage_error(pbd, ["study", "merge"], ["reports", "see `pbd study merge --help`"])
    usage_error(pbd, ["study", "--solvers", "gauss"], ["--solvers", "gauss"])  # pbd's own check, same style
    for sub in ([], ["run"], ["color"], ["list"], ["study"], ["study", "merge"]):
        r = run(pbd, sub + ["--help"])
        if "Usage:" not in r.stdout or r.stderr:
            fail(f"pbd {' '.join(sub)} --help: no usage on stdout, or something on stderr: {r.stderr!r}")
    r = run(pbd, ["--version"])
    if r.stdout != f"pbd {version}\n" or r.stderr:
        fail(f"pbd --version printed {r.stdout!r} (expected 'pbd {version}')")


def check_option_rules(pbd, out):
    folder = os.path.join(out, "rules")
    os.makedirs(folder, exist_ok=True)
    rules = [
        (["run", "cloth", "--format", "vtu"], ["--format does nothing without --frames"]),
        (["run", "cloth", "--every", "2"], ["--every does nothing without --frames"]),
        (["run", "cloth", "--solver", "jacobi", "--sweep-order", "symmetric"], ["--sweep-order", "--solver jacobi"]),
        (["run", "cloth", "--solver", "serial", "--threads", "2"], ["--threads", "--solver serial"]),
        (["run", "cloth", "--solver", "serial-colored", "--threads", "2"], ["--threads", "--solver serial-colored"]),
        (["run", "cloth", "--solver", "serial", "--chebyshev", "0.5"], ["--chebyshev", "--solver serial"]),
        (["study", "--split", "1x4"], ["--split does nothing without --scaling"]),
        (["study", "--plots", "p", "--estimate"], ["--plots does nothing with --estimate"]),
        (["study", "--plot-script", "x.py"], ["--plot-script does nothing without --plots"]),
        (["study", "--python", "python3"], ["--python does nothing without --plots"]),
        (["study", "merge", "a.json", "--python", "python3"], ["--python does nothing without --plots"]),
        (["study", "merge", "a.json", "--plot-script", "x.py"], ["--plot-script does nothing without --plots"]),
        (["study", "--quick", "merge", "a.json"], ["--quick is an option of `pbd study`"]),
        (["study", "--json", "j.json", "merge", "a.json"], ["--json is an option of `pbd study`"]),
    ]
    for option, value in (("--budgets", "2"), ("--reference", "8x1"), ("--reference-solver", "colored"),
                          ("--reference-max", "8"), ("--reference-seconds", "5"), ("--variants", "plain"),
                          ("--target", "2")):
        rules.append((["study", "--scaling", option, value], [f"{option} does nothing with --scaling"]))
    for option, value in (("--json", "j.json"), ("--format", "csv"), ("--commit", "abc")):
        rules.append((["study", "--estimate", option, value], [f"{option} does nothing with --estimate"]))
    for args, words in rules:
        usage_error(pbd, args, words, cwd=folder)
    if os.listdir(folder):
        fail(f"refused options left files: {os.listdir(folder)}")
    # From the environment, not the command line, they ask for nothing: the study and its --estimate run.
    env = dict(os.environ, PBD_PYTHON="python3", PBD_PLOT_SCRIPT="x.py", PBD_COMMIT="abc")
    run(pbd, ["study", "--estimate", "--scene", "rope"], env=env)


def check_scenes(pbd, sanitized):
    listed = [line.split()[:2] for line in run(pbd, ["list"]).stdout.splitlines() if line.strip()]
    names = [name for name, _ in listed]
    for expected in ("cloth", "rope", "cloth30", "cloth300", "cloth30-rest", "chain30"):
        if expected not in names:
            fail(f"pbd list does not show {expected}: {names}")
    for name, particles in listed:
        # Under the sanitizers the million-particle cloth alone takes minutes to build and color; cloth300 takes
        # the same path (any cloth<N>), and Release runs it too.
        if sanitized and int(particles) > 100000:
            continue
        r = run(pbd, ["run", name, "--steps", "1"])
        if not r.stdout.startswith(f"# scene {name}:"):
            fail(f"pbd run {name}: header {r.stdout.splitlines()[:1]}")
        r = run(pbd, ["color", name])
        if not r.stdout.startswith(f"# scene {name} "):
            fail(f"pbd color {name}: header {r.stdout.splitlines()[:1]}")
        r = run(pbd, ["study", "--scene", name, "--variants", "plain", "--estimate"])
        if not any(line.split()[:1] == [name] for line in r.stdout.splitlines()):
            fail(f"pbd study --scene {name} --estimate: no line for it:\n{r.stdout}")
    for cmd in (["run"], ["color"], ["study", "--scene"]):
        usage_error(pbd, cmd + ["cloth1"], ["unknown scene \"cloth1\"", "cloth300", "cloth<N>"])


def no_progress(r, args):
    if "pbd study: " in r.stderr:
        fail(f"pbd {' '.join(args)} started the study before refusing its plots: {r.stderr!r}")


def check_plot_tools(pbd, out):
    plots = os.path.join(out, "plots")
    args = TINY + ["--plots", plots, "--plot-script", "/no/such/plot_study.py"]
    no_progress(usage_error(pbd, args, ["/no/such/plot_study.py", "--plot-script"]), args)
    args = TINY + ["--plots", plots, "--python", "/no/such/python3"]
    no_progress(usage_error(pbd, args, ["cannot start the interpreter \"/no/such/python3\""]), args)
    fake = os.path.join(out, "python-without-matplotlib")
    with open(fake, "w") as f:
        f.write("#!/bin/sh\necho 'ModuleNotFoundError' >&2\nexit 1\n")
    os.chmod(fake, 0o755)
    args = TINY + ["--plots", plots, "--python", fake]
    no_progress(usage_error(pbd, args, [fake, "cannot import matplotlib"]), args)
    # A program moved away from its share/pbd: the default script is missing (its scenes are given by PBD_SCENE_DIR).
    scenes = os.path.realpath(os.path.join(os.path.dirname(os.path.realpath(pbd)), "..", "share", "pbd", "scenes"))
    moved = os.path.join(out, "moved", "bin")
    os.makedirs(moved, exist_ok=True)
    shutil.copy2(pbd, os.path.join(moved, "pbd"))
    env = dict(os.environ, PBD_SCENE_DIR=scenes)
    env.pop("PBD_PLOT_SCRIPT", None)
    args = TINY + ["--plots", plots]
    r = usage_error(os.path.join(moved, "pbd"), args, ["share/pbd/plot_study.py", "--plot-script"], env=env)
    no_progress(r, args)
    if os.path.exists(plots):
        fail(f"a refused study made {plots}")


def slurm_env(**values):
    env = {k: v for k, v in os.environ.items() if k not in SLURM}
    env.update({f"SLURM_ARRAY_TASK_{k}": str(v) for k, v in values.items()})
    return env


def check_shard_auto(pbd):
    usage_error(pbd, TINY + ["--shard", "auto"], ["not in a Slurm job array", "SLURM_ARRAY_TASK_ID"],
                env=slurm_env())
    for values, shard in ((dict(ID=6, MIN=5, MAX=7, COUNT=3, STEP=1), "2/3"), (dict(ID=1, COUNT=2), "1/2")):
        doc = json.loads(run(pbd, TINY + ["--shard", "auto", "--format", "json"], env=slurm_env(**values)).stdout)
        if doc["study"]["options"]["shard"] != shard:
            fail(f"--shard auto under {values}: shard {doc['study']['options']['shard']}, expected {shard}")
    usage_error(pbd, TINY + ["--shard", "auto"], ["not contiguous"], env=slurm_env(ID=3, MIN=1, MAX=5, COUNT=3, STEP=2))
    usage_error(pbd, TINY + ["--shard", "auto"], ["outside the array"], env=slurm_env(ID=9, MIN=1, MAX=4))
    usage_error(pbd, TINY + ["--shard", "auto"], ["number of parts"], env=slurm_env(ID=1))


def main(pbd, version, out, sanitized=False):
    os.makedirs(out, exist_ok=True)
    check_exit_codes(pbd, version)
    check_option_rules(pbd, out)
    check_scenes(pbd, sanitized)
    check_plot_tools(pbd, out)
    check_shard_auto(pbd)
    print("ok: usage errors (status 2, one style), --help and --version, option rules, every listed scene in run, "
          "color and study, the plot tools checked first, --shard auto")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5) or sys.argv[4:] not in ([], ["--sanitized"]):
        sys.exit(__doc__)
    main(*sys.argv[1:4], sanitized=sys.argv[4:] == ["--sanitized"])
