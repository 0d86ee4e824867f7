#!/usr/bin/python3
"""Reads back the frames `pbd run --frames DIR --format vtu` writes, with meshio (Debian's python3-meshio) and numpy.

    /usr/bin/python3 check_frames.py PBD SCENE_DIR TEST_SCENE TET_SCENE WORK_DIR

Runs `pbd run` for 3 steps on scenes/rope.json, scenes/cloth.json and TEST_SCENE (a cloth and a rope: two bodies),
once with --format vtu and once with the default OBJ, and checks every .vtu frame: its point count and positions
against the OBJ frame of the same step (%.7g there), velocity, inverse_mass and pinned, the rope's line cells and the
cloth's triangles, the stretch of every line and triangle cell recomputed with numpy, the area array, and the .pvd's
timesteps (xml.etree) against step × dt. Then TET_SCENE (one tet body of a box generator with Neo-Hookean and tet
volume constraints): meshio reads each frame's surface triangles (the OBJ frame's faces) and one tetra cell per tet,
and its volume_ratio and strain recomputed with numpy from the step-0 frame as the rest shape. meshio 7.0 (Debian 12) reads every piece's points and point data of a
multi-piece .vtu but only the last piece's cells and cell data (the loop that collects the cell blocks of
_organize_cells sits outside its loop over pieces); so the cells and cell data are read with xml.etree here, and
meshio's cells are checked against the last piece's. Exits non-zero on the first failed check.
"""
import base64
import json
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

VTK_TYPES = {"Float32": np.float32, "Float64": np.float64, "Int64": np.int64, "UInt8": np.uint8, "Int32": np.int32,
             "UInt64": np.uint64}
STEPS = 3


def fail(message):
    print("check_frames: FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def run(pbd, scene, out, fmt, extra=()):
    if os.path.exists(out):
        shutil.rmtree(out)
    cmd = [pbd, "run", scene, "--frames", out, "--steps", str(STEPS), *extra] + (["--format", fmt] if fmt else [])
    r = subprocess.run(cmd, capture_output=True, text=True)
    check(r.returncode == 0, f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}")
    return r.stdout


def read_obj(path):
    """Vertices (N×3), and per object (in file order) its name, faces and lines (0-based, global)."""
    v, objects = [], []
    with open(path) as src:
        for line in src:
            t = line.split()
            if not t:
                continue
            if t[0] == "o":
                objects.append({"name": t[1], "f": [], "l": [], "first": len(v)})
            elif t[0] == "v":
                v.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                objects[-1]["f"].append([int(x) - 1 for x in t[1:4]])
            elif t[0] == "l":
                objects[-1]["l"].append([int(x) - 1 for x in t[1:3]])
    return np.array(v), objects


def decode(array, header_type):
    """The values of a base64 binary <DataArray> (header and data encoded together)."""
    raw = base64.b64decode("".join(array.text.split()))
    header = np.dtype(VTK_TYPES[header_type]).itemsize
    size = int(np.frombuffer(raw[:header], VTK_TYPES[header_type])[0])
    check(size == len(raw) - header, f"{array.get('Name')}: header says {size} bytes, has {len(raw) - header}")
    values = np.frombuffer(raw[header:], VTK_TYPES[array.get("type")])
    components = int(array.get("NumberOfComponents", "1"))
    return values.reshape(-1, components) if components > 1 else values


def read_pieces(path):
    """Per <Piece>: its points, point data, cells (connectivity split by offsets) with types, and cell data."""
    root = ET.parse(path).getroot()
    check(root.get("type") == "UnstructuredGrid" and root.get("byte_order") == "LittleEndian", f"{path}: header")
    header_type = root.get("header_type")
    pieces = []
    for piece in root.find("UnstructuredGrid").findall("Piece"):
        p = {"points": decode(piece.find("Points/DataArray"), header_type)}
        p["point_data"] = {a.get("Name"): decode(a, header_type) for a in piece.find("PointData")}
        p["cell_data"] = {a.get("Name"): decode(a, header_type) for a in piece.find("CellData")}
        cells = {a.get("Name"): decode(a, header_type) for a in piece.find("Cells")}
        starts = np.concatenate([[0], cells["offsets"][:-1]])
        p["cells"] = [cells["connectivity"][s:e] for s, e in zip(starts, cells["offsets"])]
        p["types"] = cells["types"]
        check(len(p["points"]) == int(piece.get("NumberOfPoints")), f"{path}: NumberOfPoints")
        check(len(p["types"]) == int(piece.get("NumberOfCells")), f"{path}: NumberOfCells")
        pieces.append(p)
    time = decode(root.find("UnstructuredGrid/FieldData/DataArray[@Name='TimeValue']"), header_type)
    return pieces, float(time[0])


def relative_stretch(x, a, b, rest):
    return np.abs(np.linalg.norm(x[a] - x[b], axis=-1) - rest) / rest


def check_scene(pbd, scene_file, work):
    with open(scene_file) as f:
        scene = json.load(f)
    name, dt = scene["name"], scene["dt"]
    vtu_dir, obj_dir = os.path.join(work, name + "_vtu"), os.path.join(work, name + "_obj")
    out = run(pbd, scene_file, vtu_dir, "vtu")
    check(f"wrote {STEPS + 1} frames" in out, f"{name}: the run should say it wrote {STEPS + 1} frames: {out}")
    run(pbd, scene_file, obj_dir, None)
    check(sorted(os.listdir(obj_dir)) == [f"{name}_{s:05d}.obj" for s in range(STEPS + 1)], f"{name}: OBJ files")
    check(sorted(os.listdir(vtu_dir)) == sorted([f"{name}_{s:05d}.vtu" for s in range(STEPS + 1)] + [name + ".pvd"]),
          f"{name}: VTU files {sorted(os.listdir(vtu_dir))}")

    # The .pvd: every frame, timestep = step × dt.
    collection = ET.parse(os.path.join(vtu_dir, name + ".pvd")).getroot()
    check(collection.get("type") == "Collection", f"{name}.pvd: not a Collection")
    datasets = collection.findall("Collection/DataSet")
    check([d.get("file") for d in datasets] == [f"{name}_{s:05d}.vtu" for s in range(STEPS + 1)], f"{name}.pvd files")
    for s, d in enumerate(datasets):
        check(math.isclose(float(d.get("timestep")), s * dt, rel_tol=1e-6, abs_tol=1e-12),
              f"{name}.pvd: step {s} timestep {d.get('timestep')}, expected {s * dt}")

    bodies = scene["bodies"]
    rest = None  # per body, its step-0 positions (the rest state of the rope and the flat cloth)
    meshio_note = ""
    for s in range(STEPS + 1):
        path = os.path.join(vtu_dir, f"{name}_{s:05d}.vtu")
        mesh = meshio.read(path)
        pieces, time = read_pieces(path)
        check(math.isclose(time, s * dt, rel_tol=1e-6, abs_tol=1e-12), f"{path}: TimeValue {time}")
        x_obj, objects = read_obj(os.path.join(obj_dir, f"{name}_{s:05d}.obj"))
        check(len(pieces) == len(bodies) == len(objects), f"{path}: {len(pieces)} pieces for {len(bodies)} bodies")
        check(mesh.points.shape == x_obj.shape, f"{path}: meshio reads {mesh.points.shape} points, OBJ has {x_obj.shape}")
        check(np.allclose(mesh.points, x_obj, rtol=1e-6, atol=1e-6), f"{path}: positions differ from the OBJ frame")
        check(np.array_equal(mesh.points, np.concatenate([p["points"] for p in pieces])), f"{path}: meshio's points")
        for key in ("velocity", "inverse_mass", "pinned"):
            check(np.array_equal(mesh.point_data[key], np.concatenate([p["point_data"][key] for p in pieces])),
                  f"{path}: meshio's {key}")
        # meshio's cells: all pieces' (a fixed meshio) or the last piece's only (meshio 7.0).
        last = pieces[-1]
        offset = len(mesh.points) - len(last["points"])
        meshio_cells = np.concatenate([c.data.ravel() for c in mesh.cells]) if mesh.cells else np.array([])
        every = np.concatenate([np.concatenate(p["cells"]) + sum(len(q["points"]) for q in pieces[:i])
                                for i, p in enumerate(pieces)])
        if len(pieces) > 1 and not np.array_equal(meshio_cells, every):
            check(np.array_equal(meshio_cells, np.concatenate(last["cells"]) + offset),
                  f"{path}: meshio's cells are neither every piece's nor the last piece's")
            meshio_note = "meshio read the points and point data of every piece but the cells of the last piece only"
        if rest is None:
            rest = [p["points"].astype(np.float64) for p in pieces]
        for b, (body, piece, obj) in enumerate(zip(bodies, pieces, objects)):
            x = piece["points"].astype(np.float64)
            n = len(x)
            where = f"{path}: piece {b} ({body['type']})"
            check(obj["name"] == f"{body['type']}_{b}", f"{where}: OBJ object {obj['name']}")
            check(np.array_equal(x, x_obj[obj["first"]:obj["first"] + n].astype(np.float32).astype(np.float64))
                  or np.allclose(x, x_obj[obj["first"]:obj["first"] + n], rtol=1e-6, atol=1e-6),
                  f"{where}: positions differ from the OBJ object's")
            v, w, pinned = (piece["point_data"][k] for k in ("velocity", "inverse_mass", "pinned"))
            check(v.shape == (n, 3) and np.all(np.isfinite(v)), f"{where}: velocity")
            check(np.array_equal(pinned, (w == 0).astype(np.uint8)), f"{where}: pinned is not (inverse_mass == 0)")
            check(np.all(v[pinned == 1] == 0), f"{where}: a pinned particle moves")
            check(np.all(x[pinned == 1] == rest[b][pinned == 1]), f"{where}: a pinned particle left its place")
            if s == 0:
                check(np.all(v == 0), f"{where}: velocity at step 0")
            else:
                check(np.any(v[:, 2] < 0), f"{where}: nothing falls")
            cells, types = piece["cells"], piece["types"]
            stretch, area = piece["cell_data"]["stretch"], piece["cell_data"]["area"]
            if body["type"] == "rope":
                m = body["particles"]
                check(n == m, f"{where}: {n} points")
                check(pinned[0] == 1 and np.all(pinned[1:] == 0), f"{where}: pinned {pinned}")
                check(np.allclose(w[1:-1], 1 / body["mass"], rtol=1e-6)
                      and math.isclose(w[-1], 1 / body.get("end_mass", body["mass"]), rel_tol=1e-6),
                      f"{where}: inverse masses {w}")
                check(np.all(x[0] == np.array(body["origin"])), f"{where}: the pinned end is not at the origin")
                check(np.all(types == 3), f"{where}: cell types {types}")
                check(np.array_equal(np.array(cells), np.array([[i, i + 1] for i in range(m - 1)])), f"{where}: lines")
                expected = relative_stretch(x, np.arange(m - 1), np.arange(1, m), body["length"] / (m - 1))
                check(np.allclose(stretch, expected, rtol=1e-6, atol=1e-7), f"{where}: stretch {stretch} vs {expected}")
                check(np.all(np.isnan(area)), f"{where}: area on a line must be NaN")
                check(obj["f"] == [] and np.array_equal(np.array(obj["l"]) - obj["first"], np.array(cells)),
                      f"{where}: the OBJ object's lines")
            elif body["type"] == "cloth":
                r = body["resolution"]
                check(n == r * r, f"{where}: {n} points")
                check(np.allclose(w[pinned == 0], r * r / body.get("mass", 1.0), rtol=1e-6), f"{where}: inverse masses")
                check(np.all(types == 5) and len(cells) == 2 * (r - 1) ** 2, f"{where}: {len(cells)} cells")
                tri = np.array(cells)
                check(np.array_equal(np.array(obj["f"]) - obj["first"], tri), f"{where}: the OBJ object's faces")
                # A triangle's stretch: the largest relative stretch of its three edges (every edge has a
                # constraint), rest lengths from the grid: particle k is (k mod r, k div r) × size / (r − 1).
                h = body.get("size", 1.0) / (r - 1)
                grid = np.stack([np.arange(n) % r, np.arange(n) // r], axis=1) * h
                edges = [(tri[:, e], tri[:, (e + 1) % 3]) for e in range(3)]
                expected = np.max([relative_stretch(x, a, c, np.linalg.norm(grid[a] - grid[c], axis=-1))
                                   for a, c in edges], axis=0)
                check(np.allclose(stretch, expected, rtol=1e-6, atol=1e-7),
                      f"{where}: stretch, largest difference {np.max(np.abs(stretch - expected))}")
                if "area" in body:
                    def areas(p):
                        return 0.5 * np.linalg.norm(np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]]),
                                                    axis=-1)
                    a0 = 0.5 * h * h
                    check(np.allclose(area, np.abs(areas(x) - a0) / a0, rtol=1e-6, atol=1e-7),
                          f"{where}: area, largest difference {np.max(np.abs(area - np.abs(areas(x) - a0) / a0))}")
                else:
                    check(np.all(np.isnan(area)), f"{where}: area without area constraints must be NaN")
                pin = body.get("pin", "corners")
                check(int(pinned.sum()) == {"none": 0, "corners": 2, "edge": r}[pin], f"{where}: {pinned.sum()} pinned")
    print(f"check_frames: {name}: {STEPS + 1} frames of {len(bodies)} bodies OK" +
          (f" ({meshio_note})" if meshio_note else ""))
    return vtu_dir


def edge_matrices(x, tets):
    """Per tet, [p1 − p0, p2 − p0, p3 − p0] as the columns of a 3×3 matrix."""
    return np.stack([x[tets[:, k]] - x[tets[:, 0]] for k in (1, 2, 3)], axis=2)


def check_tet_scene(pbd, scene_file, work):
    """A one-body tet scene: meshio reads every frame's triangles and tets with volume_ratio and strain."""
    with open(scene_file) as f:
        scene = json.load(f)
    name, (body,) = scene["name"], scene["bodies"]
    vtu_dir, obj_dir = os.path.join(work, name + "_vtu"), os.path.join(work, name + "_obj")
    run(pbd, scene_file, vtu_dir, "vtu")
    run(pbd, scene_file, obj_dir, None)
    cells = body["generator"]["cells"]
    num_tets = 6 * cells[0] * cells[1] * cells[2]  # a box cell is 6 tets; one cell per tet, not per constraint
    rest = None
    for s in range(STEPS + 1):
        path = os.path.join(vtu_dir, f"{name}_{s:05d}.vtu")
        mesh = meshio.read(path)
        x_obj, (obj,) = read_obj(os.path.join(obj_dir, f"{name}_{s:05d}.obj"))
        check(sorted(c.type for c in mesh.cells) == ["tetra", "triangle"], f"{path}: meshio's cells {mesh.cells}")
        triangles, tets = mesh.cells_dict["triangle"], mesh.cells_dict["tetra"]
        check(np.array_equal(triangles, np.array(obj["f"])), f"{path}: the triangles are not the OBJ frame's faces")
        check(tets.shape == (num_tets, 4), f"{path}: {tets.shape[0]} tets, expected {num_tets}")
        check(len(np.unique(np.sort(tets, axis=1), axis=0)) == num_tets, f"{path}: a tet is drawn twice")
        x = mesh.points.astype(np.float64)
        check(np.allclose(x, x_obj, rtol=1e-6, atol=1e-6), f"{path}: positions differ from the OBJ frame")
        if rest is None:
            rest = x
        ds, dm = edge_matrices(x, tets), edge_matrices(rest, tets)
        check(np.all(np.linalg.det(dm) > 0), f"{path}: a tet is not positively oriented (VTK_TETRA wants it so)")
        ratio, strain = mesh.cell_data_dict["volume_ratio"]["tetra"], mesh.cell_data_dict["strain"]["tetra"]
        expected = np.linalg.det(ds) / np.linalg.det(dm)
        check(np.allclose(ratio, expected, rtol=0, atol=1e-5), f"{path}: volume_ratio, largest difference "
              f"{np.max(np.abs(ratio - expected))}")
        F = ds @ np.linalg.inv(dm)
        green = np.linalg.norm(0.5 * (np.transpose(F, (0, 2, 1)) @ F - np.eye(3)), axis=(1, 2))
        check(np.allclose(strain, green, rtol=0, atol=1e-5), f"{path}: strain, largest difference "
              f"{np.max(np.abs(strain - green))}")
        for key in ("stretch", "area"):
            check(np.all(np.isnan(mesh.cell_data_dict[key]["tetra"])), f"{path}: {key} on a tet must be NaN")
        # A surface triangle shows the values of the tet it is a face of (the first such tet).
        face_tet = {}
        for k, t in enumerate(tets):
            for face in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
                face_tet.setdefault(tuple(sorted(t[list(face)])), k)
        on = [face_tet[tuple(sorted(t))] for t in triangles]
        for key, values in (("volume_ratio", ratio), ("strain", strain)):
            check(np.array_equal(mesh.cell_data_dict[key]["triangle"], values[on]),
                  f"{path}: a triangle's {key} is not its tet's")
    print(f"check_frames: {name}: {STEPS + 1} frames of {len(triangles)} triangles and {num_tets} tets OK "
          f"(largest strain {np.max(strain):.3g}, volume ratio in [{np.min(ratio):.6f}, {np.max(ratio):.6f}])")


def check_ligament(pbd, scene_dir, work):
    """The ligament (fibers that break): each frame draws the fibers left as line cells, with fiber_strain (total
    strain, recomputed here from the points and the step-0 rest lengths) and fiber_force; a frame after the breaks
    draws as many fewer lines as `pbd run --breaks` lists breaks up to its step."""
    out = os.path.join(work, "ligament")
    shutil.rmtree(out, ignore_errors=True)
    breaks = os.path.join(work, "ligament_breaks.csv")
    r = subprocess.run([pbd, "run", os.path.join(scene_dir, "ligament.json"), "--frames", out, "--format", "vtu",
                        "--every", "150", "--breaks", breaks], capture_output=True, text=True)
    check(r.returncode == 0, f"ligament: exit {r.returncode}: {r.stderr}")
    with open(breaks) as f:
        broke_at = [int(line.split(",")[0]) for line in f.read().splitlines()[1:]]
    check(len(broke_at) > 0, "ligament: no fiber broke")
    rest = None
    for step in (0, 150, 300, 450):
        (piece,), _ = read_pieces(os.path.join(out, f"ligament_{step:05d}.vtu"))
        x, lines = piece["points"], np.array(piece["cells"])
        check(set(piece["types"]) == {3}, f"ligament step {step}: cell types {set(piece['types'])}")
        expected = 140 - sum(1 for s in broke_at if s <= step)
        check(len(lines) == expected, f"ligament step {step}: {len(lines)} lines, expected {expected}")
        length = np.linalg.norm(x[lines[:, 0]] - x[lines[:, 1]], axis=1)
        if rest is None:
            rest = {tuple(l): d for l, d in zip(lines.tolist(), length)}
        strain = piece["cell_data"]["fiber_strain"]
        want = length / np.array([rest[tuple(l)] for l in lines.tolist()]) - 1
        check(np.allclose(strain, want, rtol=0, atol=2e-6), f"ligament step {step}: fiber_strain off by "
              f"{np.max(np.abs(strain - want))}")
        force = piece["cell_data"]["fiber_force"]
        check(np.all(np.isnan(force)) if step == 0 else np.all(np.isfinite(force)),
              f"ligament step {step}: fiber_force {force[:3]}")


def check_tet_tear(pbd, scene_dir, work):
    """The tet-tear scene (a block of tets reinforced by fibers on every edge, torn by its grips): each frame draws
    the tets that hold no broken fiber's two ends (`pbd run --breaks` up to its step) and, as its triangles, their
    boundary (each a face of exactly one of them); by the end the tets left are in two pieces, one on each grip."""
    out = os.path.join(work, "tet_tear")
    shutil.rmtree(out, ignore_errors=True)
    breaks = os.path.join(work, "tet_tear_breaks.csv")
    scene_file = os.path.join(scene_dir, "tet-tear.json")
    with open(scene_file) as f:
        scene = json.load(f)
    last = scene["steps"]
    r = subprocess.run([pbd, "run", scene_file, "--frames", out, "--format", "vtu", "--every", str(last // 3),
                        "--breaks", breaks], capture_output=True, text=True)
    check(r.returncode == 0, f"tet-tear: exit {r.returncode}: {r.stderr}")
    with open(breaks) as f:
        rows = [line.split(",") for line in f.read().splitlines()[1:]]
    check(all(row[2] == "fiber" for row in rows), "tet-tear: a break that is not a fiber's")
    broke = [(int(row[0]), int(row[5]), int(row[6])) for row in rows]
    check(len(broke) > 0, "tet-tear: no fiber broke")
    all_tets = None
    for step in range(0, last + 1, last // 3):
        (piece,), _ = read_pieces(os.path.join(out, f"tet-tear_{step:05d}.vtu"))
        cells, types = piece["cells"], np.array(piece["types"])
        tets = [tuple(c) for c, t in zip(cells, types) if t == 10]
        triangles = [tuple(c) for c, t in zip(cells, types) if t == 5]
        if all_tets is None:
            all_tets = tets
        gone = {tuple(sorted((a, b))) for s, a, b in broke if s <= step}
        want = [t for t in all_tets if not any(tuple(sorted((t[i], t[j]))) in gone
                                              for i in range(4) for j in range(i + 1, 4))]
        check(tets == want, f"tet-tear step {step}: {len(tets)} tets drawn, {len(want)} hold no broken fiber")
        faces = {}
        for t in tets:
            for face in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
                key = tuple(sorted(t[i] for i in face))
                faces[key] = faces.get(key, 0) + 1
        boundary = sorted(k for k, n in faces.items() if n == 1)
        check(sorted(tuple(sorted(t)) for t in triangles) == boundary,
              f"tet-tear step {step}: the triangles are not the boundary of the tets drawn")
    parent = list(range(len(piece["points"])))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    for t in tets:
        for p in t[1:]:
            parent[find(p)] = find(t[0])
    body = scene["bodies"][0]
    left = {find(p) for p in body["grips"][0]["particles"]}
    right = {find(p) for p in body["grips"][1]["particles"]}
    check(len(left) == 1 and len(right) == 1 and left != right,
          f"tet-tear: at step {last} the grips are in pieces {left} and {right}: not torn in two")
    print(f"check_frames: tet-tear: {len(broke)} fibers broke, {len(all_tets) - len(tets)} of {len(all_tets)} tets "
          f"went with them, torn in two")


def main():
    if len(sys.argv) != 6:
        fail(__doc__)
    pbd, scene_dir, test_scene, tet_scene, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    for scene in (os.path.join(scene_dir, "rope.json"), os.path.join(scene_dir, "cloth.json"), test_scene):
        check_scene(pbd, scene, work)
    check_tet_scene(pbd, tet_scene, work)
    check_ligament(pbd, scene_dir, work)
    check_tet_tear(pbd, scene_dir, work)
    # --every 2: steps 0 and 2 only, and the .pvd lists those two.
    out = os.path.join(work, "every")
    run(pbd, test_scene, out, "vtu", ["--every", "2"])
    check(sorted(os.listdir(out)) == ["rope_and_cloth.pvd", "rope_and_cloth_00000.vtu", "rope_and_cloth_00002.vtu"],
          f"--every 2: {sorted(os.listdir(out))}")
    steps = [d.get("file") for d in ET.parse(os.path.join(out, "rope_and_cloth.pvd")).getroot().iter("DataSet")]
    check(steps == ["rope_and_cloth_00000.vtu", "rope_and_cloth_00002.vtu"], f"--every 2: the .pvd lists {steps}")
    # A bad format is refused, naming the valid ones.
    r = subprocess.run([pbd, "run", test_scene, "--frames", out, "--format", "ply"], capture_output=True, text=True)
    check(r.returncode != 0 and "obj" in r.stderr + r.stdout and "vtu" in r.stderr + r.stdout,
          f"--format ply: exit {r.returncode}, {r.stderr}")
    print("check_frames: OK")


if __name__ == "__main__":
    main()
