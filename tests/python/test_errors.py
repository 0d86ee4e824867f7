"""Every error path raises: pbd.Error (a RuntimeError) with the library's message, ValueError for bad arrays."""
import json

import numpy as np
import pytest

import pbd
from conftest import SCENES, cloth


def test_error_is_a_runtime_error():
    assert issubclass(pbd.Error, RuntimeError)


def test_bad_particle_index(world_type):
    w = cloth(world_type, n=3)
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    with pytest.raises(pbd.Error, match=r"add_stretch: stretch constraint \d+: particle index 9 out of range \(the world has 9 particles\)"):
        w.add_stretch(0, 9, s)
    with pytest.raises(pbd.Error, match="add_anchor: .*particle index 100"):
        w.add_anchor(100, s)
    with pytest.raises(ValueError, match="add_stretch: a must be a particle index >= 0, got -1"):
        w.add_stretch(-1, 0, s)


def test_bad_set(world_type):
    w = cloth(world_type, n=3)
    with pytest.raises(pbd.Error, match=r"add_stretch: stretch constraint \d+: .*set 7"):
        w.add_stretch(0, 1, 7)


@pytest.mark.parametrize("stiffness, message", [
    (pbd.Stiffness.pbd_k(1.5), "add_constraint_set: set 0"),
    (pbd.Stiffness.iteration_independent(-0.1), "add_constraint_set: set 0"),
    (pbd.Stiffness.xpbd_compliance(-1.0), "add_constraint_set: set 0"),
    (pbd.Stiffness.xpbd_compliance(float("nan")), "add_constraint_set: set 0"),
])
def test_bad_stiffness(world_type, stiffness, message):
    with pytest.raises(pbd.Error, match=message):
        world_type().add_constraint_set(stiffness)


@pytest.mark.parametrize("field, value, message", [
    ("dt", 0.0, "set_params: dt must be finite and > 0, got 0"),
    ("dt", -1.0, "set_params: dt must be finite and > 0, got -1"),
    ("substeps", 0, "set_params: substeps must be >= 1, got 0"),
    ("iterations", -1, "set_params: iterations must be >= 0, got -1"),
    ("damping", -1.0, "set_params: damping must be finite and >= 0"),
    ("collision_margin", float("inf"), "set_params: collision_margin must be finite and >= 0"),
    ("jacobi_omega", 2.0, r"set_params: jacobi_omega must be in \(0, 2\)"),
    ("gravity", (0.0, float("nan"), 0.0), "set_params: gravity is not finite"),
])
def test_bad_params(world_type, field, value, message):
    w = world_type()
    before = w.params
    p = w.params
    setattr(p, field, value)
    with pytest.raises(pbd.Error, match=message):
        w.params = p
    assert w.params.dt == before.dt and w.params.substeps == before.substeps  # unchanged


def test_bad_mass_and_colliders(world_type):
    w = world_type()
    with pytest.raises(pbd.Error, match="add_particle"):
        w.add_particle((0, 0, 0), -1.0)
    with pytest.raises(pbd.Error, match="add_sphere"):
        w.add_sphere((0, 0, 0), 0.0)
    with pytest.raises(pbd.Error, match="restitution must be in"):
        w.add_plane((0, 0, 1), 0.0, pbd.ContactMaterial(restitution=2.0))
    w.add_particle((0, 0, 0), 1.0)
    with pytest.raises(pbd.Error, match=r"add_contact_body: body 0: particles \[0, 5\) are not a non-empty range of the 1 particles"):
        w.add_contact_body(0, 5, 0.1)


def test_contact_and_collider_lengths_are_bounded(world_type):
    # issue 48: a radius of 1e30 used to give NaN positions with no exception; a sphere of 3e38 to overflow.
    w = cloth(world_type, n=6)
    with pytest.raises(pbd.Error, match=r"add_contact_body: body 0: radius must be finite and >= 0 and at most 1000000 m"):
        w.add_contact_body(0, 36, 1e30)
    with pytest.raises(pbd.Error, match=r"add_contact_body: body 0: .*cover"):
        w.add_contact_body(0, 36, 1e5)  # 36 particles 0.2 m apart, each touching every other
    assert w.add_contact_body(0, 36, 0.05) == 0  # the refused calls added nothing
    p = w.params
    p.collision_margin = 1e5
    with pytest.raises(pbd.Error, match=r"set_params: contact body 0: .*cover"):
        w.params = p
    with pytest.raises(pbd.Error, match="add_sphere: sphere 0: radius must be finite and > 0 and at most"):
        w.add_sphere((0, 0, 0), 1e200 if world_type is pbd.WorldDouble else 3e38)
    with pytest.raises(pbd.Error, match="add_plane: plane 0: offset must be at most"):
        w.add_plane((0, 0, 1), -1e200 if world_type is pbd.WorldDouble else -3e38)
    w.step()
    assert np.isfinite(w.positions).all()


def test_bad_volume_mesh(world_type):
    w = cloth(world_type, n=3)
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    with pytest.raises(pbd.Error, match="add_volume"):
        w.add_volume([[0, 1, 3]], s)  # a single triangle is not closed
    with pytest.raises(ValueError, match=r"add_volume: triangles must have shape \(M, 3\), got \(4,\)"):
        w.add_volume([0, 1, 3, 4], s)
    with pytest.raises(ValueError, match="add_volume: triangles must be an array of integers, got dtype float64"):
        w.add_volume(np.zeros((2, 3)), s)


def test_wrong_array_shapes_and_dtypes(world_type):
    w = cloth(world_type, n=3)
    with pytest.raises(ValueError, match=r"add_particles: positions must have shape \(N, 3\), got \(4, 2\)"):
        w.add_particles(np.zeros((4, 2)), np.ones(4))
    with pytest.raises(ValueError, match=r"add_particles: masses must have shape \(4,\), got \(3,\)"):
        w.add_particles(np.zeros((4, 3)), np.ones(3))
    with pytest.raises(ValueError, match="add_particles: positions must be an array of real numbers, got dtype <U1"):
        w.add_particles(np.array([["a", "b", "c"]]), np.ones(1))
    with pytest.raises(ValueError, match=r"add_particle: position must have shape \(3,\), got \(2,\)"):
        w.add_particle((0.0, 1.0), 1.0)
    with pytest.raises(ValueError, match=r"step: forces must have shape \(9, 3\), got \(8, 3\)"):
        w.step(np.zeros((8, 3)))
    with pytest.raises(ValueError, match=r"step: forces must have shape \(9, 3\), got \(27,\)"):
        w.step(np.zeros(27))
    assert w.time == 0.0  # nothing stepped


def test_non_finite_force(world_type):
    w = cloth(world_type, n=3)
    f = np.zeros((9, 3))
    f[4, 1] = np.inf
    with pytest.raises(pbd.Error, match="step: force on particle 4 is not finite"):
        w.step(f)


def test_bad_scene_json_names_the_key():
    good = json.loads((SCENES / "rope.json").read_text())
    pbd.parse_scene(json.dumps(good), "rope.json")
    for change, message in [
        (lambda d: d.update(dt=-1), r"bad.json: /dt: value -1 is out of range"),
        (lambda d: d.update(nonsense=1), r"bad.json: /nonsense"),
        (lambda d: d["bodies"][0]["stretch"].update(stiffness=2.0), r"bad.json: /bodies/0/stretch/stiffness"),
        (lambda d: d.pop("dt"), r"bad.json: /dt: required key is missing"),
    ]:
        scene = json.loads(json.dumps(good))
        change(scene)
        with pytest.raises(pbd.Error, match=message):
            pbd.parse_scene(json.dumps(scene), "bad.json")
    with pytest.raises(pbd.Error, match="bad.json.*line 1"):
        pbd.parse_scene('{"name": ', "bad.json")
    with pytest.raises(pbd.Error, match="no-such-scene.json"):
        pbd.load_scene(SCENES / "no-such-scene.json")
