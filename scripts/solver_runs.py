"""Summarises several runs of scripts/bench_solvers (one JSON each) against the solver's speed targets.

Usage: /usr/bin/python3 scripts/solver_runs.py RUN.json [RUN.json ...]   (runs in the order given; any JSON files
written by `scripts/bench_solvers REPETITIONS RUN.json`, or by bench_solvers with --benchmark_out)

Prints one row per run (unpaired medians, then the paired counters), then for each figure its range, its median
over the runs and how many runs meet the target. Ratios are rounded to two digits before they are counted, as in
docs/performance.md. Per-thread figures are ns per projection per thread: the 1T time, and the 2T time × 2.
"""
import statistics
import sys

from solver_table import load

# The targets (docs/performance.md), as (test, what the count says): each figure that has one also prints how many
# runs meet it.
RATIO = (lambda v: v >= 1.85, "at 1.85× or more")        # colored 2T vs 1T, for >= 10^5 constraints
NS = (lambda v: v <= 2.0, "at 2.0 ns or less")           # ns per stretch projection per sweep, 2 threads, 300²
VS_SERIAL = (lambda v: v >= 4.0, "at 4× or more")       # colored 2T against the serial reference, 300²
NO_SLOWER = (lambda v: v >= 1.0, "no slower")            # colored 2T against the serial reference, 30²
AT_OR_ABOVE = (lambda v: v >= 0, "first at or above second")  # differences of two ratios


def r2(x):
    return round(x, 2)


def spread(values):
    return f"{min(values):.2f}–{max(values):.2f}, median {statistics.median(values):.2f}"


def main(paths):
    unpaired, paired_rows = [], []
    figures = {}  # name -> (values over runs, target or None)

    def add(name, value, target=None):
        figures.setdefault(name, ([], target))[0].append(value)

    for path in paths:
        ctx, med, triad, paired = load(path)
        when = ctx.get("date", "")[11:16]
        ns = {key: value[0] for key, value in med.items()}
        s300, c300_1, c300_2 = ns[("serial", 300, 1)], ns[("colored", 300, 1)], ns[("colored", 300, 2)]
        c1000_1, c1000_2 = ns[("colored", 1000, 1)], ns[("colored", 1000, 2)]
        s30, c30_2 = ns[("serial", 30, 1)], ns[("colored", 30, 2)]
        add("unpaired 300² 2T vs 1T", r2(c300_1 / c300_2), RATIO)
        add("unpaired 1000² 2T vs 1T", r2(c1000_1 / c1000_2), RATIO)
        add("unpaired 300² 1T ns", r2(c300_1))
        add("unpaired 300² 2T ns", r2(c300_2), NS)
        add("unpaired 1000² 1T ns", r2(c1000_1))
        add("unpaired 1000² 2T ns", r2(c1000_2))
        add("300² 2T vs serial", r2(s300 / c300_2), VS_SERIAL)
        add("30² 2T vs serial", r2(s30 / c30_2), NO_SLOWER)
        triad_ratio = triad[2] / triad[1] if 1 in triad and 2 in triad else float("nan")
        unpaired.append(f"| {when} | {c300_1:.2f} / {c300_2:.2f} | {c300_1 / c300_2:.2f}× | {s300 / c300_2:.2f}× |"
                        f" {c1000_1:.2f} / {c1000_2:.2f} | {c1000_1 / c1000_2:.2f}× | {s30 / c30_2:.2f}× |"
                        f" {triad_ratio:.2f}× |")

        cells = [when]
        for name, label in [("BM_ColoredScaling/n:300", "colored 300²"),
                            ("BM_SharedNothingHalvesScaling/n:300", "same data, nothing shared, 300²"),
                            ("BM_ColoredScaling/n:1000", "colored 1000²"),
                            ("BM_SharedNothingHalvesScaling/n:1000", "same data, nothing shared, 1000²"),
                            ("BM_SharedNothingScaling/n:300", "two 300² cloths, nothing shared")]:
            b = paired.get(name)
            if b is None:
                cells += ["–", "–"]
                continue
            cells += [f"{b['ns_1T']:.2f} / {b['ns_2T']:.2f}", f"{b['speedup']:.2f}×"]
            add(f"paired {label}: 2T vs 1T", r2(b["speedup"]), RATIO)
            add(f"paired {label}: 1T ns per thread", b["ns_1T"])
            add(f"paired {label}: 2T ns per thread", 2 * b["ns_2T"])
            if name == "BM_ColoredScaling/n:300":
                add("paired 300² 2T ns", r2(b["ns_2T"]), NS)
        for a, b, label in [("BM_ColoredScaling/n:300", "BM_SharedNothingHalvesScaling/n:300",
                             "300², colored minus the same data with nothing shared"),
                            ("BM_ColoredScaling/n:1000", "BM_SharedNothingHalvesScaling/n:1000",
                             "1000², colored minus the same data with nothing shared"),
                            ("BM_ColoredScaling/n:300", "BM_SharedNothingScaling/n:300",
                             "300², colored minus two 300² cloths with nothing shared"),
                            ("BM_SharedNothingHalvesScaling/n:300", "BM_SharedNothingScaling/n:300",
                             "300², the same data with nothing shared minus two 300² cloths")]:
            if a in paired and b in paired:
                add(f"{label}: difference of 2T vs 1T", r2(r2(paired[a]["speedup"]) - r2(paired[b]["speedup"])),
                    AT_OR_ABOVE)
        compute = paired.get("BM_ComputeScaling")
        cells.append(f"{compute['speedup']:.2f}×" if compute else "–")
        if compute:
            add("paired compute only: 2T vs 1T", r2(compute["speedup"]))
        paired_rows.append("| " + " | ".join(cells) + " |")

    print("| run (UTC) | 300²: 1T / 2T ns | 2T vs 1T | 2T vs serial | 1000²: 1T / 2T ns | 2T vs 1T |"
          " 30²: 2T vs serial | triad 2T vs 1T |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(unpaired))
    print()
    print("| run (UTC) | colored 300² | 2T vs 1T | same data, nothing shared, 300² | 2T vs 1T | colored 1000² | 2T vs 1T |"
          " same data, nothing shared, 1000² | 2T vs 1T | two 300² cloths | 2T vs 1T | compute only: 2T vs 1T |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(paired_rows))
    print()
    for name, (values, target) in figures.items():
        line = f"- {name}: {spread(values)}"
        if target is not None:
            meets, says = target
            line += f"; {sum(meets(v) for v in values)} of {len(values)} {says}"
        print(line)
    print(f"\n{len(paths)} runs.")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: solver_runs.py RUN.json [RUN.json ...]")
    main(sys.argv[1:])
