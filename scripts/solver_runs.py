"""Summarises several runs of scripts/bench_solvers (one JSON each) against the targets of issue 4.

Usage: /usr/bin/python3 scripts/solver_runs.py RUN.json [RUN.json ...]   (runs in the order given)

Prints one row per run (unpaired medians, then the paired counters), then for each figure its range, its median
over the runs and how many runs meet the target. Ratios are rounded to two digits before they are counted, as in
docs/performance.md. Per-thread figures are ns per projection per thread: the 1T time, and the 2T time × 2.
"""
import statistics
import sys

from solver_table import load

TARGET_RATIO = 1.85  # colored 2T vs 1T, for >= 10^5 constraints
TARGET_NS = 2.0      # ns per stretch projection per sweep, 2 threads, 300²
TARGET_VS_SERIAL = 4.0


def r2(x):
    return round(x, 2)


def spread(values, fmt="{:.2f}"):
    return f"{fmt.format(min(values))}–{fmt.format(max(values))}, median {fmt.format(statistics.median(values))}"


def main(paths):
    unpaired, paired_rows = [], []
    figures = {}  # name -> list over runs

    def add(name, value):
        figures.setdefault(name, []).append(value)

    for path in paths:
        ctx, med, triad, paired = load(path)
        when = ctx.get("date", "")[11:16]
        ns = {key: value[0] for key, value in med.items()}
        s300, c300_1, c300_2 = ns[("serial", 300, 1)], ns[("colored", 300, 1)], ns[("colored", 300, 2)]
        c1000_1, c1000_2 = ns[("colored", 1000, 1)], ns[("colored", 1000, 2)]
        s30, c30_2 = ns[("serial", 30, 1)], ns[("colored", 30, 2)]
        add("unpaired 300² 2T vs 1T", r2(c300_1 / c300_2))
        add("unpaired 1000² 2T vs 1T", r2(c1000_1 / c1000_2))
        add("unpaired 300² 1T ns", r2(c300_1))
        add("unpaired 300² 2T ns", r2(c300_2))
        add("unpaired 1000² 2T ns", r2(c1000_2))
        add("300² 2T vs serial", r2(s300 / c300_2))
        add("30² 2T vs serial", r2(s30 / c30_2))
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
            add(f"paired {label}: 2T vs 1T", r2(b["speedup"]))
            add(f"paired {label}: 1T ns per thread", b["ns_1T"])
            add(f"paired {label}: 2T ns per thread", 2 * b["ns_2T"])
            if name == "BM_ColoredScaling/n:300":
                add("paired 300² 2T ns", r2(b["ns_2T"]))
        for a, b, label in [("BM_ColoredScaling/n:300", "BM_SharedNothingHalvesScaling/n:300",
                             "300², colored minus the same data with nothing shared"),
                            ("BM_ColoredScaling/n:1000", "BM_SharedNothingHalvesScaling/n:1000",
                             "1000², colored minus the same data with nothing shared"),
                            ("BM_ColoredScaling/n:300", "BM_SharedNothingScaling/n:300",
                             "300², colored minus two 300² cloths with nothing shared"),
                            ("BM_SharedNothingHalvesScaling/n:300", "BM_SharedNothingScaling/n:300",
                             "300², the same data with nothing shared minus two 300² cloths")]:
            if a in paired and b in paired:
                add(f"{label}: difference of 2T vs 1T", r2(r2(paired[a]["speedup"]) - r2(paired[b]["speedup"])))
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
    runs = len(paths)
    for name, values in figures.items():
        line = f"- {name}: {spread(values)}"
        if "minus" in name:
            line += f"; first at or above second in {sum(v >= 0 for v in values)} of {len(values)}"
        elif name.endswith("2T vs 1T") and "compute" not in name:
            line += f"; {sum(v >= TARGET_RATIO for v in values)} of {len(values)} at {TARGET_RATIO}× or more"
        elif name.endswith("300² 2T ns"):
            line += f"; {sum(v <= TARGET_NS for v in values)} of {len(values)} at {TARGET_NS} ns or less"
        elif name == "300² 2T vs serial":
            line += f"; {sum(v >= TARGET_VS_SERIAL for v in values)} of {len(values)} at {TARGET_VS_SERIAL}× or more"
        elif name == "30² 2T vs serial":
            line += f"; {sum(v >= 1 for v in values)} of {len(values)} no slower"
        print(line)
    print(f"\n{runs} runs.")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: solver_runs.py RUN.json [RUN.json ...]")
    main(sys.argv[1:])
