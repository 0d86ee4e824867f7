"""positions() and velocities(): numpy views of the engine's storage, their dtype, sharing, writes and lifetime."""
import gc

import numpy as np
import pytest

import pbd
from conftest import cloth


def test_views_have_shape_dtype_and_share_memory(world_type):
    w = cloth(world_type, n=4)
    x, v = w.positions(), w.velocities()
    dtype = np.float32 if world_type is pbd.World else np.float64
    for a in (x, v):
        assert a.shape == (16, 3)
        assert a.dtype == dtype
        assert a.flags.writeable and a.flags.c_contiguous
    assert np.shares_memory(x, w.positions())
    assert np.shares_memory(v, w.velocities())
    assert not np.shares_memory(x, v)
    assert x.base is not None  # the token that keeps the world alive


def test_write_through_the_view_is_seen_by_the_engine(world_type):
    w = world_type()
    w.add_particle((0.0, 0.0, 0.0), 1.0)
    p = w.params
    p.gravity = (0.0, 0.0, 0.0)
    w.params = p
    x, v = w.positions(), w.velocities()
    x[0] = (1.0, 2.0, 3.0)
    v[0] = (0.0, 0.0, 6.0)  # 0.1 m per step of 1/60 s
    w.step()
    np.testing.assert_allclose(w.positions()[0], (1.0, 2.0, 3.1), rtol=1e-6)
    # The view taken before the step shows the stepped state too, and a write through it reaches the next step.
    np.testing.assert_allclose(x[0], (1.0, 2.0, 3.1), rtol=1e-6)
    x[0, 0] = -5.0
    w.step()
    np.testing.assert_allclose(x[0], (-5.0, 2.0, 3.2), rtol=1e-6)


@pytest.mark.parametrize("substeps", [1, 2, 3])
def test_views_stay_current_across_steps(world_type, substeps):
    w = cloth(world_type, n=5)
    p = w.params
    p.substeps = substeps
    w.params = p
    x = w.positions()
    for _ in range(3):
        w.step()
        assert np.shares_memory(x, w.positions())
        np.testing.assert_array_equal(x, w.positions())


def test_a_view_keeps_the_world_alive(world_type):
    x = cloth(world_type, n=3).positions()  # the world is no longer named
    gc.collect()
    assert x.shape == (9, 3) and np.isfinite(x).all()
    x[:] = 0.0


def test_adding_particles_while_a_view_is_alive_raises(world_type):
    w = cloth(world_type, n=3)
    x, v = w.positions(), w.velocities()
    assert w.num_views() == 2
    with pytest.raises(pbd.Error, match=r"add_particle: 2 numpy view\(s\) of positions\(\)/velocities\(\) are alive"):
        w.add_particle((0, 0, 0), 1.0)
    copy = x.copy()
    del v
    with pytest.raises(pbd.Error, match=r"add_particles: 1 numpy view"):
        w.add_particles(np.zeros((2, 3)), np.ones(2))
    del x
    assert w.num_views() == 0
    assert w.add_particle((0, 0, 0), 1.0) == 9
    assert w.num_particles == 10
    np.testing.assert_array_equal(w.positions()[:9], copy)


def test_views_derived_from_a_view_count_too(world_type):
    w = cloth(world_type, n=3)
    column = w.positions()[:, 2]  # a slice keeps the view (its base) alive
    with pytest.raises(pbd.Error, match="view"):
        w.add_particle((0, 0, 0), 1.0)
    del column
    w.add_particle((0, 0, 0), 1.0)


def test_inverse_masses_is_a_copy(world_type):
    w = cloth(world_type, n=3)
    im = w.inverse_masses()
    assert im.shape == (9,)
    assert im[6] == 0.0 and im[8] == 0.0 and im[0] == 1.0
    assert w.num_views() == 0
