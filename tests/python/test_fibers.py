"""Fibers with a stress-strain curve from Python: pbd.Material, Stiffness.fiber, World.add_fiber, World.fibers (the
strains and the force from lambda as numpy arrays) and World.last_breaks."""
import math

import numpy as np
import pytest

import pbd

LIGAMENT = dict(stiffness=1000.0, toe_strain=0.03, yield_strain=0.08, hardening=200.0, rupture_strain=0.14)


def tension(world_type):
    """Two fibers of 1 cm between a fixed grip (particle 0) and a moving one (particle 2), a 1 g particle between."""
    w = world_type()
    w.add_particle((0, 0, 0), math.inf)
    w.add_particle((0.01, 0, 0), 1e-3)
    w.add_particle((0.02, 0, 0), math.inf)
    s = w.add_constraint_set(pbd.Stiffness.fiber(pbd.Material(**LIGAMENT)))
    w.add_fiber(0, 1, s)
    w.add_fiber(1, 2, s)
    p = w.params
    p.dt, p.substeps, p.iterations, p.gravity = 1e-3, 10, 10, (0, 0, 0)
    w.params = p
    return w


@pytest.mark.parametrize("world_type", [pbd.World, pbd.WorldDouble])
def test_a_pulled_fiber_reads_the_curve_yields_and_breaks_at_its_rupture_strain(world_type):
    m = pbd.Material(**LIGAMENT)
    w = tension(world_type)
    assert np.isnan(w.fibers()["force"]).all()  # no step yet: lambda says nothing
    broke = None
    for step in range(1, 2000):
        w.positions()[2, 0] = 0.02 * (1 + 1e-4 * step)
        w.step()
        if w.last_breaks():
            broke = w.last_breaks()
            break
        f = w.fibers()
        assert f["strain"].shape == (2,) and f["force"].dtype == np.float64
        if step in (200, 600, 1000):  # toe, linear part, past yield
            s = 1e-4 * step
            assert f["force"][1] == pytest.approx(m.loading_force(s), rel=0.02)
        if step == 1000:
            assert f["plastic"][0] == pytest.approx(1000 * 0.02 / 1200, rel=0.02)
    assert broke is not None and len(broke) >= 1
    assert broke[0].strain == pytest.approx(0.14, rel=0.01)
    assert broke[0].force == pytest.approx(m.loading_force(broke[0].strain), rel=0.02)
    assert "FiberBreak(step=" in repr(broke[0])
    assert len(w.fibers()["strain"]) == 2 - len(broke)


def test_a_bad_curve_and_a_stretch_in_a_curved_set_are_refused_by_name():
    w = pbd.World()
    with pytest.raises(pbd.Error, match="yield_strain must be at least toe_strain"):
        w.add_constraint_set(pbd.Stiffness.fiber(pbd.Material(1000, toe_strain=0.1, yield_strain=0.05)))
    s = w.add_constraint_set(pbd.Stiffness.fiber(pbd.Material(1000)))
    w.add_particle((0, 0, 0), 1.0)
    w.add_particle((1, 0, 0), 1.0)
    with pytest.raises(pbd.Error, match="add_stretch: stretch constraint 0: set 0 has a stress-strain curve"):
        w.add_stretch(0, 1, s)


def test_a_cloth_of_fibers_tears_and_its_surface_shows_the_copies():
    """A 6 x 6 cloth of fibers with its triangles as a surface, its two top corners pulled apart (pinned particles
    move at their velocity): it tears, the surface's triangles name the copies, and the copies sit where the
    particles they copy were."""
    n, d = 6, 0.01
    w = pbd.WorldDouble()
    for j in range(n):
        for i in range(n):
            w.add_particle((d * i, d * j, 0), math.inf if j == n - 1 else 1e-3)
    s = w.add_constraint_set(pbd.Stiffness.fiber(pbd.Material(20.0, rupture_strain=0.1)))
    tris = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            tris += [(a, a + 1, a + n + 1), (a, a + n + 1, a + n)]
    for a, b, c in tris:
        for e in ((a, b), (b, c), (a, c)):
            if e[0] < e[1] and (e[1] - e[0] in (1, n, n + 1)):
                w.add_fiber(e[0], e[1], s)
    assert w.add_surface(tris) == 0
    v = w.velocities()
    for i in range(n):
        v[(n - 1) * n + i] = (-0.2 if i < n // 2 else 0.2, 0, 0)   # the top row's halves move apart
    p = w.params
    p.dt, p.substeps, p.iterations, p.gravity = 1e-3, 10, 4, (0, -9.81, 0)
    w.params = p
    copies = []
    for _ in range(200):
        w.step()
        copies += w.last_copies()
    assert copies and w.num_particles == n * n + len(copies)
    named = {q for t in w.surface(0) for q in t}
    assert any(c in named for c, _ in copies)
    w.validate()
