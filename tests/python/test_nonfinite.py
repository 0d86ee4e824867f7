"""A non-finite value written through positions()/velocities() between steps: the next step() raises pbd.Error
naming the particle and leaves the world as it was (the engine checks the state after a mutable map was handed out;
Python's step() hands one out while any view is alive). Repairing the value lets the world step on."""
import numpy as np
import pytest

import pbd
from conftest import SCENES, cloth

SOLVERS = [pbd.Solver.serial, pbd.Solver.colored, pbd.Solver.jacobi, pbd.Solver.block]


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda s: s.name)
@pytest.mark.parametrize("view", ["positions", "velocities"])
@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf], ids=["nan", "inf", "-inf"])
def test_a_non_finite_write_stops_the_next_step(world_type, solver, view, value):
    w = cloth(world_type, n=6)
    p = w.params
    p.solver = solver
    w.params = p
    a = getattr(w, view)()
    w.step()  # the view is kept across steps, as a plotting loop keeps it
    before_x, before_v, before_t = w.positions().copy(), w.velocities().copy(), w.time
    kept = a[14, 2]
    a[14, 2] = value
    what = "position" if view == "positions" else "velocity"
    with pytest.raises(pbd.Error, match=f"step: particle 14 has a non-finite {what}"):
        w.step()
    assert w.time == before_t
    a[14, 2] = kept
    np.testing.assert_array_equal(w.positions(), before_x)
    np.testing.assert_array_equal(w.velocities(), before_v)
    w.step()  # repaired: steps on
    assert np.isfinite(w.positions()).all()


@pytest.mark.parametrize("scene", ["balls.json", "cloth-fold.json", "inflate.json"])
def test_scenes_with_contacts_and_volumes_refuse_it_too(world_type, scene):
    build = pbd.build_world if world_type is pbd.World else pbd.build_world_double
    w = build(pbd.load_scene(SCENES / scene))
    w.step()
    x = w.positions()
    x[3, 0] = np.nan
    with pytest.raises(pbd.Error, match="particle 3 has a non-finite position"):
        w.step()
