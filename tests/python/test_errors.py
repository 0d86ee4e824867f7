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
    ("substeps", 0, r"set_params: substeps must be in \[1, 100000\], got 0"),
    ("substeps", 100001, r"set_params: substeps must be in \[1, 100000\], got 100001"),
    ("iterations", -1, r"set_params: iterations must be in \[0, 100000\], got -1"),
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


def test_sweeps_per_step_are_bounded(world_type):
    # 100,000 sub-steps of 100,000 sweeps (10^10 a step) used to be accepted, and a step never ended.
    w = world_type()
    p = w.params
    p.substeps, p.iterations = 100000, 100000
    with pytest.raises(pbd.Error, match=r"substeps × iterations is 10000000000 sweeps a step, more than the limit of 1000000"):
        w.params = p
    assert w.params.substeps == 1
    p.substeps, p.iterations = 1000, 1000
    w.params = p
    assert w.params.substeps == 1000


def test_a_mass_the_world_cannot_hold_is_an_error_not_a_pinned_particle():
    # 1e39 becomes infinity in float, the mass of a pinned particle; 1e38's inverse is subnormal in float.
    w = pbd.World()
    w.add_particle((0, 0, 0), 1.0)
    for mass in (1e39, 1e38):
        with pytest.raises(pbd.Error, match=r"add_particle: particle 1: mass .* kg is (beyond the range of|out of range for) float"):
            w.add_particle((0, 0, 0), mass)
        with pytest.raises(pbd.Error, match="set_mass: particle 0: mass"):
            w.set_mass(0, mass)
        with pytest.raises(pbd.Error, match="add_particles: particle 2: mass"):
            w.add_particles(np.zeros((2, 3)), np.array([1.0, mass]))
    assert w.num_particles == 1 and w.inverse_masses()[0] == 1.0
    w.add_particle((0, 0, 0), w.kPinned)  # infinity still pins
    assert w.inverse_masses()[1] == 0.0
    d = pbd.WorldDouble()
    d.add_particle((0, 0, 0), 1e39)  # double holds it
    assert d.inverse_masses()[0] > 0.0
    with pytest.raises(pbd.Error, match=r"particle 0: mass .*e\+38 kg is out of range for float"):
        pbd.World().add_cloth(resolution=2, mass=1e39)


def test_messages_quoting_bytes_that_are_not_utf8_keep_their_words(tmp_path):
    # Smart quotes typed in cp1252 (0x93, 0x94): pbd.Error used to have an empty message (Python could not decode it).
    text = '{"name": \x93t\x94, "dt": 0.01, "bodies": []}'.encode("latin-1")
    path = tmp_path / "smart.json"
    path.write_bytes(text)
    for call in (lambda: pbd.load_scene(str(path)), lambda: pbd.parse_scene(text, "smart.json")):
        with pytest.raises(pbd.Error) as e:
            call()
        assert "smart.json: parse error at line 1, column" in str(e.value)
        assert "\\x93" in str(e.value)


def test_scene_strings_refuse_control_and_bidi_characters():
    scene = {"name": "x\u202egpj", "dt": 0.01, "bodies": []}
    with pytest.raises(pbd.Error, match=r"/name: .*U\+202E .*control or format character"):
        pbd.parse_scene(json.dumps(scene), "s.json")


def test_load_scene_refuses_a_primary_error_the_scene_cannot_measure(tmp_path):
    scene = {"name": "s", "dt": 0.01, "primary_error": "bending",
             "bodies": [{"type": "rope", "particles": 3, "stretch": {}}]}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(scene))
    with pytest.raises(pbd.Error, match="/primary_error: the scene has no bending constraint to measure"):
        pbd.load_scene(str(path))
    scene["primary_error"] = "stretch"
    path.write_text(json.dumps(scene))
    assert pbd.load_scene(str(path)).primary_error == "stretch"


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
    assert np.isfinite(w.positions()).all()


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
