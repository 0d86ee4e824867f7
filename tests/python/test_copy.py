"""copy.deepcopy and pickle of a World and a WorldDouble: equal bits after the round trip and after stepping both on."""
import copy
import pickle

import numpy as np
import pytest

import pbd
from conftest import SCENES

# Scenes with most of the model: cloth (stretch, bending, colliders), inflate (volume, pressure schedule), ligament
# (fibers with plastic strain, tethers), jelly (tets).
SCENES_USED = ["cloth", "inflate", "ligament", "jelly"]


def built(world_type, name, steps=3):
    scene = pbd.load_scene(SCENES / f"{name}.json")
    w = pbd.build_world(scene) if world_type is pbd.World else pbd.build_world_double(scene)
    for _ in range(steps):
        w.step()
    return w


def same_bits_on(a, b, steps=5):
    assert (pbd.position_hash(a), a.time, a.num_constraints()) == (pbd.position_hash(b), b.time, b.num_constraints())
    assert np.array_equal(a.velocities(), b.velocities())
    for _ in range(steps):
        a.step()
        b.step()
    assert pbd.position_hash(a) == pbd.position_hash(b)


@pytest.mark.parametrize("name", SCENES_USED)
def test_deepcopy_steps_on_to_the_same_bits(world_type, name):
    w = built(world_type, name)
    c = copy.deepcopy(w)
    assert type(c) is world_type and c is not w
    same_bits_on(w, c)
    c.positions()[:] += 1.0  # independent storage
    assert pbd.position_hash(c) != pbd.position_hash(w)
    assert pbd.position_hash(copy.copy(w)) == pbd.position_hash(w)


@pytest.mark.parametrize("name", SCENES_USED)
def test_pickle_round_trip_steps_on_to_the_same_bits(world_type, name):
    w = built(world_type, name)
    w.threads = 2
    data = pickle.dumps(w)
    back = pickle.loads(data)
    assert type(back) is world_type and back.threads == 2
    assert repr(back.params) == repr(w.params)
    same_bits_on(w, back)


def test_a_world_with_a_force_callback_refuses_pickling_and_copies_share_it(world_type):
    w = built(world_type, "cloth", steps=0)
    calls = []
    w.set_force_callback(lambda t, x: calls.append(t))
    with pytest.raises(pbd.Error, match="force callback"):
        pickle.dumps(w)
    copy.deepcopy(w).step()
    assert len(calls) == w.params.substeps  # the copy called the same callback


def test_unpickling_checks_the_data(world_type):
    w = built(world_type, "rope", steps=1)
    precision, time, threads, data = w.__getstate__()
    other = "float64" if world_type is pbd.World else "float32"
    for state, message in [((precision, time, threads, data[:-3]), "ends too early"),
                           ((precision, time, threads, b"junk" + data), "not the state of a pbd World"),
                           ((other, time, threads, data), "not the state of a")]:
        fresh = world_type.__new__(world_type)
        with pytest.raises(pbd.Error, match=message):
            fresh.__setstate__(state)
