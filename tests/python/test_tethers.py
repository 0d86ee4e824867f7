"""Long-range attachments from Python: World.add_tethers (pbd/tethers.hpp) and the generated add_tether."""
import numpy as np
import pytest

import pbd


def pendulum(world_type, compliance=0.0):
    w = world_type()
    w.add_particle((0, 0, 1), float("inf"))   # the pin
    w.add_particle((0, 0, 0.5), 1.0)          # a 1 kg bob 0.5 m below it
    assert w.add_tethers([0, 1], compliance=compliance) == 1
    return w


@pytest.mark.parametrize("world_type", [pbd.World, pbd.WorldDouble])
def test_a_tether_holds_a_pendulum_at_its_length_and_an_xpbd_one_at_l_plus_alpha_m_g(world_type):
    for compliance, stretched in ((0.0, 0.0), (1e-3, 1e-3 * 9.81)):
        w = pendulum(world_type, compliance)
        for _ in range(600):
            w.step()
        assert w.positions()[1, 2] == pytest.approx(0.5 - stretched, abs=1e-5)
        assert pbd.tether_violation(w).max == pytest.approx(stretched, abs=1e-5)


def test_a_tether_never_pushes_and_follows_a_moved_pin():
    w = pendulum(pbd.WorldDouble)
    x = w.positions()
    x[1] = (0.1, 0.0, 0.9)          # inside its length: moved by gravity alone
    free = pbd.WorldDouble()
    free.add_particle((0, 0, 1), float("inf"))
    free.add_particle((0.1, 0.0, 0.9), 1.0)
    w.step()
    free.step()
    assert np.array_equal(w.positions(), free.positions())
    x[0] = (0.0, 0.0, 3.0)          # the host lifts the pin: the bob is dragged to within 0.5 m of it
    w.step()
    assert np.linalg.norm(w.positions()[1] - w.positions()[0]) == pytest.approx(0.5, abs=1e-12)
    del x


def test_options_and_their_errors():
    w = pbd.WorldDouble()
    for x in ((0, 0, 0), (1, 0, 0), (2, 0, 0)):
        w.add_particle(x, 1.0)
    assert w.add_tethers([0, 1, 2]) == 0       # no pinned or anchored particle: nothing to hang from
    w.set_mass(0, float("inf"))
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    w.add_stretch(0, 1, s)
    w.add_stretch(1, 2, s)
    assert w.add_tethers(np.arange(3), to="all", length="geodesic") == 2
    assert w.add_tether(2, s, target=(0, 0, 0), length=2.5) == 2   # the per-constraint call of the type
    with pytest.raises(ValueError, match='to must be "nearest" or "all"'):
        w.add_tethers([0, 1], to="far")
    with pytest.raises(ValueError, match='length must be "euclidean" or "geodesic"'):
        w.add_tethers([0, 1], length="straight")
    with pytest.raises(pbd.Error, match="add_tethers: particle 1 is listed twice"):
        w.add_tethers([0, 1, 1])
    with pytest.raises(pbd.Error, match="add_tethers: compliance must be finite and >= 0"):
        w.add_tethers([0, 1], compliance=-1.0)
    assert w.num_constraints() == 5


def test_a_scene_s_tethers_key():
    scene = pbd.parse_scene('{"name": "c", "dt": 0.01, "bodies": [{"type": "cloth", "resolution": 5, '
                            '"stretch": {"stiffness": 1.0}, "tethers": {"to": "all"}}]}')
    w = pbd.build_world(scene)
    assert pbd.tether_violation(w).count == 2 * 23
