"""What `pbd run --frames DIR --stats FILE` leaves, checked whole (shared by check_run.py and check_signals.py): the
frames present are exactly those the .pvd lists (vtu), each one complete and finite (a .vtu parses as XML and its
positions decode to NumberOfPoints finite points; an .obj has finite vertices and faces on them), no temporary is
left, and the statistics CSV has a header and one complete row per step, 1, 2, ... in order."""
import base64
import math
import os
import re
import struct
import xml.etree.ElementTree as ET

FRAME = re.compile(r"^(?P<stem>.+)_(?P<step>\d{5,})\.(?P<fmt>obj|vtu)$")


class Invalid(Exception):
    pass


def _check_obj(path):
    vertices, faces = 0, 0
    with open(path) as f:
        for n, line in enumerate(f, 1):
            t = line.split()
            if t and t[0] == "v":
                if len(t) != 4 or not all(math.isfinite(float(x)) for x in t[1:]):
                    raise Invalid(f"{path}:{n}: not a finite vertex: {line!r}")
                vertices += 1
            elif t and t[0] in ("f", "l"):
                if not all(1 <= int(i) <= vertices for i in t[1:]):
                    raise Invalid(f"{path}:{n}: an index beyond the {vertices} vertices: {line!r}")
                faces += 1
    if not vertices:
        raise Invalid(f"{path}: no vertex")


def _check_vtu(path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise Invalid(f"{path}: not XML ({e})")
    piece = root.find("UnstructuredGrid/Piece")
    array = piece.find("Points/DataArray")
    raw = base64.b64decode("".join(array.text.split()))
    size = struct.unpack("<Q", raw[:8])[0]
    width = 4 if array.get("type") == "Float32" else 8
    if size != len(raw) - 8 or size != 3 * width * int(piece.get("NumberOfPoints")):
        points = piece.get("NumberOfPoints")
        raise Invalid(f"{path}: positions of {size} bytes, {len(raw) - 8} there, for {points} points")
    values = struct.unpack(f"<{size // width}{'f' if width == 4 else 'd'}", raw[8:])
    if not all(math.isfinite(v) for v in values):
        raise Invalid(f"{path}: a non-finite position")


def check_frames(folder, stem, fmt):
    """The steps of the frames in `folder`, sorted, after checking each, the .pvd (vtu) and that no other file is
    there (a temporary). Raises Invalid."""
    steps, others = [], []
    for name in os.listdir(folder):
        m = FRAME.match(name)
        if m and m["stem"] == stem and m["fmt"] == fmt:
            steps.append(int(m["step"]))
            (_check_vtu if fmt == "vtu" else _check_obj)(os.path.join(folder, name))
        elif name != f"{stem}.pvd" or fmt != "vtu":
            others.append(name)
    if others:
        raise Invalid(f"{folder}: files other than frames and the .pvd (temporaries?): {sorted(others)}")
    steps.sort()
    if fmt == "vtu" and steps:
        try:
            listed = [d.get("file") for d in ET.parse(os.path.join(folder, stem + ".pvd")).getroot().iter("DataSet")]
        except (ET.ParseError, FileNotFoundError) as e:
            raise Invalid(f"{folder}/{stem}.pvd: {e}")
        if listed != [f"{stem}_{s:05d}.vtu" for s in steps]:
            raise Invalid(f"{stem}.pvd lists {len(listed)} frames, the folder has {len(steps)}: {listed[:3]}...")
    return steps


def check_stats(path):
    """The steps of the rows of a --stats CSV, which must be 1, 2, ..., each row as long as the header."""
    with open(path) as f:
        text = f.read()
    if not text.endswith("\n"):
        raise Invalid(f"{path}: the last row is cut short: {text[-80:]!r}")
    lines = text.splitlines()
    header = lines[0].split(",")
    if header[0] != "step":
        raise Invalid(f"{path}: header {lines[0]!r}")
    steps = []
    for n, line in enumerate(lines[1:], 2):
        cells = line.split(",")
        if len(cells) != len(header):
            raise Invalid(f"{path}:{n}: {len(cells)} cells, the header has {len(header)}")
        steps.append(int(cells[0]))
    if steps != list(range(1, len(steps) + 1)):
        raise Invalid(f"{path}: steps {steps[:5]}..., expected 1, 2, ...")
    return steps
