"""Hierarchical PBD from Python: the params attribute round trips, bad settings raise, and a hanging cloth with the
hierarchy on stretches less at the same budget."""
import pytest

import pbd


def hanging_cloth(world_type, n=30):
    w = world_type()
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    for j in range(n):
        for i in range(n):
            pinned = j == n - 1 and i in (0, n - 1)
            w.add_particle((i / (n - 1), j / (n - 1), 1.0), float("inf") if pinned else 1.0 / (n * n))
    for j in range(n):
        for i in range(n):
            p = j * n + i
            if i + 1 < n:
                w.add_stretch(p, p + 1, s)
            if j + 1 < n:
                w.add_stretch(p, p + n, s)
            if i + 1 < n and j + 1 < n:
                w.add_stretch(p, p + n + 1, s)
    return w


def rms_after(w, hierarchy):
    p = w.params
    p.substeps, p.iterations = 4, 1
    p.hierarchy.enabled = hierarchy
    w.params = p
    for _ in range(30):
        w.step()
    return pbd.stretch_violation(w).rms


@pytest.mark.parametrize("world_type", [pbd.World, pbd.WorldDouble])
def test_params_attribute_round_trips_and_checks(world_type):
    w = world_type()
    p = w.params
    assert not p.hierarchy.enabled
    p.hierarchy.enabled = True
    p.hierarchy.levels = 3
    w.params = p
    assert w.params.hierarchy.enabled and w.params.hierarchy.levels == 3
    p.hierarchy.slack = 0.002
    w.params = p
    assert w.params.hierarchy.slack == 0.002
    p.hierarchy.slack = -1.0
    with pytest.raises(pbd.Error, match="hierarchy.slack"):
        w.params = p
    p.hierarchy.slack = 0.001
    p.hierarchy.levels = 0
    with pytest.raises(pbd.Error, match="hierarchy.levels"):
        w.params = p


def test_hierarchy_lowers_the_stretch_of_a_hanging_cloth():
    assert rms_after(hanging_cloth(pbd.World), True) < 0.5 * rms_after(hanging_cloth(pbd.World), False)
