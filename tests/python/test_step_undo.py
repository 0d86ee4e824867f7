"""A step() that fails anywhere leaves the world as it was (docs/robustness.md): a fault injected after each phase of a
sub-step (pbd._inject_fault: the engine's fault points), as pbd.Error or as an allocation failure (MemoryError), under
every solver and on threads of the world's own, on scenes with contacts, volumes and fibers that break. The failed
world pickles to the same bytes as before, has the same positions, velocities and time, and steps on to the same bits
as a copy taken before the failed step; so does one whose force callback raises at a later sub-step."""
import copy
import os
import pickle

import numpy as np
import pytest

import pbd
from conftest import SCENES

SOLVERS = [pbd.Solver.serial, pbd.Solver.serial_colored, pbd.Solver.colored, pbd.Solver.jacobi, pbd.Solver.block]
PHASES = ["predict", "contacts", "solve", "update", "step_end"]


def scene_world(name, solver, world_type=pbd.WorldDouble, threads=0):
    build = pbd.build_world if world_type is pbd.World else pbd.build_world_double
    w = build(pbd.load_scene(SCENES / f"{name}.json"))
    p = w.params
    p.solver = solver
    p.substeps = max(p.substeps, 2)
    w.params = p
    w.threads = threads
    return w


def snapshot(w):
    return pickle.dumps(w), w.positions().copy(), w.velocities().copy(), w.time


def assert_same(w, snap):
    data, x, v, t = snap
    assert pickle.dumps(w) == data
    np.testing.assert_array_equal(w.positions(), x)
    np.testing.assert_array_equal(w.velocities(), v)
    assert w.time == t


@pytest.fixture(autouse=True)
def no_fault_left():
    yield
    pbd._clear_fault()


@pytest.mark.parametrize("solver", SOLVERS, ids=lambda s: s.name)
@pytest.mark.parametrize("scene", ["balls", "cloth-tear", "inflate"])
@pytest.mark.parametrize("kind", ["error", "bad_alloc"])
def test_a_fault_at_any_phase_leaves_the_world_as_it_was(scene, solver, kind):
    for phase in PHASES:
        w = scene_world(scene, solver, threads=2)
        w.step()
        before = snapshot(w)
        clean = copy.deepcopy(w)
        pbd._inject_fault(phase, kind, 1 if phase == "step_end" else 2)
        with pytest.raises(MemoryError if kind == "bad_alloc" else pbd.Error):
            w.step()
        assert pbd._clear_fault(), phase
        assert_same(w, before)
        for _ in range(2):
            w.step()
            clean.step()
        np.testing.assert_array_equal(w.positions(), clean.positions())
        np.testing.assert_array_equal(w.velocities(), clean.velocities())


def test_a_float_world_too(world_type=pbd.World):
    w = scene_world("cloth-fold", pbd.Solver.colored, world_type)
    w.step()
    before = snapshot(w)
    pbd._inject_fault("solve", "bad_alloc", 2)
    with pytest.raises(MemoryError):
        w.step()
    assert_same(w, before)


def test_a_callback_raising_at_a_later_sub_step_leaves_the_world_as_it_was():
    w = scene_world("balls", pbd.Solver.colored)
    w.step()
    before = snapshot(w)
    calls = []

    def push(t, x):
        calls.append(t)
        if len(calls) == 2:
            raise MemoryError("the host ran out")
        return np.zeros_like(x)

    w.set_force_callback(push)
    with pytest.raises(MemoryError, match="the host ran out"):
        w.step()
    w.set_force_callback(None)
    assert_same(w, before)


def test_faults_are_checked_by_name():
    with pytest.raises(ValueError, match="no phase"):
        pbd._inject_fault("nowhere")
    with pytest.raises(ValueError, match="kind"):
        pbd._inject_fault("solve", "segfault")


@pytest.mark.parametrize("kind", ["error", "bad_alloc"])
def test_a_fault_while_writing_a_frame_leaves_the_world_and_the_series_whole(tmp_path, kind):
    scene = pbd.load_scene("rope")
    w = pbd.build_world_double(scene)
    series = pbd.FrameSeries(tmp_path, "rope", "vtu", dt=scene.dt)
    series.write(w, 0, scene=scene)
    w.step()
    before = snapshot(w)
    pbd._inject_fault("frame_write", kind, 1)  # the frame's own file
    with pytest.raises(MemoryError if kind == "bad_alloc" else pbd.Error):
        series.write(w, 1, scene=scene)
    assert pbd._clear_fault()
    assert_same(w, before)
    series.write(w, 2, scene=scene)
    series.finish()
    assert sorted(os.listdir(tmp_path)) == ["rope.pvd", "rope_00000.vtu", "rope_00002.vtu"]
    assert (tmp_path / "rope.pvd").read_text().count("<DataSet ") == 2
