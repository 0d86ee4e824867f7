"""The ligament scene (scenes/ligament.json): 7 fibers crimped by 0 to 3% of their length, fixed at the top and
pulled by grips moving down at 0.02 m/s. Plots the ligament's tension (the sum of its fibers' tensions at the grips,
from lambda) against the grips' travel as a strain of the 4 cm length: the fibers are recruited one after another as
their crimp straightens, yield, and break one after another at 14%. Beside it, the fibers in the y-z plane before,
during and after the tear. Prints each step with breaks.

Usage: ligament.py SCENE_DIR [PLOT.png]"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pbd

scene = pbd.load_scene(os.path.join(sys.argv[1], "ligament.json"))
w = pbd.build_world_double(scene)
chains, segments, length = 7, 20, 0.04
grips = {(segments + 1) * c + segments for c in range(chains)}  # each fiber's last particle
pairs = [((segments + 1) * c + j, (segments + 1) * c + j + 1) for c in range(chains) for j in range(segments)]
z0 = w.positions()[min(grips), 2]
travel, tension, shots = [], [], {0: (w.positions().copy(), list(pairs))}
for step in range(1, scene.steps + 1):
    w.step()
    gone = [b.fiber for b in w.last_breaks()]
    if gone:
        print(f"step {step}: {len(gone)} fibers broke, at strains {', '.join(f'{b.strain:.4f}' for b in w.last_breaks())}")
    for i in sorted(gone, reverse=True):  # the fibers' indices as the world numbers them now
        del pairs[i]
    force = w.fibers()["force"]
    travel.append((z0 - w.positions()[min(grips), 2]) / length)
    tension.append(sum(force[i] for i, (a, b) in enumerate(pairs) if b in grips))
    if step in (270, 300, 450):
        shots[step] = (w.positions().copy(), list(pairs))

fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.2), gridspec_kw={"width_ratios": [1.3, 1]})
ax.plot(100 * np.array(travel), tension, color="C0")
ax.set_xlabel("grips' travel (% of the 4 cm length)")
ax.set_ylabel("ligament tension at the grips (N)")
ax.set_title("7 crimped fibers: recruited, yielding, breaking one by one", fontsize=10)
for k, (step, (x, ps)) in enumerate(sorted(shots.items())):
    off = 0.016 * k
    for a, b in ps:
        bx.plot([x[a, 1] + off, x[b, 1] + off], [x[a, 2], x[b, 2]], color="C0", lw=0.8)
    bx.text(off, 0.004, f"step {step}", ha="center", fontsize=8)
bx.set_aspect("equal")
bx.set_xlabel("y (m), each step shifted by 16 mm")
bx.set_ylabel("z (m)")
bx.set_title("the fibers (y-z plane)", fontsize=10)
fig.tight_layout()
fig.savefig(sys.argv[2] if len(sys.argv) > 2 else "ligament.png", dpi=110)
print(f"fibers left: {len(pairs)} of {chains * segments}")
