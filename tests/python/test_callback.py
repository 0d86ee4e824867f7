"""The force callback: called at every sub-step with the time and the positions, its forces applied as step(forces)
applies them; an exception it raises reaches the caller as itself and leaves the world as it was."""
import threading

import numpy as np
import pytest

import pbd
from conftest import cloth


def test_callback_forces_act_as_step_forces(world_type):
    a, b = cloth(world_type), cloth(world_type)
    f = np.zeros((a.num_particles, 3))
    f[:, 0] = 2.0
    a.set_force_callback(lambda t, x: f)
    for _ in range(5):
        a.step()
        b.step(f)
    assert pbd.position_hash(a) == pbd.position_hash(b)
    a.set_force_callback(None)
    a.step()
    b.step()
    assert pbd.position_hash(a) == pbd.position_hash(b)


def test_callback_sees_each_substeps_time_and_a_read_only_copy_of_the_positions(world_type):
    w = cloth(world_type)
    p = w.params
    p.substeps = 3
    w.params = p
    seen = []
    n = w.num_particles

    def record(t, x):
        assert x.shape == (n, 3) and not x.flags.writeable
        seen.append((t, x.copy()))

    w.set_force_callback(record)
    start = w.positions().copy()
    w.step()
    assert len(seen) == 3
    assert np.array_equal(seen[0][1], start)
    h = p.dt / 3
    assert [t for t, _ in seen] == pytest.approx([h, 2 * h, 3 * h])  # the time each sub-step ends at


def test_worlds_with_callbacks_step_concurrently_from_two_threads():
    # step() runs without the GIL and takes it only for the callback: two threads stepping two such worlds neither
    # deadlock nor change each other's results.
    def world():
        w = cloth(n=20)
        w.set_force_callback(lambda t, x: np.where(x[:, 2:3] > 0.5, 1.0, 0.0) * np.array([0.0, 1.0, 0.0]))
        return w

    sequential = world()
    for _ in range(30):
        sequential.step()
    worlds = [world(), world()]
    threads = [threading.Thread(target=lambda w=w: [w.step() for _ in range(30)]) for w in worlds]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [pbd.position_hash(w) for w in worlds] == [pbd.position_hash(sequential)] * 2


class Boom(Exception):
    pass


@pytest.mark.parametrize("substeps, threads", [(1, 0), (3, 0), (3, 2)])
def test_an_exception_in_the_callback_propagates_as_itself_and_leaves_the_world_as_it_was(world_type, substeps, threads):
    w = cloth(world_type)
    w.threads = threads  # through the world's own task_arena too
    p = w.params
    p.substeps = substeps
    w.params = p
    w.step()
    before = (pbd.position_hash(w), w.time, w.velocities().copy())
    raised = Boom("no force today")
    calls = []
    n = w.num_particles

    def fail_at_the_last_substep(t, x):
        calls.append(t)
        if len(calls) == substeps:
            raise raised
        return np.ones((n, 3))

    w.set_force_callback(fail_at_the_last_substep)
    with pytest.raises(Boom) as caught:
        w.step()
    assert caught.value is raised
    assert (pbd.position_hash(w), w.time) == before[:2]
    assert np.array_equal(w.velocities(), before[2])
    w.validate()
    w.set_force_callback(None)
    w.step()  # steps on


def test_a_callback_cannot_call_its_world(world_type):
    w = cloth(world_type)
    w.set_force_callback(lambda t, x: w.add_particle((0, 0, 0), 1.0))
    with pytest.raises(pbd.Error, match=r"add_particle: the world is stepping \(in another thread, or this is its force"):
        w.step()
    w.set_force_callback(None)  # the callback refers to w: clear it to break the cycle


def test_a_callback_returning_the_wrong_shape_is_a_value_error_naming_it(world_type):
    w = cloth(world_type)
    h = pbd.position_hash(w)
    w.set_force_callback(lambda t, x: np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"force callback: the forces it returned must have shape \(36, 3\)"):
        w.step()
    assert pbd.position_hash(w) == h and w.time == 0.0
    with pytest.raises(TypeError, match="callable"):
        w.set_force_callback(3)
