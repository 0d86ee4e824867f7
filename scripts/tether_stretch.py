"""RMS stretch averaged over a run of the study's hanging cloth, with and without tethers (issue 44's measure).

Usage: PYTHONPATH=build/release/python /usr/bin/python3 scripts/tether_stretch.py N SUBSTEPS ITERATIONS STEPS
       [TETHERS ...]
The cloth: N×N particles on a 1 m square, two corners pinned, PBD stretch k = 1, XPBD bending compliance 1000,
dt = 1/60 s; float, the colored solver, TBB's default thread count. Each TETHERS is a body "tethers" value as JSON
(default: none and true; "none" for no key), e.g. '{"to": "all"}'. Prints per variant the mean over the steps of the
per-step RMS relative stretch, the final step's, and the median wall time of step() alone.
"""
import json
import statistics
import sys
import time

import pbd

n, substeps, iterations, steps = (int(a) for a in sys.argv[1:5])
for variant in sys.argv[5:] or ["none", "true"]:
    body = {"type": "cloth", "resolution": n, "size": 1.0, "mass": 1.0, "origin": [0, 0, 1], "pin": "corners",
            "stretch": {"stiffness": 1.0}, "bending": {"compliance": 1000}}
    if variant != "none":
        body["tethers"] = json.loads(variant)
    scene = {"name": f"cloth{n}", "dt": 1 / 60, "substeps": substeps, "iterations": iterations, "steps": steps,
             "bodies": [body]}
    world = pbd.build_world(pbd.parse_scene(json.dumps(scene)))
    params = world.params
    params.solver = pbd.Solver.colored
    world.params = params
    rms, ms = [], []
    for _ in range(steps):
        t0 = time.perf_counter()
        world.step()
        ms.append(1000 * (time.perf_counter() - t0))
        rms.append(pbd.stretch_violation(world).rms)
    print(f"N={n} {substeps}x{iterations} tethers={variant:<40} mean RMS stretch {100 * statistics.mean(rms):.3f}%  "
          f"final {100 * rms[-1]:.3f}%  median {statistics.median(ms):.2f} ms/step", flush=True)
