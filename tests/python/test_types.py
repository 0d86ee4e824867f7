"""The constraint calls generated from the list of built-in types (constraint_types.hpp): add_<name> with its
particles, set and rest values (measured when None), <name>_violation, and each NamedViolation's measure and unit."""
import math

import pytest

import pbd

# name -> (particle argument names, rest value names, the study's measure and unit), as the types' headers declare.
TYPES = {"stretch": (["a", "b"], ["rest"], "stretch_pct", "%"),
         "anchor": (["particle"], ["target"], "anchor_mm", "mm"),
         "bending": (["p1", "p2", "p3", "p4"], ["rest"], "bending_rad", "rad"),
         "area": (["a", "b", "c"], ["rest"], "area_pct", "%"),
         "tether": (["particle"], ["target", "length"], "tether_mm", "mm")}


def four_particles(world_type):
    w = world_type()
    for x in ((0, 0, 0), (1, 0, 0), (0.2, 1, 0.1), (0.3, -1, 0.4)):
        w.add_particle(x, 1.0)
    return w, w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))


@pytest.mark.parametrize("world_type", [pbd.World, pbd.WorldDouble])
@pytest.mark.parametrize("name", sorted(TYPES))
def test_each_type_has_its_calls_and_its_measure(world_type, name):
    particles, rest, measure, unit = TYPES[name]
    w, s = four_particles(world_type)
    add = getattr(w, f"add_{name}")
    assert add(*range(len(particles)), s) == 0                           # rest values measured
    assert add(**{p: i for i, p in enumerate(particles)}, set=s) == 1   # by keyword
    assert all(f"{a}" in add.__doc__ for a in particles + rest)
    v = getattr(pbd, f"{name}_violation")(w)
    assert v.count == 2 and v.max < 1e-6
    (named,) = pbd.constraint_violations(w)
    assert (named.type, named.measure, named.unit) == (name, measure, unit)
    assert named.scale > 0
    with pytest.raises(pbd.Error, match=rf"add_{name}: .* 2: particle index 9 out of range"):
        add(*([9] + list(range(1, len(particles)))), s)


def test_a_given_rest_value_is_kept_and_checked():
    w, s = four_particles(pbd.WorldDouble)
    w.add_stretch(0, 1, s, rest=0.5)
    assert math.isclose(pbd.stretch_violation(w).max, 1.0)  # |1 - 0.5| / 0.5
    with pytest.raises(pbd.Error, match="add_stretch: stretch constraint 1: rest distance must be finite and >= 0"):
        w.add_stretch(0, 1, s, rest=-1.0)
    w.add_anchor(2, s, target=(0.2, 1, 1.1))
    assert math.isclose(pbd.anchor_violation(w).max, 1.0)  # 1 m from its target
    with pytest.raises(pbd.Error, match="add_anchor: anchor 1: target is not finite"):
        w.add_anchor(2, s, target=(math.nan, 0, 0))


def test_shape_match_takes_eight_particles_and_reports_mm():
    """add_shape_match: eight particles, rest offsets q0..q7 measured, beta given or 0; its violation in mm."""
    w = pbd.WorldDouble()
    for x in ((0, 0, 0), (1, 0, 0), (0.2, 1, 0.1), (0.3, -1, 0.4), (-0.6, 0.4, 0.9), (0.8, 0.7, -0.5),
              (-0.3, -0.8, -0.7), (1.1, -0.4, 1.2)):
        w.add_particle(x, 1.0)
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    assert w.add_shape_match(*range(8), s) == 0
    assert w.add_shape_match(*range(8), s, beta=0.5) == 1
    assert all(f"q{i}" in w.add_shape_match.__doc__ for i in range(8)) and "beta" in w.add_shape_match.__doc__
    v = pbd.shape_match_violation(w)
    assert v.count == 2 and v.max < 1e-12
    (named,) = pbd.constraint_violations(w)
    assert (named.type, named.measure, named.unit, named.scale) == ("shape_match", "shape_mm", "mm", 1000.0)
    with pytest.raises(pbd.Error, match=r"add_shape_match: shape-matching cluster 2: beta must be in \[0, 1\], got 2"):
        w.add_shape_match(*range(8), s, beta=2.0)
