"""Turns bench_solvers' JSON (with repetitions) into a Markdown table of median ns per projection and ratios."""
import json
import sys


def load(path):
    """The medians of one bench_solvers JSON: (context, sweeps, triad, paired).

    sweeps: (kind, n, threads) -> (ns per projection, constraints, colors); triad: threads -> GB/s; paired: benchmark
    name without "/iterations:K" (e.g. "BM_ColoredScaling/n:300") -> its median counters.
    """
    data = json.load(open(path))
    med, triad, paired = {}, {}, {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = b["run_name"]  # e.g. BM_ColoredSweep/n:300/threads:2/real_time
        if "Scaling" in name:
            paired[name.split("/iterations")[0]] = b
            continue
        if name.startswith("BM_StreamTriad"):
            triad[int(b["threads"])] = b["bytes_per_second"] / 1e9
            continue
        parts = dict(p.split(":") for p in name.split("/")[1:] if ":" in p)
        kind = name.split("/")[0].replace("BM_", "").replace("Sweep", "").lower()
        if parts.get("bending") == "1" and not kind.endswith("bending"):
            kind += "bending"
        key = (kind, int(parts["n"]), int(parts.get("threads", 1)))
        med[key] = (b["ns_per_projection"], int(b["constraints"]), int(b["colors"]))  # the counter is already ns
    return data["context"], med, triad, paired


def main(path):
    ctx, med, triad, paired = load(path)
    print(f"machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, date {ctx.get('date')}")
    print()
    print("| cloth | constraints | colors | serial | colored 1T | colored 2T | Jacobi 1T | Jacobi 2T |"
          " colored 2T vs 1T | colored 2T vs serial |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in sorted({k[1] for k in med}):
        def ns(kind, t):
            return med.get((kind, n, t), (float("nan"), 0, 0))[0]
        s, c1, c2, j1, j2 = ns("serial", 1), ns("colored", 1), ns("colored", 2), ns("jacobi", 1), ns("jacobi", 2)
        cons, colors = med[("colored", n, 1)][1], med[("colored", n, 1)][2]
        print(f"| {n}² | {cons:,} | {colors} | {s:.2f} | {c1:.2f} | {c2:.2f} | {j1:.2f} | {j2:.2f} |"
              f" {c1 / c2:.2f}× | {s / c2:.2f}× |")
    print()
    print("ns per constraint projection per sweep (median of the repetitions); ratios from the same run.")
    block = sorted({k[1] for k in med if k[0] in ("block", "blockbending")})
    if block:
        print()
        print("Block Gauss-Seidel against colored (ns per projection per sweep; \"+ bending\": the grid cloth with dihedral"
              " bending, whose bending projections are scalar in both):")
        print()
        print("| cloth | block 1T | block 2T | colored 1T | colored 2T | block 1T vs colored 1T | block 2T vs 1T |")
        print("|---|---|---|---|---|---|---|")
        for kind, col, suffix in (("block", "colored", ""), ("blockbending", "coloredbending", " + bending")):
            for n in block:
                if (kind, n, 1) not in med:
                    continue
                b1, b2 = med[(kind, n, 1)][0], med.get((kind, n, 2), (float("nan"),))[0]
                c1, c2 = med.get((col, n, 1), (float("nan"),))[0], med.get((col, n, 2), (float("nan"),))[0]
                print(f"| {n}²{suffix} | {b1:.2f} | {b2:.2f} | {c1:.2f} | {c2:.2f} | {c1 / b1:.2f}× | {b1 / b2:.2f}× |")
    if 1 in triad and 2 in triad:
        print()
        print(f"Memory ceiling (BM_StreamTriad, two 64 MB arrays): {triad[1]:.1f} GB/s on 1 thread, {triad[2]:.1f} GB/s"
              f" on 2 ({triad[2] / triad[1]:.2f}×).")
    if paired:
        print()
        print("Paired 2T vs 1T (one unit of work on 1 thread, then on 2, alternated; speed-up = median over the pairs):")
        print()
        print("| work | 1 thread | 2 threads | 2T vs 1T |")
        print("|---|---|---|---|")
        for name, b in sorted(paired.items()):
            n = name.split("n:")[1] if "n:" in name else None
            if name.startswith("BM_ColoredScaling"):
                label, unit = f"colored sub-step, {n}² cloth (ns per projection)", "ns"
            elif name.startswith("BM_BlockScaling"):
                m = n.split("/")[0]
                extra = " + bending" if "bending:1" in name else ""
                per = name.split("per_block:")[1].split("/")[0] if "per_block:" in name else "0"
                extra += f", blocks of about {per} constraints" if per != "0" else ""
                label, unit = f"block sub-step, {m}² cloth{extra}, {int(b['blocks'])} blocks (ms)", "ms"
            elif name.startswith("BM_SharedNothingHalvesBlockScaling"):
                m = n.split("/")[0]
                extra = " + bending" if "bending:1" in name else ""
                label, unit = (f"block on two independent cloths of {m}²/2{extra}, one per thread, nothing shared"
                               " (ms)"), "ms"
            elif name.startswith("BM_SharedNothingHalvesScaling"):
                label, unit = (f"two independent cloths of {int(b['side'])}², one per thread: the data of one {n}² cloth,"
                               " nothing shared (ns per projection)"), "ns"
            elif name.startswith("BM_SharedNothingScaling"):
                label, unit = f"two independent {n}² cloths, one per thread, nothing shared (ns per projection)", "ns"
            else:
                label, unit = "compute only, no memory (ms): the machine's own ceiling", "ms"
            print(f"| {label} | {b[unit + '_1T']:.2f} | {b[unit + '_2T']:.2f} | {b['speedup']:.2f}× |")


if __name__ == "__main__":
    main(sys.argv[1])
