"""Volumetric soft bodies from Python: TetMesh and its sources (tet_box_mesh, load_tet_mesh, tetrahedralize), its
boundary, the Neo-Hookean material and World.add_tet_body, with their errors. tetrahedralize runs the tetgen program
(scripts/deps installs it): without it that test fails, as the C++ ones do."""
import inspect
import math

import numpy as np
import pytest

import pbd


def volumes(positions, tets):
    """Signed volume of each tet, m^3."""
    p = positions[tets.astype(np.int64)]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def surface_volume(positions, triangles):
    """Volume enclosed by a closed surface wound counter-clockwise from outside (divergence theorem), m^3."""
    p = positions[triangles.astype(np.int64)]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0


def edge_counts(triangles):
    """How many triangles name each directed edge, and each undirected one."""
    directed, undirected = {}, {}
    for t in triangles.tolist():
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            directed[(a, b)] = directed.get((a, b), 0) + 1
            undirected[frozenset((a, b))] = undirected.get(frozenset((a, b)), 0) + 1
    return directed, undirected


def unit_cube_surface():
    """The unit cube's 8 corners and 12 triangles, counter-clockwise seen from outside."""
    x = np.array([[i, j, k] for k in (0, 1) for j in (0, 1) for i in (0, 1)], dtype=float)  # vertex i + 2j + 4k
    # the faces z-, z+, y-, y+, x-, x+
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return x, np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])


# ---- meshes ----

def test_box_mesh_volume_and_surface():
    m = pbd.tet_box_mesh((3, 2, 1), (0.3, 0.2, 0.1))
    assert (m.num_vertices, m.num_tets) == (4 * 3 * 2, 6 * 3 * 2 * 1)
    assert m.positions.shape == (24, 3) and m.positions.dtype == np.float64
    assert m.tets.shape == (36, 4) and m.tets.dtype == np.uint32
    i, j, k = 2, 1, 1  # vertex (i, j, k) is (k (ny + 1) + j) (nx + 1) + i
    np.testing.assert_allclose(m.positions[(k * 3 + j) * 4 + i], (0.2, 0.1, 0.1))
    v = volumes(m.positions, m.tets)
    assert (v > 0).all() and math.isclose(v.sum(), 0.3 * 0.2 * 0.1)
    s = pbd.tet_mesh_surface(m)
    assert s.shape == (2 * 2 * (3 * 2 + 3 * 1 + 2 * 1), 3) and s.dtype == np.uint32
    directed, undirected = edge_counts(s)
    assert set(undirected.values()) == {2} and set(directed.values()) == {1}  # closed, consistently wound
    assert math.isclose(surface_volume(m.positions, s), 0.3 * 0.2 * 0.1)
    assert repr(m) == "<pbd.TetMesh: 24 vertices, 36 tets>"


def test_mesh_from_arrays_is_checked_and_immutable():
    box = pbd.tet_box_mesh((1, 1, 1), (1.0, 1.0, 1.0))
    m = pbd.TetMesh(box.positions.tolist(), box.tets.astype(np.int32))  # any array-like, any integer dtype
    np.testing.assert_array_equal(m.positions, box.positions)
    np.testing.assert_array_equal(m.tets, box.tets)
    m.positions[0] = 99.0  # a copy: the mesh keeps its own
    assert m.positions[0, 0] == 0.0
    pbd.check_tet_mesh(m, "box")  # every TetMesh passed it when made
    with pytest.raises(AttributeError):
        m.positions = box.positions


def test_bad_meshes_raise_naming_the_problem():
    x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    pbd.TetMesh(x, [[0, 1, 2, 3]])
    with pytest.raises(pbd.Error, match=r"TetMesh: tet 0 is inverted \(signed volume -0.16666"):
        pbd.TetMesh(x, [[0, 2, 1, 3]])
    with pytest.raises(pbd.Error, match="TetMesh: tet 0 names vertex 7; the mesh has 4"):
        pbd.TetMesh(x, [[0, 1, 2, 7]])
    with pytest.raises(pbd.Error, match="TetMesh: tet 0 names vertex 1 twice"):
        pbd.TetMesh(x, [[0, 1, 1, 3]])
    with pytest.raises(pbd.Error, match="TetMesh: tet 0 is degenerate"):
        pbd.TetMesh(x * [1, 1, 0], [[0, 1, 2, 3]])
    with pytest.raises(pbd.Error, match="TetMesh: the mesh has no tetrahedra"):
        pbd.TetMesh(x, np.zeros((0, 4), dtype=int))
    with pytest.raises(ValueError, match=r"TetMesh: tets must have shape \(T, 4\), got \(1, 3\)"):
        pbd.TetMesh(x, [[0, 1, 2]])
    with pytest.raises(ValueError, match="TetMesh: tets must be an array of integers, got dtype float64"):
        pbd.TetMesh(x, [[0.0, 1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match=r"TetMesh: tets\[0\] must hold vertex indices >= 0, got -1"):
        pbd.TetMesh(x, [[0, 1, 2, -1]])
    with pytest.raises(ValueError, match=r"TetMesh: positions must have shape \(N, 3\), got \(4, 2\)"):
        pbd.TetMesh(x[:, :2], [[0, 1, 2, 3]])
    with pytest.raises(pbd.Error, match=r"tet box: cells\[1\] must be >= 1, got 0"):
        pbd.tet_box_mesh((1, 0, 1), (1.0, 1.0, 1.0))
    with pytest.raises(pbd.Error, match=r"tet box: size\[2\] must be > 0 and finite"):
        pbd.tet_box_mesh((1, 1, 1), (1.0, 1.0, -1.0))


def test_load_tetgen_files_written_here(tmp_path):
    box = pbd.tet_box_mesh((2, 1, 1), (2.0, 1.0, 1.0))
    node = [f"{box.num_vertices} 3 0 0", "# numbered from 1"]
    node += [f"{i + 1} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(box.positions)]
    ele = [f"{box.num_tets} 4 0"] + [f"{t + 1} " + " ".join(str(v + 1) for v in tet) for t, tet in enumerate(box.tets)]
    (tmp_path / "bar.node").write_text("\n".join(node) + "\n")
    (tmp_path / "bar.ele").write_text("\n".join(ele) + "\n")
    for path in (tmp_path / "bar.ele", str(tmp_path / "bar.node")):  # a pathlib.Path or a str, either file
        m = pbd.load_tet_mesh(path)
        np.testing.assert_array_equal(m.positions, box.positions)
        np.testing.assert_array_equal(m.tets, box.tets)
    a, b, c, d = box.tets[0] + 1
    ele[1] = f"1 {b} {a} {c} {d}"  # tet 0's first two corners swapped: inverted
    (tmp_path / "bar.ele").write_text("\n".join(ele) + "\n")
    inverted = r"bar.ele: tet 0 is inverted \(signed volume -0.1666.*\); it is the one numbered 1 at line 2"
    with pytest.raises(pbd.Error, match=inverted):
        pbd.load_tet_mesh(tmp_path / "bar.ele")
    with pytest.raises(pbd.Error, match="nothing.msh"):
        pbd.load_tet_mesh(tmp_path / "nothing.msh")
    with pytest.raises(pbd.Error, match="bar.obj"):
        pbd.load_tet_mesh(tmp_path / "bar.obj")


def test_tetrahedralize_a_cube():
    x, triangles = unit_cube_surface()
    assert math.isclose(surface_volume(x, triangles), 1.0)
    # keep_surface (the default): the surface's triangles are exactly the boundary; the cube's 8 corners need no more
    m = pbd.tetrahedralize(x, triangles, max_volume=0.01)
    np.testing.assert_array_equal(m.positions, x)
    v = volumes(m.positions, m.tets)
    assert (v > 0).all() and math.isclose(v.sum(), 1.0)
    surface = pbd.tet_mesh_surface(m)
    assert sorted(map(tuple, np.sort(surface, axis=1))) == sorted(map(tuple, np.sort(triangles, axis=1)))
    # keep_surface=False: tetgen splits the faces too, so max_volume holds everywhere
    fine = pbd.tetrahedralize(x, triangles, max_volume=0.01, keep_surface=False)
    np.testing.assert_array_equal(fine.positions[:8], x)  # the surface's vertices first, as they are
    v = volumes(fine.positions, fine.tets)
    assert fine.num_tets >= 100 and (v > 0).all() and v.max() <= 0.01 and math.isclose(v.sum(), 1.0)
    again = pbd.tetrahedralize(x, triangles, max_volume=0.01, keep_surface=False)  # deterministic
    np.testing.assert_array_equal(again.tets, fine.tets)
    np.testing.assert_array_equal(again.positions, fine.positions)
    with pytest.raises(pbd.Error, match="cube: cannot fill with tets"):
        pbd.tetrahedralize(x, triangles[:-1], source="cube")  # a hole
    with pytest.raises(pbd.Error, match="max_radius_edge_ratio"):
        pbd.tetrahedralize(x, triangles, max_radius_edge_ratio=0.5)
    with pytest.raises(ValueError, match=r"tetrahedralize: triangles must have shape \(M, 3\)"):
        pbd.tetrahedralize(x, triangles[:, :2])


# ---- material ----

def test_young_poisson_and_the_material():
    m = pbd.young_poisson(1e6, 0.25)
    assert math.isclose(m.mu, 1e6 / 2.5) and math.isclose(m.lambda_, 1e6 / (2.5 * 0.5))
    assert math.isclose(m.compliance(), 1 / m.mu) and math.isclose(m.ratio(), m.mu / m.lambda_)
    assert eval(repr(m), {"pbd": pbd}).mu == m.mu
    assert pbd.NeoHookeanMaterial(mu=2.0, lambda_=math.inf).ratio() == 0.0  # incompressible
    with pytest.raises(pbd.Error, match=r"poisson: Poisson's ratio must be in \(-1, 0.5\), got 0.5"):
        pbd.young_poisson(1e6, 0.5)
    with pytest.raises(pbd.Error, match="young: Young's modulus must be finite and > 0 Pa, got 0"):
        pbd.young_poisson(0.0, 0.3)
    with pytest.raises(pbd.Error, match="NeoHookeanMaterial: mu must be finite and > 0 Pa, got -1"):
        pbd.NeoHookeanMaterial(-1.0, 1.0)
    with pytest.raises(pbd.Error, match="NeoHookeanMaterial: lambda_ must be > 0 Pa"):
        pbd.NeoHookeanMaterial(1.0, math.nan)


# ---- bodies ----

def bar(world_type, **kwargs):
    """A 0.5 x 0.1 x 0.1 m bar of 10 x 2 x 2 cells, E = 1 MPa, nu = 0.3, clamped at x = 0, damped."""
    mesh = pbd.tet_box_mesh((10, 2, 2), (0.5, 0.1, 0.1))
    w = world_type()
    body = w.add_tet_body(mesh, neo_hookean=pbd.young_poisson(1e6, 0.3), clamped="x_min", **kwargs)
    p = w.params
    p.substeps, p.iterations, p.damping = 40, 1, 15.0
    w.params = p
    return w, mesh, body


def test_a_clamped_bar_sags_under_gravity_and_settles(world_type):
    w, mesh, body = bar(world_type)
    assert (body.first_particle, body.num_particles) == (0, mesh.num_vertices)
    np.testing.assert_array_equal(body.triangles, pbd.tet_mesh_surface(mesh))  # first particle 0
    clamped = mesh.positions[:, 0] == 0.0
    tip = mesh.positions[:, 0] == 0.5
    im = w.inverse_masses()
    assert (im[clamped] == 0).all() and (im[~clamped] > 0).all()
    x0 = w.positions().copy()
    sags = []
    for _ in range(60):  # 1 s
        w.step()
        sags.append(x0[tip, 2].mean() - w.positions()[tip, 2].mean())
    x = w.positions()
    assert np.isfinite(x).all()
    np.testing.assert_array_equal(x[clamped], x0[clamped])
    # Timoshenko's tip sag rho g A (L^4 / (8 E I) + L^2 / (2 kappa G A)); 2 linear tets through the thickness are
    # stiffer than the beam (locking), so the bar sags less, but by the same order.
    E, nu, rho, g, h, L = 1e6, 0.3, 1000.0, 9.81, 0.1, 0.5
    G, kappa = E / (2 * (1 + nu)), 10 * (1 + nu) / (12 + 11 * nu)
    closed = rho * g * h * h * (L ** 4 / (8 * E * h ** 4 / 12) + L * L / (2 * kappa * G * h * h))
    assert 0.3 * closed < sags[-1] < closed
    assert abs(sags[-1] - sags[-10]) < 0.01 * sags[-1]  # at rest
    v = pbd.neo_hookean_violation(w)
    assert v.count == mesh.num_tets and math.isfinite(v.rms) and math.isfinite(v.max) and 0 < v.max < 0.2
    assert pbd.tet_volume_violation(w).count == 0


def test_masses_sets_and_placement(world_type):
    mesh = pbd.tet_box_mesh((2, 2, 2), (1.0, 1.0, 1.0))
    w = world_type()
    w.add_particle((0, 0, 0), 1.0)
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    body = w.add_tet_body(mesh, tet_volume=pbd.Stiffness.pbd_k(1.0), neo_hookean=pbd.young_poisson(1e5, 0.4),
                          density=500.0, scale=0.5, origin=(1.0, 2.0, 3.0), pinned=np.array([0, 26]))
    assert (body.first_particle, body.num_particles) == (1, 27) and body.triangles.min() >= 1
    assert "particles [1, 28), 48 triangles" in repr(body)
    lumped = np.zeros(27)  # each tet gives density x volume / 4 to each corner
    for tet, v in zip(mesh.tets, volumes(mesh.positions * 0.5, mesh.tets)):
        lumped[tet] += 500.0 * v / 4
    im = w.inverse_masses()
    assert im[1] == 0 and im[27] == 0  # pinned
    np.testing.assert_allclose(1 / im[2:27], lumped[1:26], rtol=1e-6)
    np.testing.assert_allclose(w.positions()[1:28], mesh.positions * 0.5 + (1.0, 2.0, 3.0), rtol=1e-6)
    assert pbd.tet_volume_violation(w).count == 48 and pbd.neo_hookean_violation(w).count == 48
    assert w.add_constraint_set(pbd.Stiffness.pbd_k(1.0)) == s + 3  # the body made two sets


def test_total_mass_is_density_times_volume():
    mesh = pbd.tet_box_mesh((3, 2, 2), (0.3, 0.2, 0.2))
    w = pbd.WorldDouble()
    w.add_tet_body(mesh, tet_volume=pbd.Stiffness.xpbd_compliance(0.0), density=800.0, scale=2.0)
    assert math.isclose((1 / w.inverse_masses()).sum(), 800.0 * 0.3 * 0.2 * 0.2 * 8)


def test_fibers_on_the_edges_tear_the_tets(world_type):
    """stretch=Stiffness.fiber(material): a fiber on every tet edge (4 cubes in a row: 4 x 19 edges, 3 x 5 shared);
    its far end pinned and moving away, fibers break and take tets with them; no particle is added or changed."""
    mesh = pbd.tet_box_mesh((4, 1, 1), (0.04, 0.01, 0.01))
    w = world_type()
    far = [i for i in range(mesh.num_vertices) if mesh.positions[i, 0] > 0.039]
    body = w.add_tet_body(mesh, neo_hookean=pbd.young_poisson(1e4, 0.3), clamped="x_min", pinned=far,
                          stretch=pbd.Stiffness.fiber(pbd.Material(20.0, rupture_strain=0.1)))
    fibers = w.fibers()
    assert len(fibers["strain"]) == 4 * 19 - 3 * 5 and pbd.neo_hookean_violation(w).count == 24
    end = [body.first_particle + i for i in far]
    v = w.velocities()
    v[end] = (0.5, 0.0, 0.0)
    m = w.inverse_masses()
    del v
    p = w.params
    p.dt, p.gravity = 1e-3, (0.0, 0.0, 0.0)
    w.params = p
    broken = []
    for _ in range(40):
        w.step()
        broken += w.last_breaks()
    assert broken and len(w.fibers()["strain"]) == 61 - len(broken)
    assert pbd.neo_hookean_violation(w).count < 24
    assert np.array_equal(w.inverse_masses(), m) and w.num_particles == body.num_particles
    w.validate()


def test_tet_fibers_follow_their_curve_in_pascals_and_tear_their_tets(world_type):
    """tet_fibers=Stiffness.fiber(material): a tet fiber on every tet along fiber_direction (24 for 4 cubes). Pulled
    along it, tet_fibers() reads the stress of the curve in Pa (E = 20 kPa, linear from the start) at the strain it
    reads; past the rupture strain they break (type 'tet_fiber', four particles) and take their tets with them."""
    mesh = pbd.tet_box_mesh((4, 1, 1), (0.04, 0.01, 0.01))
    w = world_type()
    far = [i for i in range(mesh.num_vertices) if mesh.positions[i, 0] > 0.039]
    body = w.add_tet_body(mesh, neo_hookean=pbd.young_poisson(1e3, 0.3), clamped="x_min", pinned=far,
                          tet_fibers=pbd.Stiffness.fiber(pbd.Material(2e4, rupture_strain=0.1)),
                          fiber_direction=(2.0, 0.0, 0.0))
    assert len(w.tet_fibers()["strain"]) == 24 and np.isnan(w.tet_fibers()["force"]).all()
    end = [body.first_particle + i for i in far]
    p = w.params
    p.dt, p.gravity, p.substeps, p.iterations = 1e-3, (0.0, 0.0, 0.0), 4, 8
    w.params = p
    broken = []
    for step in range(1, 200):
        x = w.positions()
        x[end, 0] = 0.04 * (1.0 + 2e-3 * step)  # 0.2% strain a step
        del x
        w.step()
        broken += w.last_breaks()
        if step == 20:  # 4% strain at the grips: each tet fiber's stress is E times its own strain
            r = w.tet_fibers()
            assert abs(r["strain"].mean() - 0.04) < 0.004
            assert np.allclose(r["force"], 2e4 * r["strain"], rtol=0.02)
        if broken:
            break
    assert {b.type for b in broken} == {"tet_fiber"} and all(len(b.particles) == 4 for b in broken)
    assert all(abs(b.strain - 0.1) < 0.005 for b in broken)
    assert len(w.tet_fibers()["strain"]) == 24 - len(broken) and pbd.neo_hookean_violation(w).count == 24 - len(broken)
    assert "type='tet_fiber'" in repr(broken[0])
    w.validate()


@pytest.mark.parametrize("kwargs, error, message", [
    ({}, pbd.Error, "add_tet_body: a tet body needs neo_hookean, tet_volume or tet_fibers"),
    ({"tet_volume": pbd.Stiffness.pbd_k(1.5)}, pbd.Error, r"add_tet_body: tet_volume: stiffness k must be in \[0, 1\]"),
    ({"clamped": "left"}, ValueError, r'add_tet_body: clamped must be "x_min", .* got "left"'),
    ({"pinned": [99]}, pbd.Error, r"add_tet_body: pinned vertex 99 out of range \(12 vertices\)"),
    ({"pinned": [-1]}, ValueError, r"add_tet_body: pinned\[0\] must be a particle index >= 0, got -1"),
    ({"density": 0.0}, pbd.Error, "add_tet_body: density must be finite and > 0"),
    ({"scale": -1.0}, pbd.Error, "add_tet_body: scale must be finite and > 0"),
    ({"origin": (0.0, math.inf, 0.0)}, pbd.Error, "add_tet_body: origin must be finite"),
    ({"stretch": pbd.Stiffness.pbd_k(2.0)}, pbd.Error, r"add_tet_body: stretch: stiffness k must be in \[0, 1\]"),
    ({"tet_fibers": pbd.Stiffness.pbd_k(1.0), "fiber_direction": (0.0, 0.0, 0.0)}, pbd.Error,
     "add_tet_body: the tet fibers' direction must be finite and not zero"),
])
def test_bad_bodies_raise_and_add_nothing(world_type, kwargs, error, message):
    mesh = pbd.tet_box_mesh((2, 1, 1), (1.0, 0.5, 0.5))
    w = world_type()
    w.add_particle((0, 0, 0), 1.0)
    first_set = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    if "tet_volume" not in kwargs and kwargs:  # a material, so that the argument tested is the one wrong
        kwargs["neo_hookean"] = pbd.young_poisson(1e6, 0.3)
    with pytest.raises(error, match=message):
        w.add_tet_body(mesh, **kwargs)
    assert w.num_particles == 1 and w.num_constraints() == 0
    assert w.add_constraint_set(pbd.Stiffness.pbd_k(1.0)) == first_set + 1  # no set left behind
    w.validate()


def test_a_live_view_refuses_a_body(world_type):
    w = world_type()
    w.add_particle((0, 0, 0), 1.0)
    x = w.positions()
    with pytest.raises(pbd.Error, match=r"add_tet_body: 1 numpy view\(s\)"):
        w.add_tet_body(pbd.tet_box_mesh((1, 1, 1), (1.0, 1.0, 1.0)), tet_volume=pbd.Stiffness.pbd_k(1.0))
    del x
    body = w.add_tet_body(pbd.tet_box_mesh((1, 1, 1), (1.0, 1.0, 1.0)), tet_volume=pbd.Stiffness.pbd_k(1.0))
    assert body.num_particles == 8


# ---- signatures and docstrings ----

@pytest.mark.parametrize("function, signature", [
    (pbd.World.add_tet_body,
     "(self, /, mesh, *, neo_hookean=None, tet_volume=None, density=1000.0, scale=1.0, origin=(0.0, 0.0, 0.0), "
     "pinned=(), clamped=None, stretch=None, tet_fibers=None, fiber_direction=(1.0, 0.0, 0.0))"),
    (pbd.TetMesh.__init__, "(self, /, positions, tets)"),
    (pbd.tet_box_mesh, "(cells, size)"),
    (pbd.load_tet_mesh, "(path)"),
    (pbd.tetrahedralize,
     "(surface_positions, triangles, max_radius_edge_ratio=1.5, max_volume=0.0, keep_surface=True, source='surface')"),
    (pbd.tet_mesh_surface, "(mesh)"),
    (pbd.check_tet_mesh, "(mesh, source)"),
    (pbd.young_poisson, "(young, poisson)"),
    (pbd.NeoHookeanMaterial.__init__, "(self, /, mu, lambda_)"),
])
def test_signatures_are_readable_and_documented(function, signature):
    # inspect reads each signature (signature.hpp); the types are in pbd.pyi (test_stubs.py); a description follows.
    assert str(inspect.signature(function)) == signature
    assert len(function.__doc__.strip()) > 40


def test_every_new_name_has_a_docstring():
    for name in ("TetMesh", "NeoHookeanMaterial", "Body"):
        cls = getattr(pbd, name)
        assert len(cls.__doc__) > 40
        for attr, value in vars(cls).items():
            if not attr.startswith("_") and (callable(value) or isinstance(value, property)):
                assert value.__doc__ and len(value.__doc__.strip()) > 10, f"{name}.{attr}"


@pytest.mark.parametrize("inner", [True, False])
def test_a_tet_bodys_inner_particles_touch_no_other_body(world_type, inner):
    # A 2 x 2 x 2-cell box's one inner vertex (on no boundary face) as a point: a ball of another body resting on it
    # (0.05 m away, radii 0.1 m, 0.45 m from every surface vertex) is not pushed; as a ball, it is.
    mesh = pbd.tet_box_mesh((2, 2, 2), (1.0, 1.0, 1.0))
    w = world_type()
    body = w.add_tet_body(mesh, neo_hookean=pbd.young_poisson(1e5, 0.3))
    on_surface = np.zeros(body.num_particles, dtype=bool)
    on_surface[np.asarray(body.triangles).ravel() - body.first_particle] = True
    interior = np.flatnonzero(~on_surface) + body.first_particle
    np.testing.assert_allclose(w.positions()[interior], [[0.5, 0.5, 0.5]])
    ball = w.add_particle((0.55, 0.5, 0.5), 1.0)
    w.add_contact_body(body.first_particle, body.num_particles, 0.1, interior=interior.tolist() if inner else [])
    w.add_contact_body(ball, 1, 0.1)
    p = w.params
    p.gravity = (0.0, 0.0, 0.0)
    w.params = p
    for _ in range(10):
        w.step()
    moved = np.linalg.norm(w.positions()[ball] - (0.55, 0.5, 0.5))
    assert (moved < 1e-6) if inner else (moved > 0.05)
    with pytest.raises(pbd.Error, match="interior particle 0"):
        w.add_contact_body(0, 2, 0.1, interior=[5])
