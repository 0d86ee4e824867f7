"""The cloth-tear scene (scenes/cloth-tear.json): a cloth of fibers hanging from two corners that move apart until it
tears. Draws the surface's triangles as they are (World.surface: particles copied along each cut) at four steps,
seen along z, and prints the fibers broken and the particles the tears added.

Usage: cloth_tear.py SCENE_DIR [PLOT.png]"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import numpy as np
import pbd

scene = pbd.load_scene(os.path.join(sys.argv[1], "cloth-tear.json"))
w = pbd.build_world(scene)
show = (0, 100, 200, scene.steps)
shots = {0: (w.positions().copy(), np.array(w.surface(0)))}
broken = copies = 0
for step in range(1, scene.steps + 1):
    w.step()
    broken += len(w.last_breaks())
    copies += len(w.last_copies())
    if step in show:
        shots[step] = (w.positions().copy(), np.array(w.surface(0)))
fig, axes = plt.subplots(1, len(show), figsize=(3.2 * len(show), 3.6))
for ax, step in zip(axes, show):
    x, tris = shots[step]
    ax.add_collection(PolyCollection(x[tris][:, :, :2], facecolor="C1", edgecolor="0.3", lw=0.2))
    ax.set_xlim(-0.35, 0.85)
    ax.set_ylim(-0.45, 0.6)
    ax.set_aspect("equal")
    ax.set_title(f"step {step} (t = {step * w.params.dt:.2f} s)", fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])
fig.suptitle("cloth-tear: fibers break, particles along each cut are copied, the cloth parts", fontsize=10)
fig.tight_layout()
fig.savefig(sys.argv[2] if len(sys.argv) > 2 else "cloth_tear.png", dpi=110)
print(f"fibers broken: {broken}; particles added by the tears: {copies}; particles now {w.num_particles}")
