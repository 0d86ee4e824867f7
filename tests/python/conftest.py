"""Shared helpers of the Python tests: the module under test, the scene folder and small worlds."""
import os
import pathlib

import pytest

import pbd

SCENES = pathlib.Path(os.environ.get("PBD_SCENE_DIR", pathlib.Path(__file__).resolve().parents[2] / "scenes"))


def cloth(world_type=pbd.World, n=6, gravity=True):
    """An n x n cloth of stretch constraints pinned at two corners (returns the world)."""
    w = world_type()
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    for j in range(n):
        for i in range(n):
            pinned = j == n - 1 and i in (0, n - 1)
            w.add_particle((i / (n - 1), j / (n - 1), 1.0), pbd.PINNED if pinned else 1.0)
    for a in range(n * n):
        if a % n < n - 1:
            w.add_stretch(a, a + 1, s)
        if a < n * (n - 1):
            w.add_stretch(a, a + n, s)
    if not gravity:
        p = w.params
        p.gravity = (0.0, 0.0, 0.0)
        w.params = p
    return w


@pytest.fixture(params=[pbd.World, pbd.WorldDouble], ids=["float", "double"])
def world_type(request):
    return request.param
