#!/usr/bin/python3
"""Renders OBJ frames written by `pbd run` to a PNG with matplotlib (headless, Agg backend).

Triangles are drawn flat-shaded by a fixed light, "l" segments as lines, and, with --scene, the scene's colliders:
the planes z = const as a grey floor and the spheres as wireframes. Several frames give side-by-side panels with
the same axes (e.g. before and after). Run with Debian's /usr/bin/python3 (matplotlib and numpy from apt).

    scripts/render_frame.py FRAME.obj [FRAME2.obj ...] OUT.png [--scene SCENE.json] [--title TEXT]
                            [--labels "a,b"] [--elev 20] [--azim -60]
"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402


def read_obj(path):
    v, f, l = [], [], []
    with open(path) as src:
        for line in src:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                v.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                f.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
            elif t[0] == "l":
                l.append([int(x) - 1 for x in t[1:3]])
    return np.array(v), np.array(f, dtype=int).reshape(-1, 3), np.array(l, dtype=int).reshape(-1, 2)


def colliders(path):
    floor, spheres = None, []
    if path:
        with open(path) as src:
            scene = json.load(src)
        for c in scene.get("colliders", []):
            if c["type"] == "plane":
                n = np.array(c["normal"], dtype=float)
                if abs(n[0]) < 1e-12 and abs(n[1]) < 1e-12 and n[2] > 0:
                    floor = c.get("offset", 0.0) / np.linalg.norm(n)
            elif c["type"] == "sphere":
                spheres.append((np.array(c["center"], dtype=float), float(c["radius"])))
    return floor, spheres


def draw(ax, v, f, l, floor, spheres, centre, half):
    # Drawn in a fixed order (floor, colliders, body): matplotlib cannot depth-sort intersecting collections.
    if floor is not None:
        g = np.array([[centre[0] - half, centre[1] - half], [centre[0] + half, centre[1] - half],
                      [centre[0] + half, centre[1] + half], [centre[0] - half, centre[1] + half]])
        ax.add_collection3d(Poly3DCollection([np.c_[g, np.full(4, floor)]], facecolor=(0.85, 0.85, 0.82),
                                             edgecolor="none", zorder=0))
    for c, r in spheres:
        u, w = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
        ax.plot_wireframe(c[0] + r * np.cos(u) * np.sin(w), c[1] + r * np.sin(u) * np.sin(w),
                          c[2] + r * np.cos(w), color=(0.5, 0.5, 0.6), linewidth=0.4, zorder=1)
    if len(f):
        tri = v[f]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
        light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
        shade = 0.35 + 0.65 * np.abs(n @ light)  # two-sided: cloth shows either side
        colors = np.clip(shade[:, None] * np.array([0.85, 0.45, 0.35])[None, :], 0, 1)
        ax.add_collection3d(Poly3DCollection(tri, facecolors=colors, edgecolor=(0, 0, 0, 0.15), linewidths=0.2,
                                             zorder=2))
    if len(l):
        ax.add_collection3d(Line3DCollection(v[l], colors=(0.2, 0.3, 0.6), linewidths=1.5, zorder=2))
        ends = v[np.unique(l)]
        ax.scatter(ends[:, 0], ends[:, 1], ends[:, 2], s=4, color=(0.2, 0.3, 0.6), zorder=3)
    if not len(f) and not len(l):
        ax.scatter(v[:, 0], v[:, 1], v[:, 2], s=4, zorder=2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="FRAME.obj ... OUT.png")
    ap.add_argument("--scene", help="scene JSON: draw its colliders")
    ap.add_argument("--title", default="")
    ap.add_argument("--labels", default="", help="comma-separated panel titles")
    ap.add_argument("--elev", type=float, default=22)
    ap.add_argument("--azim", type=float, default=-60)
    a = ap.parse_args()
    if len(a.files) < 2:
        ap.error("give at least one frame and the output PNG")
    frames, out = a.files[:-1], a.files[-1]
    meshes = [read_obj(p) for p in frames]
    floor, spheres = colliders(a.scene)
    # The view holds what is drawn: a frame with triangles or lines, the particles on them (a torn body's loose
    # particles, on neither, may fly far); else every particle.
    drawn = [v[np.unique(np.r_[f.ravel(), l.ravel()])] if len(f) or len(l) else v for v, f, l in meshes]
    lo = np.min([d.min(axis=0) for d in drawn], axis=0)
    hi = np.max([d.max(axis=0) for d in drawn], axis=0)
    for c, r in spheres:
        lo, hi = np.minimum(lo, c - r), np.maximum(hi, c + r)
    if floor is not None:
        lo[2] = min(lo[2], floor)
    centre = (lo + hi) / 2
    half = max((hi - lo).max() / 2, 1e-9) * 1.05
    labels = a.labels.split(",") if a.labels else [""] * len(frames)
    fig = plt.figure(figsize=(8, 6) if len(frames) == 1 else (4.5 * len(frames), 4.8), dpi=100)
    for k, (v, f, l) in enumerate(meshes):
        ax = fig.add_subplot(1, len(frames), k + 1, projection="3d", computed_zorder=False)
        draw(ax, v, f, l, floor, spheres, centre, half)
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=a.elev, azim=a.azim)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_zlabel("z (m)")
        if k < len(labels) and labels[k]:
            ax.set_title(labels[k])
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(out)


if __name__ == "__main__":
    main()
