"""A non-finite value written through positions()/velocities(): what step() does with it today.

step() checks forces (step(forces), the force callback) but not the state: it raises nothing and steps on. The
poisoned particle stays non-finite (its position and velocity). A NaN stays on its particle: the constraints on it
skip their projection (a NaN gradient fails the length test). An infinity can spread to a neighbour through a
constraint (inf - inf = NaN there; seen: one neighbour of the cloth). stretch_violation() becomes NaN. The policy is the
lead's to decide on main; these tests pin the behaviour so that a change of it is seen.
"""
import numpy as np
import pytest

import pbd
from conftest import SCENES, cloth

SOLVERS = [pbd.Solver.serial, pbd.Solver.colored, pbd.Solver.jacobi, pbd.Solver.block]


def finite_rows(a):
    return np.isfinite(a).all(axis=1)


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda s: s.name)
@pytest.mark.parametrize("view", ["positions", "velocities"])
@pytest.mark.parametrize("value", [np.nan, np.inf], ids=["nan", "inf"])
def test_non_finite_state_is_stepped_without_error(world_type, solver, view, value):
    w = cloth(world_type, n=6)
    p = w.params
    p.solver = solver
    w.params = p
    getattr(w, view)()[14, 2] = value
    for _ in range(3):
        w.step()  # no pbd.Error
    assert w.time == pytest.approx(3 * p.dt)
    x, v = w.positions(), w.velocities()
    assert not finite_rows(x)[14] and not finite_rows(v)[14]
    others = np.arange(w.num_particles) != 14
    if np.isnan(value):  # a NaN stays on its particle
        assert finite_rows(x)[others].all() and finite_rows(v)[others].all()
    else:  # an infinity may spread through a constraint, not past the pins
        assert finite_rows(x)[[30, 35]].all()
    assert np.isnan(pbd.stretch_violation(w).rms)
    w.validate()


@pytest.mark.parametrize("scene", ["balls.json", "cloth-fold.json", "inflate.json"])
def test_non_finite_position_with_contacts_and_volumes(world_type, scene):
    build = pbd.build_world if world_type is pbd.World else pbd.build_world_double
    w = build(pbd.load_scene(SCENES / scene))
    x = w.positions()
    x[3, 0] = np.nan
    for _ in range(5):
        w.step()
    assert np.flatnonzero(~finite_rows(x)).tolist() == [3]
