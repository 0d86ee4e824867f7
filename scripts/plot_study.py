#!/usr/bin/python3
"""Plots of a `pbd study` JSON report, schema 3 (run with Debian's /usr/bin/python3, which has python3-matplotlib).

Usage: scripts/plot_study.py STUDY.json [OUT_DIR]

Writes into OUT_DIR (default: the JSON's folder), each figure as .png (150 dpi) and .svg; one without data is skipped:
  speed_error        per scene: primary error against ms per step (median, bars min..max), marker per solver, fill
                     per thread count; grey steps: the Pareto front, labelled SxI
  headline           the same for the largest cloth<N> measured at several splits alone
  time_to_accuracy   per scene with a % primary error measured at several budgets: run-averaged error against ms
                     per step, one line per solver and variant (plain, tethers, hierarchy, both) at its most threads
                     (its lower envelope: the fastest time for each error), and the target (1%): the README's figure
  reference_distance per scene with a converged reference: the one-step distance from it (ref_error_mm) against
                     ms per step, styled as speed_error
  convergence        per scene: primary error against sweeps per step, each solver at its most threads: all
                     iterations (1xN, solid), all substeps (Nx1, dashed), the best split per budget (big markers)
  thread_scaling     study mode: per scene, speed-up of each parallel solver from 1 thread to its most threads (median
                     over the splits, bar min..max), the ideal, and the shared-nothing ceiling of this machine;
                     scaling mode: per scene, speed-up against threads (scaling.strong), the ideal and shared-nothing
  ns_per_projection  cloth<N> family (2 or more scenes): ns per constraint projection against particles
  summary.md         context and warnings; the time per step to reach the target per scene, variant, solver and
                     threads; per scene the reference and its check, the best split per budget of each solver at its
                     most threads and the dominance check; in scaling mode the strong-scaling table
Every error is the report's: averaged over the run (a quasi-static scene: over its settled last quarter). A point
timed while the machine was busy (its record's "busy") keeps its solver's colour, marker and fill and gets a ring
of that colour around it. Every figure carries, above it at the right, the machine (CPU, cores), the commit, the
date and, when the report has one, pbd's version.
"""
import json
import math
import os
import statistics
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import FixedLocator, NullFormatter  # noqa: E402

plt.rcParams.update({"font.size": 8, "axes.titlesize": 9, "axes.labelsize": 8, "legend.fontsize": 8,
                     "xtick.labelsize": 7, "ytick.labelsize": 7, "svg.fonttype": "none"})
STYLE = {"serial": ("black", "o"), "colored": ("tab:blue", "s"), "jacobi": ("tab:orange", "^"),
         "block": ("tab:green", "D"), "serial-colored": ("tab:gray", "P")}  # solver -> (color, marker)
FILLS = ["full", "top", "right", "bottom", "left"]  # by index of the thread count among all thread counts
DASHES = ["-", "--", ":", "-."]
SHARED = "shared-nothing split (this machine's ceiling)"
# Each error measure's label and unit, as the engine's constraint types declare them: the report's "measures"
# ({key: {"type", "label", "unit"}}, filled in by main). A report without it (older ones) gets them from the key
# itself: "<label>_<unit suffix>", the suffix as the engine names its units.
MEASURES = {}
STAMP = ""  # the machine, commit, date and version of the report (main fills it in); save() writes it on every figure
BUSY_RING = dict(linestyle="none", marker="o", markersize=9, markerfacecolor="none", markeredgewidth=0.7, zorder=5)
UNIT_SUFFIXES = {"pct": "%", "mm": "mm", "rad": "rad"}


def measure_label(m):
    """The axis label of measure m, wrapped so that it stays beside its own panel."""
    if m in MEASURES:
        return textwrap.fill(f"RMS {MEASURES[m]['label']} ({MEASURES[m]['unit']})", 34)
    name, _, suffix = m.rpartition("_")
    return textwrap.fill(f"RMS {name or m} ({UNIT_SUFFIXES.get(suffix, suffix if name else '?')})", 34)


def solver_style(solver):
    if solver.endswith("+chebyshev"):  # the accelerated variant: the solver's colour, a star
        return STYLE.get(solver[:-len("+chebyshev")], ("tab:purple", "v"))[0], "*"
    return STYLE.get(solver, ("tab:purple", "v"))


def pos(v):
    """v if it can be drawn on a log axis, else None."""
    return v if isinstance(v, (int, float)) and math.isfinite(v) and v > 0 else None


def fmt(v, spec=".3g"):
    return "-" if v is None else format(v, spec)


def span(d, key, spec=".3g"):
    """d[key] (d[key_min]–d[key_max])."""
    return f"{fmt(d.get(key), spec)} ({fmt(d.get(key + '_min'), spec)}–{fmt(d.get(key + '_max'), spec)})"


def bars(y, lo, hi):
    """yerr/xerr of errorbar from values and their minima and maxima."""
    return [[max(0, a - b) for a, b in zip(y, lo)], [max(0, b - a) for a, b in zip(y, hi)]]


def speedups(rows):
    """(threads, speed-ups, their minima, their maxima) of scaling.strong or shared_nothing rows, by threads."""
    return zip(*sorted((d["threads"], d["speedup"], d["speedup_min"], d["speedup_max"]) for d in rows))


def title(scene):
    return f"{scene['name']} ({scene['particles']:,} particles)"


def log_ticks(ax, which):
    """At least 3 labelled ticks on a log axis: decades, else 1-3, 1-2-5, ... steps; widens a too narrow range."""
    axis, get, put = (ax.xaxis, ax.get_xlim, ax.set_xlim) if which == "x" else (ax.yaxis, ax.get_ylim, ax.set_ylim)
    lo, hi = get()
    if hi / lo < 4:
        lo, hi = math.sqrt(lo * hi) / 2, math.sqrt(lo * hi) * 2
    for subs in ((1,), (1, 3), (1, 2, 5), (1, 2, 3, 5, 7), tuple(range(1, 10))):
        ticks = [m * 10.0 ** e for e in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1) for m in subs]
        ticks = [t for t in ticks if lo <= t * (1 + 1e-9) and t <= hi * (1 + 1e-9)]
        if len(ticks) >= 3:
            break
    ticks = ticks[::math.ceil(len(ticks) / 7) if subs == (1,) else 1]
    plain = all(1e-3 <= t < 1e6 for t in ticks)  # else all as powers of ten

    def label(v):
        if plain:
            return f"{v:.3g}" if v < 1000 else f"{v:,.0f}"
        e = math.floor(math.log10(v) + 1e-9)
        return f"$10^{{{e}}}$" if abs(v / 10 ** e - 1) < 1e-6 else f"${v / 10 ** e:.3g}\\times10^{{{e}}}$"

    axis.set_major_locator(FixedLocator(ticks))
    axis.set_ticklabels([label(t) for t in ticks])
    axis.set_minor_formatter(NullFormatter())
    put(lo, hi)


def log2_ticks(ax, values):
    lo, hi = min(values), max(values)
    ax.set_xscale("log", base=2)
    ax.set_xlim(lo / 1.4, hi * 1.4)
    ax.xaxis.set_major_locator(FixedLocator([2 ** k for k in range(int(math.log2(lo)), int(math.log2(hi)) + 1)]))
    ax.xaxis.set_major_formatter(lambda v, _: f"{v:.0f}")
    ax.xaxis.set_minor_formatter(NullFormatter())


def loglog(ax):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.margins(0.08)
    log_ticks(ax, "x")
    log_ticks(ax, "y")


def finish(ax, sc, xlabel, skipped, drawn):
    """Title, labels and grid of a per-scene panel, and a note on the points left out."""
    if skipped:
        x, y, ha, va = (0.99, 0.99, "right", "top") if drawn else (0.5, 0.5, "center", "center")
        ax.text(x, y, f"{skipped} point{'s' * (skipped > 1)} with zero or non-finite error not shown", ha=ha, va=va,
                transform=ax.transAxes, fontsize=6, color="dimgray")
    if not drawn:
        ax.set(xticks=[], yticks=[])
    ax.grid(True, which="major", alpha=0.25)
    ax.set_title(title(sc))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(measure_label(sc["primary_error"]))


def panels(n, w=3.6, h=2.9):
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(w * cols, h * rows), squeeze=False, layout="constrained")
    for k in range(n, rows * cols):
        axes[k // cols][k % cols].axis("off")
    return fig, [axes[k // cols][k % cols] for k in range(n)]


def report_version(doc):
    """pbd's version that made the report (study.pbd_version; None in reports older than the field)."""
    info = doc.get("study") or {}
    return info.get("pbd_version") or (info.get("context") or {}).get("pbd_version")


def machine(ctx):
    """"CPU, N cores"; a merge of several machines (context.mixed_machines) names them all in cpu, with no core count."""
    cpu = ctx.get("cpu") or "unknown CPU"
    return cpu if ctx.get("mixed_machines") or ctx.get("cores") is None else f"{cpu}, {ctx['cores']} cores"


def stamp(doc):
    """"CPU, N cores · commit C · date D · pbd V" of a report, each part that it has (the version only if there)."""
    info = doc.get("study") or {}
    ctx = info.get("context") or {}
    version = report_version(doc)
    parts = [machine(ctx),
             f"commit {info.get('git_commit') or ctx.get('commit') or 'unknown'}",
             str(info.get("date") or ctx.get("date") or "date unknown")]
    return " · ".join(parts + [f"pbd {version}"] * bool(version))


def busy_rings(ax, points, color):
    """Rings of `color` around `points` ((x, y) pairs), timed on a busy machine: the points keep their own style."""
    if points:
        ax.plot([p[0] for p in points], [p[1] for p in points], markeredgecolor=color, gid="busy", **BUSY_RING)


def busy_handle():
    return Line2D([], [], color="gray", markeredgecolor="gray", label="ring: timed while busy (CV > 10% or loaded)",
                  **{k: v for k, v in BUSY_RING.items() if k != "zorder"})


def save(fig, out, stem, handles, ncol=4):
    """Writes the figure with its legend below it (ncol > 0) or at its right (ncol = 0), and STAMP above it."""
    fig.text(1.0, 1.0, STAMP, ha="right", va="bottom", fontsize=6, color="dimgray", gid="stamp")
    where = dict(loc="upper center", bbox_to_anchor=(0.5, 0), ncol=ncol) if ncol else \
        dict(loc="center left", bbox_to_anchor=(1, 0.5))
    fig.legend(handles=handles, frameon=False, **where)
    paths = [os.path.join(out, f"{stem}.{ext}") for ext in ("png", "svg")]
    for path in paths:
        fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)
    return paths


class Study:
    """The report with its lookups."""

    def __init__(self, doc):
        self.doc, self.info, self.scaling = doc, doc.get("study") or {}, doc.get("scaling") or {}
        self.mode = self.info.get("mode", "study")
        self.scenes, self.records = list(doc.get("scenes") or []), doc.get("records") or []
        self.by_scene, self.top = {}, {}  # scene -> records; (scene, solver) -> most threads
        for r in self.records:
            self.by_scene.setdefault(r["scene"], []).append(r)
            self.top[r["scene"], r["solver"]] = max(r["threads"], self.top.get((r["scene"], r["solver"]), 0))
        known = {s["name"] for s in self.scenes}
        self.scenes += [{"name": n, "particles": rs[0].get("particles", 0), "primary_error": "?", "family": None}
                        for n, rs in self.by_scene.items() if n not in known]  # not in "scenes": what its records say
        self.scene = {s["name"]: s for s in self.scenes}
        self.threads = sorted({r["threads"] for r in self.records})
        self.solvers = list(dict.fromkeys(r["solver"] for r in self.records))
        self.best = doc.get("best_splits") or []

    def error(self, r):
        e = r.get("primary_error")  # null (NaN in C++) stays None: not drawn
        return e if e is not None or "errors" not in r else \
            r["errors"].get(self.scene[r["scene"]]["primary_error"], {}).get("rms")

    def order(self, solver):
        return self.solvers.index(solver) if solver in self.solvers else len(self.solvers)

    def fill(self, threads):
        return FILLS[self.threads.index(threads) % len(FILLS)] if threads in self.threads else "full"

    def with_records(self):
        return [s for s in self.scenes if self.by_scene.get(s["name"])]


def solver_handles(solvers, label=str, **kw):
    return [Line2D([], [], color=solver_style(s)[0], marker=solver_style(s)[1], label=label(s), **kw) for s in solvers]


def speed_error(st, out, headline=False, reference=False):
    """Primary error (or, reference=True, the distance from the converged reference) against time per step."""
    value = (lambda r: r.get("ref_error_mm")) if reference else st.error
    scenes = st.with_records()
    if headline:  # the largest cloth<N> measured at more than one split: the README's figure
        cloths = [s for s in scenes if s.get("family") == "cloth" and
                  len({(r["substeps"], r["iterations"]) for r in st.by_scene[s["name"]]}) > 1]
        scenes = sorted(cloths, key=lambda s: s.get("particles", 0))[-1:]
    if reference:
        scenes = [s for s in scenes if any(pos(value(r)) for r in st.by_scene[s["name"]])]
    if not scenes:
        return []
    fig, axes = panels(len(scenes), *((6.0, 4.2) if headline else ()))
    for ax, sc in zip(axes, scenes):
        rs, skipped, groups = st.by_scene[sc["name"]], 0, {}
        for r in rs:
            if pos(value(r)) and pos(r["ms_per_step"]):
                groups.setdefault((r["solver"], r["threads"]), []).append(r)
            else:
                skipped += 1
        for (solver, threads), g in sorted(groups.items(), key=lambda kv: st.order(kv[0][0])):
            color, marker = solver_style(solver)
            x, y = [r["ms_per_step"] for r in g], [value(r) for r in g]
            lo, hi = ([r.get(k) or v for r, v in zip(g, x)] for k in ("ms_per_step_min", "ms_per_step_max"))
            ax.errorbar(x, y, xerr=bars(x, lo, hi), fmt="none", ecolor=color, elinewidth=0.6, alpha=0.5, zorder=2)
            ax.plot(x, y, linestyle="none", marker=marker, markersize=4.5, zorder=3, color=color,
                    fillstyle=st.fill(threads), markerfacecoloralt="white", markeredgewidth=0.8, gid=solver)
            busy_rings(ax, [(a, b) for a, b, r in zip(x, y, g) if r.get("busy")], color)
        front = [] if reference else sorted((r for r in rs if r.get("pareto") and pos(st.error(r))
                                             and pos(r["ms_per_step"])), key=lambda r: r["ms_per_step"])
        if front:
            ax.step([r["ms_per_step"] for r in front], [st.error(r) for r in front], where="post", color="gray",
                    linewidth=0.8, zorder=1)
        if groups:
            loglog(ax)
        placed = []  # label positions in pixels: a label too close to one already placed is left out
        for r in front if len({(r["substeps"], r["iterations"]) for r in rs}) > 1 else []:
            px, py = ax.transData.transform((r["ms_per_step"], st.error(r)))
            if all(abs(px - qx) > 16 or abs(py - qy) > 7 for qx, qy in placed):
                placed.append((px, py))
                ax.annotate(f"{r['substeps']}x{r['iterations']}", (r["ms_per_step"], st.error(r)), xytext=(3, 2),
                            textcoords="offset points", fontsize=5.5, color="dimgray", zorder=4)
        finish(ax, sc, "time per step, median (ms)", skipped, groups)
        if reference:
            ax.set_ylabel("one step's RMS distance from the\nconverged reference, run RMS (mm)")
            ref = next((f for f in st.doc.get("references") or [] if f.get("scene") == sc["name"]), {})
            if not ref.get("converged", True):  # the summary says why; the panel says that it is only a bound
                ax.text(0.01, 0.01, "reference not converged: distances bounded by its own error", fontsize=6,
                        color="firebrick", transform=ax.transAxes, ha="left", va="bottom")
    handles = solver_handles(st.solvers, linestyle="none")
    handles += [Line2D([], [], color="gray", marker="o", linestyle="none", fillstyle=st.fill(t),
                       markerfacecoloralt="white", label=f"{t} thread{'s' * (t > 1)}") for t in st.threads]
    handles += [busy_handle()] * any(r.get("busy") for r in st.records)
    if reference:
        fig.suptitle("Distance from the converged reference against time per step (lower left is better; bars: "
                     "fastest to slowest timed run)", fontsize=10)
        return save(fig, out, "reference_distance", handles, ncol=min(5, 1 + len(scenes)))
    handles += [Line2D([], [], color="gray", linewidth=0.8, label="Pareto front (labels: substeps x iterations)")]
    fig.suptitle("Speed against error (lower left is better; bars: fastest to slowest timed run)", fontsize=10)
    if headline:
        return save(fig, out, "headline", handles, ncol=3)
    return save(fig, out, "speed_error", handles, ncol=min(5, 2 + len(scenes)))


def headline(st, out):
    return speed_error(st, out, headline=True)


def reference_distance(st, out):
    return speed_error(st, out, reference=True)


VARIANT_DASH = {"plain": "-", "tethers": "--", "hierarchy": ":", "tethers+hierarchy": "-."}


def time_to_accuracy(st, out):
    """Run-averaged primary error against time per step, per (solver, variant) at its most threads."""
    target = (st.info.get("options") or {}).get("target_pct", 1.0)
    bases = []
    for s in st.with_records():
        if str(s.get("primary_error", "")).endswith("_pct") and \
                len({r["budget"] for r in st.by_scene[s["name"]]}) > 1 and s.get("base", s["name"]) not in bases:
            bases.append(s.get("base", s["name"]))
    if not bases:
        return []
    fig, axes = panels(len(bases), *((6.0, 4.2) if len(bases) == 1 else ()))
    variants = []
    for ax, base in zip(axes, bases):
        scenes = [s for s in st.scenes if s.get("base", s["name"]) == base and st.by_scene.get(s["name"])]
        drawn = 0
        for sc in scenes:
            variant = sc.get("variant", "plain")
            variants += [variant] * (variant not in variants)
            for solver in sorted({r["solver"] for r in st.by_scene[sc["name"]]}, key=st.order):
                top = st.top.get((sc["name"], solver))
                pts = sorted((r["ms_per_step"], st.error(r), bool(r.get("busy"))) for r in st.by_scene[sc["name"]]
                             if r["solver"] == solver and r["threads"] == top and pos(st.error(r))
                             and pos(r["ms_per_step"]))
                env, best = [], math.inf  # lower envelope: the lowest error reached by this time
                for x, y, busy in pts:
                    if y < best:
                        best = y
                        env.append((x, y, busy))
                if not env:
                    continue
                color, marker = solver_style(solver)
                ax.plot([p[0] for p in env], [p[1] for p in env], color=color, marker=marker, markersize=3.5,
                        linestyle=VARIANT_DASH.get(variant, "-"), linewidth=1.0, gid=solver)
                busy_rings(ax, [(x, y) for x, y, busy in env if busy], color)
                drawn += 1
        if drawn:
            loglog(ax)
            ax.axhline(target, color="red", linewidth=0.7, linestyle="--")
        sc0 = st.scene.get(base) or scenes[0]
        ax.set_title(f"{base} ({sc0.get('particles', 0):,} particles)")
        ax.set_xlabel("time per step, median (ms)")
        ax.set_ylabel(measure_label(sc0.get("primary_error", "?")) + ", run average")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    handles = solver_handles(sorted({r["solver"] for r in st.records}, key=st.order), linestyle="none")
    handles += [Line2D([], [], color="gray", linestyle=VARIANT_DASH.get(v, "-"), label=v) for v in variants]
    handles += [Line2D([], [], color="red", linestyle="--", linewidth=0.7, label=f"target {target:g}%")]
    handles += [busy_handle()] * any(r.get("busy") for r in st.records)
    fig.suptitle("Time per step against run-averaged error (each solver at its most threads; lower envelope)",
                 fontsize=10)
    return save(fig, out, "time_to_accuracy", handles, ncol=4)


def convergence(st, out):
    scenes = [s for s in st.with_records() if len({r["budget"] for r in st.by_scene[s["name"]]}) > 1]
    if not scenes:
        return []
    fig, axes = panels(len(scenes))
    for ax, sc in zip(axes, scenes):
        name, skipped, budgets = sc["name"], 0, set()
        for solver in st.solvers:
            t = st.top.get((name, solver))
            rs = [r for r in st.by_scene[name] if r["solver"] == solver and r["threads"] == t]
            color, marker = solver_style(solver)
            for key, dash in (("substeps", "-"), ("iterations", "--")):  # 1xN and Nx1
                line = sorted((r["budget"], pos(st.error(r))) for r in rs if r[key] == 1)
                skipped += sum(e is None for _, e in line)
                line = [(b, e) for b, e in line if e is not None]
                if line:
                    ax.plot(*zip(*line), color=color, linestyle=dash, linewidth=1.0, marker=marker, markersize=2.5)
                    budgets.update(b for b, _ in line)
            best = sorted((b["budget"], b.get("primary_error")) for b in st.best if b["scene"] == name
                          and b["solver"] == solver and b["threads"] == t and pos(b.get("primary_error")))
            if best:
                ax.plot(*zip(*best), linestyle="none", marker=marker, markersize=7, color=color,
                        markeredgecolor="black", markeredgewidth=0.5, zorder=4)
                budgets.update(b for b, _ in best)
        if budgets:
            ax.set_yscale("log")
            ax.margins(y=0.1)
            log_ticks(ax, "y")
            log2_ticks(ax, budgets)
        finish(ax, sc, "sweeps per step (substeps × iterations)", skipped, budgets)
    most = {s: max(st.top.get((n["name"], s), 0) for n in scenes) for s in st.solvers}
    handles = solver_handles(st.solvers, lambda s: f"{s} ({most[s]} thr)", linestyle="none")
    handles += [Line2D([], [], color="gray", linestyle="-", label="1xN: iterations"),
                Line2D([], [], color="gray", linestyle="--", label="Nx1: substeps"),
                Line2D([], [], color="gray", marker="o", markersize=7, markeredgecolor="black", linestyle="none",
                       label="best split")]
    fig.suptitle("Convergence: error against work per step, each solver at its most threads", fontsize=10)
    return save(fig, out, "convergence", handles, ncol=7)


def thread_scaling(st, out):
    shared, strong = st.doc.get("shared_nothing") or [], st.scaling.get("strong") or []
    if st.mode == "scaling":
        return scaling_panels(st, out, strong, shared) if strong else []
    ms = {(r["scene"], r["solver"], r["substeps"], r["iterations"], r["threads"]): r["ms_per_step"] for r in st.records}
    top = {s: max(r["threads"] for r in st.records if r["solver"] == s) for s in st.solvers if s != "serial"}
    busy = {(r["scene"], r["solver"], r["substeps"], r["iterations"], r["threads"]) for r in st.records if r.get("busy")}
    ups, busy_ups = {}, set()  # (scene, solver) -> speed-ups from 1 thread to its most threads, one per split
    for (scene, solver, sub, it, t), v in ms.items():
        if t > 1 and top.get(solver) == t and (scene, solver, sub, it, 1) in ms and pos(v):
            ups.setdefault((scene, solver), []).append(ms[scene, solver, sub, it, 1] / v)
            if {(scene, solver, sub, it, 1), (scene, solver, sub, it, t)} & busy:
                busy_ups.add((scene, solver))  # a speed-up of a time taken while busy
    if not ups:
        return []
    scenes = sorted(st.with_records(), key=lambda s: s["particles"])
    solvers = [s for s in top if any(k[1] == s for k in ups)]
    T = max(top[s] for s in solvers)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.9 * len(scenes) + 1.5), 3.6), layout="constrained")
    width = 0.6 / len(solvers)
    for k, solver in enumerate(solvers):
        for i, sc in enumerate(scenes):
            u = ups.get((sc["name"], solver))
            if u:
                m = statistics.median(u)
                at = i - 0.3 + width * (k + 0.5)
                ax.errorbar(at, m, yerr=bars([m], [min(u)], [max(u)]), capsize=2, fmt=solver_style(solver)[1],
                            color=solver_style(solver)[0], markersize=5, elinewidth=0.8, gid=solver)
                busy_rings(ax, [(at, m)] * ((sc["name"], solver) in busy_ups), solver_style(solver)[0])
    for i, sc in enumerate(scenes):
        sn = [d for d in shared if d["scene"] == sc["name"] and d["threads"] == T]
        if sn:
            _, y, lo, hi = speedups(sn)
            m = statistics.median(y)
            ax.errorbar(i + 0.38, m, yerr=bars([m], [min(lo)], [max(hi)]), fmt="o", color="gray", markersize=5,
                        capsize=2)
    ax.axhline(T, color="black", linestyle="--", linewidth=0.8)
    ax.axhline(1, color="black", linewidth=0.5)
    ax.set_xticks(range(len(scenes)), [f"{s['name']}\n{s['particles']:,}" for s in scenes])
    ax.set_xlim(-0.6, len(scenes) - 0.4)
    ax.set_ylim(0, T * 1.15)
    ax.set_xlabel("scene (particles), by size")
    ax.set_ylabel("speed-up over the same solver\non 1 thread (×)")
    ax.grid(True, axis="y", alpha=0.25)
    ax.set_title(f"Thread scaling: median over all splits, bar min..max ({len(scenes)} scenes)")
    handles = solver_handles(solvers, lambda s: f"{s} (1 → {top[s]} threads)", linestyle="none")
    handles += [Line2D([], [], color="gray", marker="o", linestyle="none", label=SHARED)] * \
        any(d["threads"] == T for d in shared) + [Line2D([], [], color="black", linestyle="--", label=f"ideal ({T}×)")]
    handles += [busy_handle()] * bool(busy_ups)
    return save(fig, out, "thread_scaling", handles, ncol=3)


def scaling_panels(st, out, strong, shared):
    names = sorted(dict.fromkeys(d["scene"] for d in strong), key=lambda n: st.scene.get(n, {}).get("particles", 0))
    fig, axes = panels(len(names), h=2.8)
    solvers = []
    busy = {(r["scene"], r["solver"], r["threads"]) for r in st.records if r.get("busy")}  # its timings, by threads
    for ax, name in zip(axes, names):
        rows = [d for d in strong if d["scene"] == name and d["solver"] != "serial"]
        sn = [d for d in shared if d["scene"] == name]
        for solver in sorted(dict.fromkeys(d["solver"] for d in rows), key=st.order):
            t, y, lo, hi = speedups(d for d in rows if d["solver"] == solver)
            color, marker = solver_style(solver)
            ax.errorbar(t, y, yerr=bars(y, lo, hi), color=color, marker=marker, markersize=4, capsize=2, linewidth=1.0,
                        elinewidth=0.7, gid=solver)
            busy_rings(ax, [(a, b) for a, b in zip(t, y) if (name, solver, a) in busy], color)
            solvers += [solver] * (solver not in solvers)
        if sn:
            t, y, lo, hi = speedups(sn)
            ax.errorbar(t, y, yerr=bars(y, lo, hi), color="gray", marker="o", markersize=4, capsize=2, linestyle=":")
        threads = sorted({d["threads"] for d in rows + sn})
        if threads:
            ax.plot([threads[0], threads[-1]], [threads[0], threads[-1]], color="black", linestyle="--", linewidth=0.8)
            ax.set_xticks(threads)
            ax.set_xlim(threads[0] - 0.3, threads[-1] + 0.3)
            ax.set_ylim(0, threads[-1] * 1.15)
        ax.grid(True, alpha=0.25)
        ax.set_title(title(st.scene.get(name) or {"name": name, "particles": rows[0]["particles"] if rows else 0}))
        ax.set_xlabel("threads")
        ax.set_ylabel("speed-up over the same\nsolver on 1 thread (×)")
    handles = solver_handles(solvers)
    handles += [Line2D([], [], color="gray", marker="o", linestyle=":", label=SHARED)] * bool(shared) + \
        [Line2D([], [], color="black", linestyle="--", label="ideal (speed-up = threads)")]
    handles += [busy_handle()] * any((d["scene"], d["solver"], d["threads"]) in busy for d in strong)
    split = st.scaling.get("split") or {}
    at = f" at {split['substeps']}x{split['iterations']} (substeps x iterations)" if split else ""
    fig.suptitle(f"Strong scaling{at}, bars min..max", fontsize=10)
    return save(fig, out, "thread_scaling", handles, ncol=len(handles))


def ns_per_projection(st, out):
    cloth = sorted((s for s in st.scenes if s.get("family") == "cloth"), key=lambda s: s["particles"])
    particles = {s["name"]: s["particles"] for s in cloth}
    series = {}  # (solver, threads) -> {particles: [ns of its records or its scaling.size row]}
    for r in (st.scaling.get("size") or []) if st.mode == "scaling" else st.records:
        if r["scene"] in particles and pos(r.get("ns_per_projection")):
            series.setdefault((r["solver"], r["threads"]), {}).setdefault(particles[r["scene"]], []).append(
                r["ns_per_projection"])
    used = sorted({n for s in series.values() for n in s})
    if len(cloth) < 2 or len(used) < 2:
        return []
    fig, ax = plt.subplots(figsize=(6.0, 3.8), layout="constrained")
    counts = sorted({k[1] for k in series})
    for (solver, threads), pts in sorted(series.items(), key=lambda kv: (st.order(kv[0][0]), kv[0][1])):
        color, marker = solver_style(solver)
        ax.plot(*zip(*sorted((n, statistics.median(v)) for n, v in pts.items())), color=color, marker=marker,
                markersize=4, linewidth=1.0, linestyle=DASHES[counts.index(threads) % len(DASHES)],
                label=f"{solver}, {threads} thread{'s' * (threads > 1)}")
    loglog(ax)
    for sc in cloth:
        if sc["particles"] in used:
            ax.annotate(sc["name"], (sc["particles"], 1), xycoords=("data", "axes fraction"), xytext=(0, -3),
                        textcoords="offset points", ha="center", va="top", fontsize=6.5, color="dimgray")
    ax.grid(True, which="major", alpha=0.25)
    ax.set_xlabel("particles")
    ax.set_ylabel("time per constraint projection (ns)")
    split = st.scaling.get("split") or {}
    what = f"split {split.get('substeps')}x{split.get('iterations')}" if split else "median of all splits"
    ax.set_title(f"Cost per projection, cloth family ({used[0]:,}–{used[-1]:,} particles; {what})")
    return save(fig, out, "ns_per_projection", ax.get_legend_handles_labels()[0], ncol=0)


def summary(st, out):
    info, ctx = st.info, st.info.get("context") or {}
    commit, load = info.get("git_commit") or ctx.get("commit") or "unknown", lambda k: fmt(ctx.get(k), ".2g")
    version = report_version(st.doc)
    lines = [f"# pbd study ({st.mode} mode)" + (f", pbd {version}" if version else ""), "",
             f"{info.get('date') or ctx.get('date', '?')}, commit {commit}, CPU {machine(ctx)}, load before {load('load_before')}, during {load('load_during')} "
             f"(max {load('load_during_max')}), {fmt(info.get('seconds'), '.4g')} s in total.", ""]
    if info.get("warnings") or info.get("busy"):
        lines += ["**Warning:**", ""] + [f"- {w}" for w in info.get("warnings") or ["the study was marked busy"]] + [""]
    ttt = st.doc.get("time_to_target") or []
    if ttt:
        lines += [f"## Time per step to reach {fmt(ttt[0].get('target'))}% (run-averaged primary error)", "",
                  "| scene | variant | solver | threads | ms/step | split | error |", "|---|---|---|---:|---:|---|---:|"]
        for t in ttt:
            lines.append(f"| {t['base']} | {t['variant']} | {t['solver']} | {t['threads']} | "
                         + (f"{fmt(t['ms_per_step'])} | {t['substeps']}x{t['iterations']} | {fmt(t['primary_error'])} |"
                            if t["reached"] else f"not reached | lowest at {t['substeps']}x{t['iterations']} | "
                            f"{fmt(t['primary_error'])} |"))
        lines += [""]
    for ref in st.doc.get("references") or []:
        lines.append(f"- reference of {ref['scene']}: {ref['solver']}, double, {ref['substeps']}x{ref['iterations']}"
                     f", {fmt(ref.get('seconds'))} s: " + ("converged" if ref.get("converged") else
                                                          "**not converged**: " + "; ".join(ref.get("failures") or [])))
    lines += [""] if lines[-1] else []
    rec = {(r["scene"], r["solver"], r["threads"], r["substeps"], r["iterations"]): r for r in st.records}
    for sc in st.scenes:
        name, unit = sc["name"], measure_label(sc["primary_error"])
        rows = sorted((b for b in st.best if b["scene"] == name and b["threads"] == st.top.get((name, b["solver"]))),
                      key=lambda b: (b["budget"], st.order(b["solver"])))
        lines += [f"## {title(sc)}", "", "Best split per budget, each solver at its most threads.", "",
                  f"| budget | solver | threads | best split SxI | ms/step median (min–max) | {unit} |",
                  "|---:|---|---:|---|---|---:|"] if rows else \
            [f"## {title(sc)}", "", "No best splits in the report." if st.by_scene.get(name) else "No records.", ""]
        for b in rows:
            r = {**rec.get((name, b["solver"], b["threads"], b["substeps"], b["iterations"]), {}), **b}
            lines.append(f"| {b['budget']} | {b['solver']} | {b['threads']} | {b['substeps']}x{b['iterations']} | "
                         f"{span(r, 'ms_per_step')}{' busy' * bool(r.get('busy'))} | {fmt(b.get('primary_error'))} |")
        lines += [""] * bool(rows)
        for d in (st.doc.get("dominance") or []):
            if d["scene"] == name:
                und = ", ".join(d.get("undominated") or [])
                lines.append(f"- {d['solver']} on {d['threads']} thread{'s' * (d['threads'] > 1)} dominates "
                             f"{d['dominated']} of {d['serial_points']} serial points on {measure_label(d['measure'])}"
                             + (f"; not at {und}" if und else ""))
        lines += [""] if lines[-1] else []
    strong = st.scaling.get("strong") or []
    if st.mode == "scaling" and strong:
        sn = {(d["scene"], d["threads"]): d for d in st.doc.get("shared_nothing") or []}
        lines += ["## Strong scaling", "", "| scene | solver | threads | ms/step | speed-up (min–max) | "
                  "shared-nothing speed-up (min–max) |", "|---|---|---:|---:|---|---|"]
        for d in sorted(strong, key=lambda d: (d.get("particles", 0), d["scene"], st.order(d["solver"]), d["threads"])):
            s = sn.get((d["scene"], d["threads"]))
            lines.append(f"| {d['scene']} | {d['solver']} | {d['threads']} | {fmt(d['ms_per_step'])} | "
                         f"{span(d, 'speedup', '.2f')} | {span(s, 'speedup', '.2f') if s else '-'} |")
    path = os.path.join(out, "summary.md")
    with open(path, "w") as f:
        f.write("\n".join(lines).rstrip() + "\n")
    return [path]


def main(argv):
    if len(argv) not in (2, 3) or argv[1].startswith("-"):
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1]) as f:
        doc = json.load(f)
    if not isinstance(doc, dict) or doc.get("schema") != 3:
        sys.stderr.write(f"plot_study.py: {argv[1]} lacks \"schema\": 3; this script reads only schema 3 reports\n")
        return 1
    out = argv[2] if len(argv) > 2 else (os.path.dirname(argv[1]) or ".")
    os.makedirs(out, exist_ok=True)
    MEASURES.update(doc.get("measures", {}))
    st = Study(doc)
    global STAMP
    STAMP = stamp(doc)
    for plot in (speed_error, headline, reference_distance, time_to_accuracy, convergence, thread_scaling,
                 ns_per_projection, summary):
        print(f"plot_study.py: {plot.__name__}: " + (", ".join(plot(st, out)) or "no data, skipped"), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
