#!/usr/bin/env python3
"""`pbd study merge` joins only the whole set of one study's shards, and every report names pbd's version (issue 47).

Two shards of a tiny study (about a second each) are merged; then copies of them with one field changed are refused,
naming the file and the field: an incomplete set (1 of 2), a shard given twice, a whole run next to a shard, other
options, another pbd version, another commit, another build, another machine (CPU or cores). So is what pbd did not
write (issue 48), at once and naming the file and the key: a FIFO or a folder, an empty list of rounds, nesting
150,000 deep, a missing key, corrupted values (1e30 threads, 0 substeps, negative times, a hash that is not hex). --allow-mixed-machines
joins the other machine's shard, and the merged report then lists each machine and its context claims none of them
(JSON and table). The study report and the merged one carry the version (study.pbd_version, context.pbd_version, the
table's first line).

Usage: check_merge.py PBD VERSION OUT_DIR"""
import copy
import json
import os
import subprocess
import sys

TINY = ["study", "--quick", "--scene", "rope", "--budgets", "2", "--threads", "1", "--solvers", "colored",
        "--variants", "plain"]


def fail(msg):
    print(f"check_merge.py: FAIL: {msg}")
    sys.exit(1)


def run(pbd, args, expect=0):
    # A timeout: a FIFO given as a report used to block the merge forever.
    r = subprocess.run([pbd] + args, capture_output=True, text=True, timeout=120)
    if r.returncode != expect:
        fail(f"pbd {' '.join(args)}: status {r.returncode} (expected {expect})\nstderr: {r.stderr}")
    return r


def refused(pbd, files, words, extra=()):
    r = run(pbd, ["study", "merge", *files, *extra], expect=2)
    if r.stderr.count("\n") != 1:
        fail(f"merge {files}: expected one line of error, got {r.stderr!r}")
    if not r.stderr.startswith("pbd: error: ") or any(w not in r.stderr for w in words):
        fail(f"merge {files}: expected an error with {words}, got {r.stderr!r}")


def load(path):
    with open(path) as f:
        return json.load(f)


def variant(out, doc, name, edit):
    """A copy of the report `doc` with `edit` applied, written as OUT/name."""
    changed = copy.deepcopy(doc)
    edit(changed)
    path = os.path.join(out, name)
    with open(path, "w") as f:
        json.dump(changed, f)
    return path


def check_version(doc, table, version, what):
    if doc["study"].get("pbd_version") != version or doc["study"]["context"].get("pbd_version") != version:
        fail(f"{what}: study.pbd_version {doc['study'].get('pbd_version')!r}, context.pbd_version "
             f"{doc['study']['context'].get('pbd_version')!r}, expected {version!r}")
    if not table.startswith(f"# pbd {version} study"):
        fail(f"{what}: the table's first line does not name pbd {version}: {table.splitlines()[:1]}")


def main(pbd, version, out):
    os.makedirs(out, exist_ok=True)
    a, b = os.path.join(out, "shard1.json"), os.path.join(out, "shard2.json")
    table = run(pbd, TINY + ["--shard", "1/2", "--json", a]).stdout
    run(pbd, TINY + ["--shard", "2/2", "--json", b])
    check_version(load(a), table, version, "a shard's report")
    merged = os.path.join(out, "merged.json")
    table = run(pbd, ["study", "merge", a, b, "--json", merged]).stdout
    doc = load(merged)
    check_version(doc, table, version, "the merged report")
    if len(doc["study"]["machines"]) != 1 or doc["study"]["machines"][0]["reports"] != [a, b]:
        fail(f"merged on one machine: study.machines {doc['study']['machines']}")
    if doc["study"]["context"].get("mixed_machines"):
        fail("shards of one machine are reported as mixed machines")

    shard2 = load(b)
    refused(pbd, [a], ["incomplete", "1 of 2", "missing 2/2"])
    refused(pbd, [a, a], [a, "shard 1/2 is given twice"])
    whole = variant(out, shard2, "whole.json", lambda d: d["study"]["options"].update(shard=None))
    refused(pbd, [a, whole], [whole, "study.options.shard"])
    of3 = variant(out, shard2, "of3.json", lambda d: d["study"]["options"].update(shard="2/3"))
    refused(pbd, [a, of3], [of3, "study.options.shard"])
    options = variant(out, shard2, "options.json", lambda d: d["study"]["options"].update(repeats=7))
    refused(pbd, [a, options], [options, "options differ"])
    for name, path, value in (("version", ("pbd_version",), "0.0.1"), ("commit", ("git_commit",), "0123abcd"),
                              ("flags", ("context", "flags"), "-O0"), ("cpu", ("context", "cpu"), "Other CPU 9000"),
                              ("cores", ("context", "cores"), 999)):
        def edit(d, path=path, value=value):
            d["study"][path[0]] = value if len(path) == 1 else {**d["study"][path[0]], path[1]: value}
        changed = variant(out, shard2, f"{name}.json", edit)
        refused(pbd, [a, changed], [changed, "study." + ".".join(path), json.dumps(value)])
    # Another machine, allowed: each machine is listed and none is claimed as the one.
    other = variant(out, shard2, "machine.json",
                    lambda d: d["study"]["context"].update(cpu="Other CPU 9000", cores=64, host="node7"))
    refused(pbd, [a, other], ["--allow-mixed-machines"])
    table = run(pbd, ["study", "merge", a, other, "--allow-mixed-machines", "--json", merged]).stdout
    doc = load(merged)
    machines = doc["study"]["machines"]
    if len(machines) != 2 or machines[1]["cpu"] != "Other CPU 9000" or machines[1]["reports"] != [other] or \
            machines[1]["hosts"] != ["node7"]:
        fail(f"--allow-mixed-machines: study.machines {machines}")
    context = doc["study"]["context"]
    first_cpu = load(a)["study"]["context"]["cpu"]
    if not context.get("mixed_machines") or context["cores"] is not None or "2 machines" not in context["cpu"] or \
            "Other CPU 9000" not in context["cpu"] or first_cpu not in context["cpu"]:
        fail(f"--allow-mixed-machines: the context claims one machine: {context}")
    if "2 machines" not in table.splitlines()[2] or " cores;" in table.splitlines()[2]:
        fail(f"--allow-mixed-machines: the table's machine line {table.splitlines()[2]!r}")
    # Mixed machines are allowed, not another commit.
    commit = variant(out, shard2, "commit2.json", lambda d: d["study"].update(git_commit="0123abcd"))
    refused(pbd, [a, commit], ["study.git_commit"], ["--allow-mixed-machines"])
    check_bad_reports(pbd, out, a, shard2)
    print("ok: the version in every report; merge refuses incomplete, repeated, mixed shards naming file and field; "
          "--allow-mixed-machines lists each machine; a report that pbd did not write is refused naming file and key")


def check_bad_reports(pbd, out, a, shard2):
    """What the issue 48 audit gave merge: each refused at once (no crash, no hang), naming the file and the key."""
    # Not regular files: a FIFO blocked the read forever; a folder failed as basic_filebuf::underflow.
    fifo = os.path.join(out, "fifo.json")
    if os.path.exists(fifo):
        os.remove(fifo)
    os.mkfifo(fifo)
    refused(pbd, [a, fifo], [fifo + ": cannot read the study report (not a regular file)"])
    refused(pbd, [a, out], [out + ": cannot read the study report (not a regular file)"])

    def set_key(*path, value):
        def edit(d):
            for key in path[:-1]:
                d = d[key]
            d[path[-1]] = value
        return edit

    def drop_options(d):
        del d["study"]["options"]

    def no_rounds(d):  # a tiny study on 1 thread has no shared-nothing run: one is added
        d["shared_nothing"] = [{"scene": "rope", "threads": 2, "speedups": [], "speedup": None, "speedup_min": None,
                                "speedup_max": None}]

    for name, edit, words in (
            ("no-rounds.json", no_rounds, ["shared_nothing[0].speedups: the list is empty"]),
            ("threads.json", set_key("records", 0, "threads", value=1e30),
             ["records[0].threads: 1e+30 is not an integer"]),
            ("substeps.json", set_key("records", 0, "substeps", value=0),
             ["records[0].substeps: 0 is out of range [1, 10000]"]),
            ("time.json", set_key("records", 0, "ms_per_step", value=-2.5),
             ["records[0].ms_per_step: -2.5 is out of range [0, "]),
            ("seconds.json", set_key("references", 0, "seconds", value=-1), ["references[0].seconds: -1 is out of"]),
            ("hash.json", set_key("records", 0, "state_hash", value="zz"),
             ["records[0].state_hash: \"zz\" is not 16 lower-case hex digits"]),
            ("no-options.json", drop_options, ["study.options: missing"])):
        refused(pbd, [a, variant(out, shard2, name, edit)], [os.path.join(out, name) + ": " + words[0]])
    # Nested 150,000 deep: copying it overflowed the stack.
    deep = os.path.join(out, "deep.json")
    text = json.dumps({**shard2, "study": {**shard2["study"], "context": {"cpu": "DEEP"}}})
    with open(deep, "w") as f:
        f.write(text.replace('"DEEP"', "[" * 150000 + "]" * 150000))
    refused(pbd, [a, deep], [deep + ": study.context.cpu[0]", "nested more than 64 deep"])


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
