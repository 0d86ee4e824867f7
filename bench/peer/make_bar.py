#!/usr/bin/python3
"""Writes the bar of the peer's BarDemo (Bender et al., PositionBasedDynamics, Demos/BarDemo/main.cpp) as a plain
text file that both bench/peer bar drivers read, so that pbd and the peer simulate the same mesh.

It reproduces, in the peer's order:
  - SimulationModel::addRegularTetModel(width 30, height 5, depth 5, translation (5, 0, 0), rotation I,
    scale (10, 1.5, 1.5)): vertex i*height*depth + j*depth + k at (i*dx, j*dy, k*dz) + translation - scale/2, with
    dx = 10/(width - 1) and so on, i.e. x in [0, 10], y and z in [-0.75, 0.75];
  - its 5 tets per cell, the split alternating with the parity of i + j + k (neighbouring cells share faces), each
    tet's corners in the peer's order;
  - its masses: 1 kg per vertex (addRegularTetModel's setMass(i, 1.0)), then the demo's pins: every vertex of the
    i = 0 end gets mass 0;
  - the tip, the vertices of the far end i = width - 1, whose mean position the drivers follow.

Usage: make_bar.py OUT [--width 30] [--height 5] [--depth 5] [--size 10 1.5 1.5]
Format (whitespace separated, '#' lines are comments):
  pbd_peer_bar 1
  width W  height H  depth D      vertices along x, y, z (the demo's width, height, depth)
  size SX SY SZ                   the bar's extent, m
  translation TX TY TZ            the demo's translation (the bar's centre)
  vertices V       then V lines "x y z" (17 significant digits: the peer's doubles exactly)
  mass 1           every vertex's mass in kg before the pins
  pinned P         then P indices (mass 0: the clamped end, i = 0)
  tip T            then T indices (the far end, i = W - 1)
  tets N           then N lines "a b c d" (the peer's corner order)
"""
import argparse
import sys


def regular_tets(width, height, depth, translation, scale):
    """Positions and tets as addRegularTetModel(width, height, depth, translation, Identity, scale) makes them."""
    dx = scale[0] / (width - 1)
    dy = scale[1] / (height - 1)
    dz = scale[2] / (depth - 1)
    t = [translation[d] - 0.5 * scale[d] for d in range(3)]
    points = [None] * (width * height * depth)
    for i in range(width):
        for j in range(height):
            for k in range(depth):
                # rotation * (x, y, z) + t with rotation = I: 1*x + 0*y + 0*z = x exactly (all finite)
                points[i * height * depth + j * depth + k] = (dx * i + t[0], dy * j + t[1], dz * k + t[2])
    tets = []
    for i in range(width - 1):
        for j in range(height - 1):
            for k in range(depth - 1):
                p0 = i * height * depth + j * depth + k
                p1 = p0 + 1
                p3 = (i + 1) * height * depth + j * depth + k
                p2 = p3 + 1
                p7 = (i + 1) * height * depth + (j + 1) * depth + k
                p6 = p7 + 1
                p4 = i * height * depth + (j + 1) * depth + k
                p5 = p4 + 1
                if (i + j + k) % 2 == 1:
                    tets += [(p2, p1, p6, p3), (p6, p3, p4, p7), (p4, p1, p6, p5), (p3, p1, p4, p0), (p6, p1, p4, p3)]
                else:
                    tets += [(p0, p2, p5, p1), (p7, p2, p0, p3), (p5, p2, p7, p6), (p7, p0, p5, p4), (p0, p2, p7, p5)]
    return points, tets


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--width", type=int, default=30, help="vertices along x (the bar's length)")
    ap.add_argument("--height", type=int, default=5, help="vertices along y")
    ap.add_argument("--depth", type=int, default=5, help="vertices along z")
    ap.add_argument("--size", type=float, nargs=3, default=[10.0, 1.5, 1.5], metavar=("SX", "SY", "SZ"))
    a = ap.parse_args()
    if min(a.width, a.height, a.depth) < 2:
        sys.exit("make_bar.py: width, height and depth must be >= 2")
    if min(a.size) <= 0:
        sys.exit("make_bar.py: the size must be > 0")
    translation = (0.5 * a.size[0], 0.0, 0.0)  # the demo's (5, 0, 0) for a 10 m bar: x from 0, centred in y and z
    points, tets = regular_tets(a.width, a.height, a.depth, translation, a.size)
    slab = a.height * a.depth
    pinned = list(range(slab))                                   # the demo: setMass(i*h*d + j*d + k, 0) for i = 0
    tip = list(range((a.width - 1) * slab, a.width * slab))
    with open(a.out, "w") as f:
        f.write("# the peer's BarDemo bar (bench/peer/make_bar.py): %d x %d x %d vertices, %g x %g x %g m\n"
                % (a.width, a.height, a.depth, a.size[0], a.size[1], a.size[2]))
        f.write("pbd_peer_bar 1\n")
        f.write("width %d height %d depth %d\n" % (a.width, a.height, a.depth))
        f.write("size %r %r %r\n" % tuple(a.size))
        f.write("translation %r %r %r\n" % translation)
        f.write("vertices %d\n" % len(points))
        for p in points:
            f.write("%r %r %r\n" % p)
        f.write("mass 1\n")
        f.write("pinned %d\n%s\n" % (len(pinned), " ".join(map(str, pinned))))
        f.write("tip %d\n%s\n" % (len(tip), " ".join(map(str, tip))))
        f.write("tets %d\n" % len(tets))
        for t in tets:
            f.write("%d %d %d %d\n" % t)


if __name__ == "__main__":
    main()
