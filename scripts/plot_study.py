#!/usr/bin/python3
"""Plots of a `pbd study` JSON report (run with Debian's /usr/bin/python3, which has python3-matplotlib).

Usage: scripts/plot_study.py STUDY.json [OUT_DIR] [--svg]

Writes into OUT_DIR (default: the JSON's folder):
  speed_error.png      per scene: error against time per step (the speed-error plane), one curve per solver/threads,
                       one point per iteration count; top row per-step distance from the converged reference (dotted
                       red: how much the reference itself moves from N/2 to N iterations), bottom row RMS constraint
                       violation
  thread_scaling.png   per scene: speed-up over the serial solver at the same iterations, against threads
  ns_per_projection.png  time per constraint projection against the number of constraints (scene size)
  summary.md           the main table in Markdown: per scene and iteration count, ms per step and errors of each
                       solver at its most threads, and the dominance check of the report
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

STYLE = {  # solver -> (color, marker)
    "serial": ("black", "o"),
    "serial-colored": ("tab:gray", "v"),
    "colored": ("tab:blue", "s"),
    "jacobi": ("tab:orange", "^"),
    "block": ("tab:green", "D"),
}
DASH = {1: "-", 2: "--", 4: ":", 8: "-."}


def style(solver, threads):
    color, marker = STYLE.get(solver, ("tab:purple", "x"))
    return dict(color=color, marker=marker, linestyle=DASH.get(threads, "-"))


def label(solver, threads):
    return solver if solver in ("serial", "serial-colored") else f"{solver}, {threads} thr"


def scenes_of(records):
    seen = []
    for r in records:
        if r["scene"] not in seen:
            seen.append(r["scene"])
    return seen


def curves(records, scene, substeps=None):
    """{(solver, threads, substeps): [records sorted by iterations]} for one scene."""
    out = {}
    for r in records:
        if r["scene"] != scene or (substeps is not None and r["substeps"] != substeps):
            continue
        out.setdefault((r["solver"], r["threads"], r["substeps"]), []).append(r)
    for v in out.values():
        v.sort(key=lambda r: r["iterations"])
    return out


def positive(v):
    return v if v is not None and v > 0 and math.isfinite(v) else float("nan")


def grid(n):
    cols = min(n, 3)
    return (n + cols - 1) // cols, cols


def speed_error(doc, out, ext):
    records = doc["records"]
    scenes = scenes_of(records)
    cols = len(scenes)
    fig, axes = plt.subplots(2, cols, figsize=(3.6 * cols, 6.4), squeeze=False)
    for j, scene in enumerate(scenes):
        for i, (key, name) in enumerate([("ref_error", "distance to reference / size (RMS)"),
                                         ("rms_violation", "constraint violation (RMS)")]):
            ax = axes[i][j]
            multi_sub = len({r["substeps"] for r in records if r["scene"] == scene}) > 1
            for (solver, threads, sub), rs in curves(records, scene).items():
                lab = label(solver, threads) + (f", {sub} sub" if multi_sub else "")
                ax.plot([r["ms_per_step"] for r in rs], [positive(r[key]) for r in rs], label=lab, markersize=4,
                        **style(solver, threads))
                if solver == "serial":
                    for r in rs:
                        ax.annotate(str(r["iterations"]), (r["ms_per_step"], positive(r[key])), fontsize=6,
                                    xytext=(3, 3), textcoords="offset points")
            if key == "ref_error":
                for ref in doc.get("references", []):
                    if ref["scene"] == scene and ref.get("step_convergence", 0) > 0:
                        ax.axhline(ref["step_convergence"], color="tab:red", linewidth=0.8, linestyle=":",
                                   label="reference: N/2 vs N iterations")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.yaxis.set_minor_formatter(NullFormatter())
            ax.grid(True, which="both", alpha=0.25)
            if i == 0:
                ax.set_title(scene)
            else:
                ax.set_xlabel("ms per step (median)")
            if j == 0:
                ax.set_ylabel(name)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 6), fontsize=8)
    fig.suptitle("Speed vs error (lower left is better; numbers: serial iterations per substep)", fontsize=10)
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    path = os.path.join(out, "speed_error." + ext)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def thread_scaling(doc, out, ext):
    records = doc["records"]
    scenes = scenes_of(records)
    rows, cols = grid(len(scenes))
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.0 * rows), squeeze=False)
    for k, scene in enumerate(scenes):
        ax = axes[k // cols][k % cols]
        ax.yaxis.set_minor_formatter(NullFormatter())
        rs = [r for r in records if r["scene"] == scene]
        sub = min(r["substeps"] for r in rs)
        its = sorted({r["iterations"] for r in rs})
        serial = {r["iterations"]: r["ms_per_step"] for r in rs if r["solver"] == "serial" and r["substeps"] == sub}
        threads = sorted({r["threads"] for r in rs})
        for it in (its[0], its[-1]) if len(its) > 1 else its:
            for solver in ("colored", "jacobi", "block"):
                pts = sorted((r["threads"], r["ms_per_step"]) for r in rs
                             if r["solver"] == solver and r["iterations"] == it and r["substeps"] == sub)
                if not pts or it not in serial:
                    continue
                color, marker = STYLE[solver]
                ax.plot([t for t, _ in pts], [serial[it] / ms for _, ms in pts], color=color, marker=marker,
                        linestyle="-" if it == its[-1] else ":", label=f"{solver}, {it} it")
        ax.axhline(1.0, color="black", linewidth=0.8)
        ax.set_xticks(threads)
        ax.set_title(scene, fontsize=9)
        ax.set_xlabel("threads")
        ax.set_ylabel("speed-up over serial")
        ax.grid(True, alpha=0.25)
        ax.legend(fontsize=6)
    for k in range(len(scenes), rows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.suptitle("Thread scaling: serial ms/step ÷ solver ms/step at the same iterations", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, "thread_scaling." + ext)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def ns_per_projection(doc, out, ext):
    records = doc["records"]
    top = max(r["iterations"] for r in records)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    series = {}
    for r in records:
        if r["iterations"] == top:
            series.setdefault((r["solver"], r["threads"]), []).append(r)
    for (solver, threads), rs in sorted(series.items()):
        rs.sort(key=lambda r: r["constraints"])
        ax.plot([r["constraints"] for r in rs], [r["ns_per_projection"] for r in rs], label=label(solver, threads),
                **style(solver, threads))
        if solver == "serial":
            for r in rs:
                ax.annotate(r["scene"], (r["constraints"], r["ns_per_projection"]), fontsize=7, xytext=(3, 4),
                            textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("constraints in the scene")
    ax.set_ylabel("ns per constraint projection")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_title(f"Cost per projection at {top} iterations (ms/step ÷ constraints·substeps·iterations)", fontsize=9)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "ns_per_projection." + ext)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def summary(doc, out, ext):
    records = doc["records"]
    lines = []
    for scene in scenes_of(records):
        rs = [r for r in records if r["scene"] == scene]
        first = rs[0]
        lines.append(f"**{scene}** ({first['particles']} particles, {first['constraints']} constraints, "
                     f"{first['steps']} steps, {first['precision']})\n")
        solvers = []
        for r in rs:
            if r["solver"] not in solvers:
                solvers.append(r["solver"])
        most = {s: max(r["threads"] for r in rs if r["solver"] == s) for s in solvers}
        head = "| sub | iter | " + " | ".join(f"{label(s, most[s])}: ms/step, ref_error, rms_violation" for s in solvers)
        lines.append(head + " |")
        lines.append("|---|---|" + "---|" * len(solvers))
        keys = sorted({(r["substeps"], r["iterations"]) for r in rs})
        for sub, it in keys:
            cells = []
            for s in solvers:
                m = [r for r in rs if r["solver"] == s and r["threads"] == most[s] and r["substeps"] == sub
                     and r["iterations"] == it]
                cells.append(f"{m[0]['ms_per_step']:.4g}, {m[0]['ref_error']:.2e}, {m[0]['rms_violation']:.2e}"
                             if m else "-")
            lines.append(f"| {sub} | {it} | " + " | ".join(cells) + " |")
        lines.append("")
    if doc.get("references"):
        lines.append("| reference of | substeps | steps | iterations (N) | per step: N/2 vs N | whole run: N/2 vs N | "
                     "its rms_violation | seconds |")
        lines.append("|---|---|---|---|---|---|---|---|")
        for ref in doc["references"]:
            lines.append(f"| {ref['scene']} | {ref['substeps']} | {ref['steps']} | {ref['iterations']} | "
                         f"{ref['step_convergence']:.1e} | {ref['trajectory_convergence']:.1e} | "
                         f"{ref['rms_violation']:.2e} | {ref['seconds']:.1f} |")
        lines.append("")
    if doc.get("dominance"):
        lines.append("| scene | substeps | error | serial points dominated | not dominated at iterations |")
        lines.append("|---|---|---|---|---|")
        for d in doc["dominance"]:
            n = d["serial_points"] - len(d["undominated_iterations"])
            lines.append(f"| {d['scene']} | {d['substeps']} | {d['error']} | {n} of {d['serial_points']} "
                         f"({d.get('solver', 'colored')} on {d['threads']} threads) | "
                         f"{', '.join(map(str, d['undominated_iterations'])) or '-'} |")
    path = os.path.join(out, "summary.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    if not args or len(args) > 2 or any(a not in ("--svg",) for a in argv[1:] if a.startswith("--")):
        sys.stderr.write(__doc__)
        return 2
    ext = "svg" if "--svg" in argv else "png"
    with open(args[0]) as f:
        doc = json.load(f)
    if not doc.get("records"):
        sys.stderr.write(f"plot_study.py: {args[0]} has no records\n")
        return 1
    out = args[1] if len(args) > 1 else (os.path.dirname(args[0]) or ".")
    os.makedirs(out, exist_ok=True)
    for plot in (speed_error, thread_scaling, ns_per_projection, summary):
        print("plot_study.py: wrote", plot(doc, out, ext), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
