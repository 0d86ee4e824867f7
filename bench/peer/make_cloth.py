#!/usr/bin/python3
"""Writes the cloth of the peer's ClothDemo (Bender et al., PositionBasedDynamics, Demos/ClothDemo/main.cpp) as a
plain text file that both bench/peer drivers read, so that pbd and the peer simulate the same mesh.

It reproduces, in the peer's order:
  - SimulationModel::addRegularTriangleModel(N, N, translation (0,1,0), rotation 90 deg about x, scale (10, 10)):
    vertex i*N + j at R*(j*dx, i*dy, 0) + (0, 1, 0), i.e. (x, 1, y) up to rounding; triangles with the diagonal
    alternating from cell to cell ("helper");
  - the demo's pins: setMass(0, 0) and setMass(nRows - 1, 0), two corners of one edge;
  - IndexedFaceMesh::buildNeighbors: the edge list (the order addClothConstraints(method 1) adds its distance
    constraints) and each edge's two faces;
  - addBendingConstraints(method 1): one DihedralConstraint per interior edge, on (point1, point2, edge v0, edge v1)
    where point1/point2 are the first vertex of face[0]/face[1] not on the edge.

Usage: make_cloth.py N OUT [--width 10] [--height 10]
Format (whitespace separated, '#' lines are comments):
  pbd_peer_cloth 1
  n N  width W  height H
  vertices V       then V lines "x y z" (17 significant digits: the peer's doubles exactly)
  mass 1           every vertex's mass in kg before the pins
  pinned P         then P indices (mass 0)
  triangles T      then T lines "a b c"
  edges E          then E lines "a b"          (distance constraints, in the peer's order)
  bending B        then B lines "p0 p1 e0 e1"  (peer's DihedralConstraint order: opposite corners, then the edge)
"""
import argparse
import math
import sys


def regular_grid(n_cols, n_rows, width, height):
    """Positions and triangles as addRegularTriangleModel(width=n_cols, height=n_rows) makes them."""
    # Eigen's AngleAxis(pi/2, x).toRotationMatrix(): rows (1, 0, 0), (0, c, -s), (0, s, c) with c = cos(pi/2) (not
    # quite 0) and s = 1. Applied to (x, y, 0) and translated by (0, 1, 0): (x, c*y + 1, y).
    c = math.cos(math.pi * 0.5)
    s = math.sin(math.pi * 0.5)
    dy = height / (n_rows - 1)
    dx = width / (n_cols - 1)
    points = []
    for i in range(n_rows):
        for j in range(n_cols):
            y = dy * i
            x = dx * j
            points.append((x + 0.0 * y, (c * y - s * 0.0) + 1.0, (s * y + c * 0.0)))
    tris = []
    for i in range(n_rows - 1):
        for j in range(n_cols - 1):
            helper = 1 if i % 2 == j % 2 else 0
            tris.append((i * n_cols + j, i * n_cols + j + 1, (i + 1) * n_cols + j + helper))
            tris.append(((i + 1) * n_cols + j + 1, (i + 1) * n_cols + j, i * n_cols + j + 1 - helper))
    return points, tris


def build_edges(n_vertices, tris):
    """IndexedFaceMesh::buildNeighbors: edges in order of first appearance, each with (face0, face1 or None)."""
    edges = []          # [a, b, face0, face1]
    lookup = {}         # frozen (min, max) -> edge index (the peer searches the vertex's edge list: same result)
    for f, (v0, v1, v2) in enumerate(tris):
        for a, b in ((v0, v1), (v1, v2), (v2, v0)):
            key = (a, b) if a < b else (b, a)
            e = lookup.get(key)
            if e is None:
                lookup[key] = len(edges)
                edges.append([a, b, f, None])
            else:
                edges[e][3] = f
    return edges


def bending_quads(edges, tris):
    """addBendingConstraints: (point1, point2, edge v0, edge v1) for every edge with two faces."""
    quads = []
    for a, b, f0, f1 in edges:
        if f1 is None:
            continue
        p1 = next(v for v in tris[f0] if v != a and v != b)
        p2 = next(v for v in tris[f1] if v != a and v != b)
        quads.append((p1, p2, a, b))
    return quads


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("n", type=int, help="particles per side (the demo: nRows = nCols)")
    ap.add_argument("out", help="output file")
    ap.add_argument("--width", type=float, default=10.0)
    ap.add_argument("--height", type=float, default=10.0)
    a = ap.parse_args()
    if a.n < 2:
        sys.exit("make_cloth.py: n must be at least 2")
    n = a.n
    points, tris = regular_grid(n, n, a.width, a.height)
    edges = build_edges(len(points), tris)
    quads = bending_quads(edges, tris)
    pinned = [0, n - 1]  # ClothDemo: pd.setMass(0, 0.0); pd.setMass(nRows - 1, 0.0)
    with open(a.out, "w") as f:
        w = f.write
        w("# the peer's ClothDemo cloth, written by bench/peer/make_cloth.py\n")
        w("pbd_peer_cloth 1\n")
        w(f"n {n} width {a.width!r} height {a.height!r}\n")
        w(f"vertices {len(points)}\n")
        for p in points:
            w("%r %r %r\n" % p)
        w("mass 1\n")
        w(f"pinned {len(pinned)}\n")
        w(" ".join(map(str, pinned)) + "\n")
        w(f"triangles {len(tris)}\n")
        for t in tris:
            w("%d %d %d\n" % t)
        w(f"edges {len(edges)}\n")
        for e in edges:
            w("%d %d\n" % (e[0], e[1]))
        w(f"bending {len(quads)}\n")
        for q in quads:
            w("%d %d %d %d\n" % q)
    print(f"{a.out}: {len(points)} vertices, {len(tris)} triangles, {len(edges)} distance edges, "
          f"{len(quads)} bending quads, pinned {pinned}", file=sys.stderr)


if __name__ == "__main__":
    main()
