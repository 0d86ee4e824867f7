#!/usr/bin/python3
"""Test of scripts/plot_study.py on a small report made here (two cloth scenes, two solvers on 1 and 2 threads,
three splits, some timings busy), in seconds and without pbd:

    /usr/bin/python3 check_plots.py SCRIPTS_DIR WORK_DIR

Runs the script's main with matplotlib's figures kept, and checks with matplotlib's API: every plot is written as PNG and SVG, the distance to the converged reference among them;
every figure carries the machine, the commit, the date and the version (and a report without a version the rest); a busy point keeps
its solver's colour, marker and fill and has a ring of that colour around it, and no point is drawn in another
solver's colour; the thread-scaling plot rings the speed-ups of busy timings. Exits non-zero on the first failure.
"""
import copy
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

PLOTS = ["speed_error", "headline", "reference_distance", "time_to_accuracy", "convergence", "thread_scaling",
         "ns_per_projection"]
CPU, COMMIT, DATE, VERSION = "Test CPU 9000", "abc123def456", "2026-11-28T12:00:00Z", "0.9.1"


def fail(message):
    print("check_plots: FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def report():
    """A schema-3 report: serial on 1 thread and colored on 1 and 2, at 1x1, 1x2 and 2x1, on cloth30 and cloth100;
    colored's 2-thread timings of cloth100 busy."""
    scenes = [{"name": "cloth30", "particles": 900, "primary_error": "stretch_pct", "family": "cloth"},
              {"name": "cloth100", "particles": 10000, "primary_error": "stretch_pct", "family": "cloth"}]
    records = []
    for sc, scale in (("cloth30", 1.0), ("cloth100", 11.0)):
        for solver, threads in (("serial", 1), ("colored", 1), ("colored", 2)):
            for sub, it in ((1, 1), (1, 2), (2, 1)):
                ms = scale * sub * it * (1.0 if threads == 1 else 0.6) * (1.3 if solver == "serial" else 1.0)
                records.append({
                    "scene": sc, "solver": solver, "threads": threads, "substeps": sub, "iterations": it,
                    "budget": sub * it, "ms_per_step": ms, "ms_per_step_min": 0.95 * ms, "ms_per_step_max": 1.1 * ms,
                    "primary_error": 4.0 / (sub * it) * (1.2 if solver == "serial" else 1.0),
                    "ref_error_mm": 30.0 / (sub * it), "particles": 900 if sc == "cloth30" else 10000,
                    "ns_per_projection": 50.0 * (1.0 if threads == 1 else 0.6),
                    "busy": sc == "cloth100" and solver == "colored" and threads == 2,
                    "pareto": solver == "colored" and threads == 2, "variant": "plain"})
    best = [{"scene": r["scene"], "solver": r["solver"], "threads": r["threads"], "budget": r["budget"],
             "substeps": r["substeps"], "iterations": r["iterations"], "primary_error": r["primary_error"]}
            for r in records if r["substeps"] == 1]
    return {"schema": 3, "scenes": scenes, "records": records, "best_splits": best,
            "references": [{"scene": n, "converged": n == "cloth30", "solver": "colored", "substeps": 64,
                            "iterations": 1, "seconds": 1.0, "failures": ["changes at half its budget"] * (n != "cloth30")}
                           for n in ("cloth30", "cloth100")],
            "shared_nothing": [], "measures": {"stretch_pct": {"label": "stretch", "type": "stretch", "unit": "%"}},
            "study": {"mode": "study", "date": DATE, "git_commit": COMMIT, "busy": True, "pbd_version": VERSION,
                      "options": {"target_pct": 1.0},
                      "context": {"cpu": CPU, "cores": 2, "date": DATE, "commit": COMMIT}}}


def run(plot_study, doc, out):
    """plot_study's main on `doc`, returning its figures (kept from plt.close) by file stem."""
    path = os.path.join(out, "study.json")
    os.makedirs(out, exist_ok=True)
    with open(path, "w") as f:
        json.dump(doc, f)
    figures, close, save = [], plt.close, plot_study.save
    stems = {}

    def keep(fig, out_dir, stem, *args, **kw):
        stems[stem] = fig
        return save(fig, out_dir, stem, *args, **kw)
    plot_study.save, plot_study.plt.close = keep, figures.append
    try:
        check(plot_study.main(["plot_study.py", path, out]) == 0, "plot_study.py failed")
    finally:
        plot_study.save, plot_study.plt.close = save, close
    for stem in PLOTS:
        for ext in ("png", "svg"):
            file = os.path.join(out, f"{stem}.{ext}")
            check(os.path.isfile(file) and os.path.getsize(file) > 0, f"{file} not written")
        check(stem in stems, f"{stem}: no figure")
    return stems


def stamp_of(fig):
    texts = [t.get_text() for t in fig.texts if t.get_gid() == "stamp"]
    check(len(texts) == 1, f"{len(texts)} stamps on a figure")
    return texts[0]


def same_colour(a, b):
    return mcolors.to_rgba(a) == mcolors.to_rgba(b)


def check_busy_points(plot_study, fig, stem, busy_points):
    """On the figure of `stem`: the solvers' points in their own colours and markers, and a ring of the same colour at
    each of `busy_points` ({(x, y): solver}) and nowhere else."""
    points, rings = {}, {}
    for ax in fig.axes:
        for line in ax.get_lines():
            gid, xy = line.get_gid(), list(zip(*line.get_data()))
            if gid == "busy":
                for p in xy:
                    rings[p] = line.get_markeredgecolor()
                check(line.get_markerfacecolor() == "none", f"{stem}: a busy ring is filled")
            elif gid in plot_study.STYLE:
                colour, marker = plot_study.solver_style(gid)
                check(same_colour(line.get_color(), colour) and line.get_marker() == marker,
                      f"{stem}: {gid}'s points drawn in {line.get_color()} {line.get_marker()}, not its "
                      f"{colour} {marker}")
                for p in xy:
                    points[p] = gid
    check(set(rings) == set(busy_points), f"{stem}: rings at {sorted(rings)}, busy points at {sorted(busy_points)}")
    for p, solver in busy_points.items():
        check(points.get(p) == solver, f"{stem}: the busy point {p} is not drawn as a {solver} point")
        check(same_colour(rings[p], plot_study.solver_style(solver)[0]), f"{stem}: the ring at {p} is {rings[p]}")


def main():
    if len(sys.argv) != 3:
        fail(__doc__)
    scripts, work = sys.argv[1:]
    sys.path.insert(0, scripts)
    import plot_study
    doc = report()
    figures = run(plot_study, doc, os.path.join(work, "with_version"))
    for stem, fig in figures.items():
        text = stamp_of(fig)
        for part in (CPU, "2 cores", COMMIT, DATE, "pbd " + VERSION):
            check(part in text, f"{stem}: the stamp {text!r} lacks {part!r}")
    busy = [r for r in doc["records"] if r["busy"]]
    check_busy_points(plot_study, figures["speed_error"], "speed_error",
                      {(r["ms_per_step"], r["primary_error"]): r["solver"] for r in busy})
    check_busy_points(plot_study, figures["reference_distance"], "reference_distance",
                      {(r["ms_per_step"], r["ref_error_mm"]): r["solver"] for r in busy})
    # Thread scaling: colored on cloth100 (the second scene by size, at x = 1) from busy 2-thread timings: ringed.
    scaling = [line for ax in figures["thread_scaling"].axes for line in ax.get_lines() if line.get_gid() == "busy"]
    check(len(scaling) == 1 and list(zip(*scaling[0].get_data()))[0][1] > 1 and
          0.5 < list(zip(*scaling[0].get_data()))[0][0] < 1.5, "thread_scaling: no ring on cloth100's colored speed-up")
    check(same_colour(scaling[0].get_markeredgecolor(), plot_study.solver_style("colored")[0]),
          "thread_scaling: the ring is not colored's colour")
    ref_texts = [t.get_text() for ax in figures["reference_distance"].axes for t in ax.texts]
    check(any("not converged" in t for t in ref_texts), "reference_distance: cloth100's reference not marked")
    # Without a version (reports before it had one): the rest of the stamp, no "pbd".
    plain = copy.deepcopy(doc)
    del plain["study"]["pbd_version"]
    text = plot_study.stamp(plain)
    check(COMMIT in text and "pbd" not in text, f"without a version: the stamp {text!r}")
    # A merge of several machines (`pbd study merge --allow-mixed-machines`): cpu names them all, no core count.
    mixed = copy.deepcopy(doc)
    mixed["study"]["context"].update(cpu="2 machines: A (2 cores); B (4 cores)", cores=None, mixed_machines=True)
    text = plot_study.stamp(mixed)
    check("2 machines: A (2 cores); B (4 cores)" in text and "None" not in text and "? cores" not in text,
          f"mixed machines: the stamp {text!r}")
    print(f"check_plots: OK: {len(PLOTS)} plots stamped with machine, commit, date and version; busy points in "
          f"their solvers' colours, ringed")


if __name__ == "__main__":
    main()
