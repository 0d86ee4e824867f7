"""The module's version, the readable reprs, every StepParams field (Chebyshev included), the block solver's
partition, the thread count, and per-constraint violations as arrays."""
import math
import pathlib
import re

import numpy as np
import pytest

import pbd
from conftest import SCENES, cloth

ROOT = pathlib.Path(__file__).resolve().parents[2]


def scene_world(world_type=pbd.World, name="cloth"):
    scene = pbd.load_scene(SCENES / f"{name}.json")
    return pbd.build_world(scene) if world_type is pbd.World else pbd.build_world_double(scene)


def test_version_is_the_projects():
    version = re.search(r"project\(pbd VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)
    assert pbd.__version__ == version


def test_step_params_repr_shows_every_field_with_its_value():
    p = pbd.StepParams()
    p.solver = pbd.Solver.jacobi
    text = repr(p)
    assert text.startswith("pbd.StepParams(dt=0.016666666666666666, substeps=1, iterations=10, ")
    assert "solver=pbd.Solver.jacobi" in text and "sweep_order=pbd.SweepOrder.forward" in text
    assert "chebyshev=pbd.Chebyshev(enabled=False, rho=0.0, delay=4, max_rho=0.999, diverge=2.0)" in text
    assert "hierarchy=pbd.Hierarchy(enabled=False, levels=4, " in text
    for field in [n for n in dir(p) if not n.startswith("_")]:
        assert f"{field}=" in text


def test_step_stats_repr_shows_every_field():
    w = cloth()
    w.set_measure_violation(True)
    w.step()
    stats = w.last_step_stats()
    text = repr(stats)
    assert text.startswith("pbd.StepStats(seconds=") and "substeps=1, sweeps=10" in text
    assert "violation=[pbd.NamedViolation(type='stretch', value=pbd.Violation(rms=" in text
    for field in [n for n in dir(stats) if not n.startswith("_")]:
        assert f"{field}=" in text


@pytest.mark.parametrize("obj, text", [
    (pbd.ContactMaterial(0.5, 0.25, 0.0), "pbd.ContactMaterial(static_friction=0.5, kinetic_friction=0.25, restitution=0.0)"),
    (pbd.PressureSchedule(1.0, 2.0, 0.5), "pbd.PressureSchedule(from_=1.0, to=2.0, duration=0.5)"),
    (pbd.BlockOptions(), "pbd.BlockOptions(constraints_per_block=1024, use_metis=True)"),
    (pbd.Stiffness.xpbd_compliance(1e-6), "pbd.Stiffness.xpbd_compliance(1e-06)"),
    (pbd.Material(20.0), "pbd.Material(stiffness=20.0, toe_strain=0.0, yield_strain=inf, hardening=0.0, rupture_strain=inf)"),
])
def test_parameter_reprs(obj, text):
    assert repr(obj) == text


def test_energy_repr():
    assert re.fullmatch(r"pbd\.Energy\(kinetic=0\.0, potential=-?[0-9.e+-]+\)", repr(pbd.energy(cloth())))


def test_chebyshev_settings_reach_the_world_and_its_steps(world_type):
    w = cloth(world_type)
    p = w.params
    p.solver = pbd.Solver.jacobi
    p.chebyshev.enabled = True
    p.chebyshev.rho = 0.5
    p.chebyshev.delay = 2
    w.params = p
    assert (w.params.chebyshev.enabled, w.params.chebyshev.rho, w.params.chebyshev.delay) == (True, 0.5, 2)
    w.step()
    assert w.last_step_stats().chebyshev_rho == 0.5
    p.chebyshev.max_rho = 1.5
    with pytest.raises(pbd.Error):
        w.params = p


def test_block_options_set_the_block_solvers_partition(world_type):
    w = cloth(world_type, n=12)
    p = w.params
    p.solver = pbd.Solver.block
    w.params = p
    w.blocking = pbd.BlockOptions(constraints_per_block=16, use_metis=False)
    assert (w.blocking.constraints_per_block, w.blocking.use_metis) == (16, False)
    w.step()
    fine = w.last_step_stats().colors
    w.blocking = pbd.BlockOptions(constraints_per_block=100000)
    w.step()
    assert w.last_step_stats().colors < fine  # one block: fewer groups
    with pytest.raises(pbd.Error):
        w.blocking = pbd.BlockOptions(constraints_per_block=0)


def test_one_and_two_threads_give_the_same_bits(world_type):
    hashes = []
    for threads in (1, 2):
        w = scene_world(world_type)
        w.threads = threads
        assert w.threads == threads
        for _ in range(20):
            w.step()
        assert 1 <= w.last_step_stats().solve_threads <= threads
        hashes.append(pbd.position_hash(w))
    assert hashes[0] == hashes[1]
    with pytest.raises(ValueError, match="threads must be >= 0"):
        w.threads = -1


def test_violations_give_one_value_per_constraint(world_type):
    w = scene_world(world_type)
    for _ in range(3):
        w.step()
    v = w.violations("stretch")
    assert v.dtype == np.float64 and v.shape == (pbd.stretch_violation(w).count,)
    assert v.max() == pbd.stretch_violation(w).max
    assert math.isclose(np.sqrt(np.mean(v ** 2)), pbd.stretch_violation(w).rms, rel_tol=1e-12)
    assert w.violations("anchor").shape == (0,)
    with pytest.raises(ValueError, match='no built-in constraint type "bogus"; the types are stretch, anchor'):
        w.violations("bogus")
