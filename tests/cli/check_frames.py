#!/usr/bin/python3
"""Reads back the frames `pbd run --frames DIR --format vtu` writes, with meshio (Debian's python3-meshio), xml.etree
and numpy, and with VTK's own reader (Debian's python3-vtk9).

    /usr/bin/python3 check_frames.py PBD SCENE_DIR TEST_SCENE TET_SCENE WORK_DIR
    /usr/bin/python3 check_frames.py --vtk PBD SCENE_DIR TEST_SCENE WORK_DIR

A frame is one piece holding every particle, with a `body` id per point and per cell
(io/include/pbd/io/vtu_frame.hpp). The first form runs `pbd run` for 3 steps on scenes/rope.json, scenes/cloth.json
and TEST_SCENE (a cloth and a rope: two bodies), once with --format vtu and once with the default OBJ, and checks
every .vtu frame: that meshio reads it whole (every point, cell and array as xml.etree does), its points against the
OBJ frame of the same step (%.7g there), and per body (by its body ids) the velocity, inverse_mass and pinned, the
rope's line cells and the cloth's triangles, the stretch of every line and triangle cell recomputed with numpy, the
area array (only with area constraints), the .pvd's timesteps (xml.etree) against step × dt and the OBJ frame's
objects, one per body. Then TET_SCENE (one tet body of a box generator with Neo-Hookean and tet volume constraints):
meshio reads each frame's surface triangles (the OBJ frame's faces) and one tetra cell per tet, and its volume_ratio
and strain recomputed with numpy from the step-0 frame as the rest shape. Then scenes/balls.json (5 bodies) and
scenes/balls-tets.json (5 tet bodies): every point, triangle and tet with its body's id and arrays, in meshio and in
the OBJ frame's objects; and rope.json's times after 90 steps of 1/60 s in float and double (1.5, exactly). The second form
reads TEST_SCENE, balls and balls-tets frames with VTK's vtkXMLUnstructuredGridReader and checks that VTK sees what
xml.etree and meshio see; it exits 77 (a skip for ctest) if VTK's Python module is not installed. Exits non-zero on
the first failed check.
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


def read_frame(path):
    """The frame's one <Piece>: points, point data, cells (connectivity split by offsets) with types, cell data, time."""
    root = ET.parse(path).getroot()
    check(root.get("type") == "UnstructuredGrid" and root.get("byte_order") == "LittleEndian", f"{path}: header")
    header_type = root.get("header_type")
    pieces = root.find("UnstructuredGrid").findall("Piece")
    check(len(pieces) == 1, f"{path}: {len(pieces)} pieces, expected one")
    piece = pieces[0]
    p = {"points": decode(piece.find("Points/DataArray"), header_type)}
    p["point_data"] = {a.get("Name"): decode(a, header_type) for a in piece.find("PointData")}
    p["cell_data"] = {a.get("Name"): decode(a, header_type) for a in piece.find("CellData")}
    cells = {a.get("Name"): decode(a, header_type) for a in piece.find("Cells")}
    starts = np.concatenate([[0], cells["offsets"][:-1]])
    p["cells"] = [cells["connectivity"][s:e] for s, e in zip(starts, cells["offsets"])]
    p["types"] = cells["types"]
    check(len(p["points"]) == int(piece.get("NumberOfPoints")), f"{path}: NumberOfPoints")
    check(len(p["types"]) == int(piece.get("NumberOfCells")), f"{path}: NumberOfCells")
    check(p["point_data"]["body"].dtype == np.int32 and p["cell_data"]["body"].dtype == np.int32, f"{path}: body ids")
    p["time"] = float(decode(root.find("UnstructuredGrid/FieldData/DataArray[@Name='TimeValue']"), header_type)[0])
    return p


def body_part(frame, b):
    """Body b of a frame: its points (a run of them: the first and the array), its cells renumbered from its first
    point with their types, and its point and cell data."""
    on = np.flatnonzero(frame["point_data"]["body"] == b)
    check(len(on) > 0 and np.array_equal(on, np.arange(on[0], on[-1] + 1)), f"body {b}: its points are not one run")
    first = int(on[0])
    mine = frame["cell_data"]["body"] == b
    cells = [c - first for c, m in zip(frame["cells"], mine) if m]
    check(all(np.all((c >= 0) & (c < len(on))) for c in cells), f"body {b}: a cell on another body's point")
    return {"first": first, "points": frame["points"][on], "cells": cells, "types": frame["types"][mine],
            "point_data": {k: v[on] for k, v in frame["point_data"].items()},
            "cell_data": {k: v[mine] for k, v in frame["cell_data"].items()}}


VTK_CELL_NAMES = {"vertex": 1, "line": 3, "triangle": 5, "tetra": 10}


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def check_whole(path, frame, reader, seen):
    """That `reader` ("meshio" or "vtk"), whose reading of the file is `seen` (points, point_data, cells, types,
    cell_data), sees every point, cell and array of the frame as xml.etree does."""
    points, point_data, cells, types, cell_data = seen
    where = f"{path} read by {reader}"
    check(same(points, frame["points"]), f"{where}: {len(points)} points, the file has {len(frame['points'])}")
    check(len(cells) == len(frame["cells"]), f"{where}: {len(cells)} cells, the file has {len(frame['cells'])}")
    check(same(types, frame["types"]), f"{where}: cell types differ")
    check(all(same(a, b) for a, b in zip(cells, frame["cells"])), f"{where}: cells differ")
    for name, data in (("point", point_data), ("cell", cell_data)):
        theirs, ours = set(data), set(frame[name + "_data"])
        check(theirs == ours, f"{where}: {name} arrays {sorted(theirs)}, the file has {sorted(ours)}")
        for key in ours:
            check(same(np.asarray(data[key]).reshape(frame[name + "_data"][key].shape), frame[name + "_data"][key]),
                  f"{where}: {name} array {key} differs")


def meshio_view(path):
    mesh = meshio.read(path)
    cells = [row for block in mesh.cells for row in block.data]
    types = np.concatenate([[VTK_CELL_NAMES[block.type]] * len(block.data) for block in mesh.cells])
    cell_data = {k: np.concatenate(v) for k, v in mesh.cell_data.items()}
    return mesh.points, dict(mesh.point_data), cells, types, cell_data


def vtk_view(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    check(reader.GetErrorCode() == 0, f"{path}: VTK's reader reports error {reader.GetErrorCode()}")
    points = vtk_to_numpy(grid.GetPoints().GetData())
    cell_array = grid.GetCells()
    connectivity, offsets = vtk_to_numpy(cell_array.GetConnectivityArray()), vtk_to_numpy(cell_array.GetOffsetsArray())
    cells = [connectivity[a:b] for a, b in zip(offsets[:-1], offsets[1:])]
    types = vtk_to_numpy(grid.GetCellTypesArray())

    def arrays(data):
        return {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)) for i in range(data.GetNumberOfArrays())}
    return points, arrays(grid.GetPointData()), cells, types, arrays(grid.GetCellData())


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
    has_area = any("area" in body for body in bodies)
    rest = None  # per body, its step-0 positions (the rest state of the rope and the flat cloth)
    for s in range(STEPS + 1):
        path = os.path.join(vtu_dir, f"{name}_{s:05d}.vtu")
        frame = read_frame(path)
        check_whole(path, frame, "meshio", meshio_view(path))
        check(math.isclose(frame["time"], s * dt, rel_tol=1e-6, abs_tol=1e-12), f"{path}: TimeValue {frame['time']}")
        x_obj, objects = read_obj(os.path.join(obj_dir, f"{name}_{s:05d}.obj"))
        check(len(objects) == len(bodies), f"{path}: {len(objects)} OBJ objects for {len(bodies)} bodies")
        check(set(frame["point_data"]["body"]) == set(range(len(bodies))), f"{path}: body ids of the points")
        check(frame["points"].shape == x_obj.shape, f"{path}: {frame['points'].shape} points, OBJ has {x_obj.shape}")
        check(np.allclose(frame["points"], x_obj, rtol=1e-6, atol=1e-6), f"{path}: positions differ from the OBJ frame")
        check(("area" in frame["cell_data"]) == has_area, f"{path}: an area array only with area constraints")
        pieces = [body_part(frame, b) for b in range(len(bodies))]
        if rest is None:
            rest = [p["points"].astype(np.float64) for p in pieces]
        for b, (body, piece, obj) in enumerate(zip(bodies, pieces, objects)):
            x = piece["points"].astype(np.float64)
            n = len(x)
            where = f"{path}: body {b} ({body['type']})"
            check(obj["name"] == f"{body['type']}_{b}" and obj["first"] == piece["first"], f"{where}: OBJ object "
                  f"{obj['name']} from vertex {obj['first']}")
            v, w, pinned = (piece["point_data"][k] for k in ("velocity", "inverse_mass", "pinned"))
            check(v.shape == (n, 3) and np.all(np.isfinite(v)), f"{where}: velocity")
            check(np.array_equal(pinned, (w == 0).astype(np.uint8)), f"{where}: pinned is not (inverse_mass == 0)")
            check(np.all(v[pinned == 1] == 0), f"{where}: a pinned particle moves")
            check(np.all(x[pinned == 1] == rest[b][pinned == 1]), f"{where}: a pinned particle left its place")
            if s == 0:
                check(np.all(v == 0), f"{where}: velocity at step 0")
            else:
                check(np.any(v[:, 2] < 0), f"{where}: nothing falls")
            check(np.all(piece["cell_data"]["body"] == b), f"{where}: cell body ids")
            cells, types = piece["cells"], piece["types"]
            stretch = piece["cell_data"]["stretch"]
            area = piece["cell_data"].get("area", np.full(len(cells), np.nan))
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
                    check(np.all(np.isnan(area)), f"{where}: area on a cloth without area constraints must be NaN")
                pin = body.get("pin", "corners")
                check(int(pinned.sum()) == {"none": 0, "corners": 2, "edge": r}[pin], f"{where}: {pinned.sum()} pinned")
    print(f"check_frames: {name}: {STEPS + 1} frames of {len(bodies)} bodies OK, read whole by meshio")
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
            check(key not in mesh.cell_data, f"{path}: a {key} array without {key} constraints")
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
        piece = read_frame(os.path.join(out, f"ligament_{step:05d}.vtu"))
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
        piece = read_frame(os.path.join(out, f"tet-tear_{step:05d}.vtu"))
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


def check_multibody(pbd, scene_file, work, views):
    """A scene of several bodies, one step: each reader in `views` ({name: function of the path}) sees every point,
    triangle and tet; per body, its points are a run with its id, its cells lie on them, and the OBJ frame has one
    object per body with the same points and triangles."""
    name = os.path.splitext(os.path.basename(scene_file))[0]
    with open(scene_file) as f:
        bodies = json.load(f)["bodies"]
    vtu_dir, obj_dir = os.path.join(work, name + "_vtu"), os.path.join(work, name + "_obj")
    for out, fmt in ((vtu_dir, "vtu"), (obj_dir, None)):
        shutil.rmtree(out, ignore_errors=True)
        cmd = [pbd, "run", scene_file, "--frames", out, "--steps", "1"] + (["--format", fmt] if fmt else [])
        r = subprocess.run(cmd, capture_output=True, text=True)
        check(r.returncode == 0, f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}")
    path = os.path.join(vtu_dir, f"{name}_00001.vtu")
    frame = read_frame(path)
    for reader, view in views.items():
        check_whole(path, frame, reader, view(path))
    x_obj, objects = read_obj(os.path.join(obj_dir, f"{name}_00001.obj"))
    check(len(objects) == len(bodies), f"{name}: {len(objects)} OBJ objects for {len(bodies)} bodies")
    check(np.allclose(frame["points"], x_obj, rtol=1e-6, atol=1e-6), f"{path}: positions differ from the OBJ frame")
    counts = {}
    for b, obj in enumerate(objects):
        part = body_part(frame, b)
        where = f"{path}: body {b}"
        check(part["first"] == obj["first"] and obj["name"] == f"{bodies[b]['type']}_{b}",
              f"{where}: OBJ object {obj['name']} from vertex {obj['first']}, the frame's body from {part['first']}")
        triangles = [c for c, t in zip(part["cells"], part["types"]) if t == 5]
        check(same(np.array(triangles) + part["first"], np.array(obj["f"])), f"{where}: triangles differ from the OBJ's")
        for key, values in part["cell_data"].items():
            if key not in ("body", "strain"):  # strain: NaN on a tet without a rest shape, none here
                check(np.all(np.isfinite(values[part["types"] != 3])), f"{where}: {key} not finite on a cell")
        for t in set(part["types"]):
            counts[int(t)] = counts.get(int(t), []) + [int(np.sum(part["types"] == t))]
    check(sum(sum(c) for c in counts.values()) == len(frame["cells"]), f"{path}: a cell without a body")
    kinds = ", ".join(f"{sum(c)} {dict((v, k) for k, v in VTK_CELL_NAMES.items())[t]}s ({'+'.join(map(str, c))})"
                      for t, c in sorted(counts.items()))
    print(f"check_frames: {name}: {len(frame['points'])} points of {len(bodies)} bodies, {kinds}: read whole by "
          f"{' and '.join(views)}, one OBJ object per body")
    return frame


def main_vtk(argv):
    """The --vtk form: VTK's reader on the two-body test scene, balls and balls-tets."""
    if len(argv) != 4:
        fail(__doc__)
    try:
        import vtk  # noqa: F401  (Debian's python3-vtk9)
    except ImportError:
        print("check_frames: SKIPPED: VTK's Python module is not installed (Debian: python3-vtk9)")
        sys.exit(77)
    pbd, scene_dir, test_scene, work = argv
    os.makedirs(work, exist_ok=True)
    views = {"VTK": vtk_view, "meshio": meshio_view}
    for scene in (test_scene, os.path.join(scene_dir, "balls.json"), os.path.join(scene_dir, "balls-tets.json")):
        check_multibody(pbd, scene, work, views)
    print("check_frames: OK")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--vtk":
        return main_vtk(sys.argv[2:])
    if len(sys.argv) != 6:
        fail(__doc__)
    pbd, scene_dir, test_scene, tet_scene, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    for scene in (os.path.join(scene_dir, "rope.json"), os.path.join(scene_dir, "cloth.json"), test_scene):
        check_scene(pbd, scene, work)
    check_tet_scene(pbd, tet_scene, work)
    balls = check_multibody(pbd, os.path.join(scene_dir, "balls.json"), work, {"meshio": meshio_view})
    check(np.sum(balls["types"] == 5) == 1600 and "area" not in balls["cell_data"], "balls: 1600 triangles, no area")
    check_multibody(pbd, os.path.join(scene_dir, "balls-tets.json"), work, {"meshio": meshio_view})
    check_ligament(pbd, scene_dir, work)
    check_tet_tear(pbd, scene_dir, work)
    # --every 2: steps 0 and 2 only, and the .pvd lists those two.
    out = os.path.join(work, "every")
    run(pbd, test_scene, out, "vtu", ["--every", "2"])
    check(sorted(os.listdir(out)) == ["rope_and_cloth.pvd", "rope_and_cloth_00000.vtu", "rope_and_cloth_00002.vtu"],
          f"--every 2: {sorted(os.listdir(out))}")
    steps = [d.get("file") for d in ET.parse(os.path.join(out, "rope_and_cloth.pvd")).getroot().iter("DataSet")]
    check(steps == ["rope_and_cloth_00000.vtu", "rope_and_cloth_00002.vtu"], f"--every 2: the .pvd lists {steps}")
    # Times are step × the scene's dt, written exactly: 90 steps of 1/60 s are 1.5 s (a sum of 90 steps is
    # 1.4999999999999996; the float world's dt, 1/60 rounded, would give 1.5000000782), in both precisions.
    for precision in ("float", "double"):
        out = os.path.join(work, "times")
        shutil.rmtree(out, ignore_errors=True)
        cmd = [pbd, "run", os.path.join(scene_dir, "rope.json"), "--frames", out, "--format", "vtu", "--steps", "90",
               "--every", "90", "--precision", precision]
        r = subprocess.run(cmd, capture_output=True, text=True)
        check(r.returncode == 0, f"{' '.join(cmd)} exited {r.returncode}: {r.stderr}")
        times = [d.get("timestep") for d in ET.parse(os.path.join(out, "rope.pvd")).getroot().iter("DataSet")]
        check(times == ["0", "1.5"], f"rope in {precision}, 90 steps of 1/60 s: the .pvd's times are {times}")
        check(read_frame(os.path.join(out, "rope_00090.vtu"))["time"] == 1.5, f"rope in {precision}: TimeValue")
    # A bad format is refused, naming the valid ones.
    r = subprocess.run([pbd, "run", test_scene, "--frames", out, "--format", "ply"], capture_output=True, text=True)
    check(r.returncode != 0 and "obj" in r.stderr + r.stdout and "vtu" in r.stderr + r.stdout,
          f"--format ply: exit {r.returncode}, {r.stderr}")
    print("check_frames: OK")


if __name__ == "__main__":
    main()
