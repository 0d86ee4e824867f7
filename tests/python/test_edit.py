"""Removal, the generators (cloth, rope, grains, meshes), built-in scenes by name and the data folder, and frames."""
import os
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import pbd
from conftest import SCENES, cloth

TYPES = ["stretch", "anchor", "bending", "area", "tether", "tet_volume", "neo_hookean", "shape_match", "fiber",
         "tet_fiber"]


def test_every_builtin_type_can_be_removed():
    for name in TYPES:
        assert callable(getattr(pbd.World, f"remove_{name}")) and callable(getattr(pbd.WorldDouble, f"remove_{name}"))


def test_remove_stretch_removes_those_constraints(world_type):
    w = cloth(world_type)
    n = w.num_constraints()
    before = w.violations("stretch")
    w.remove_stretch([0, 2])
    assert w.num_constraints() == n - 2
    assert len(w.violations("stretch")) == len(before) - 2
    with pytest.raises(pbd.Error):
        w.remove_stretch([n])
    with pytest.raises(ValueError, match=r"remove_stretch: indices\[0\] must be a particle index >= 0"):
        w.remove_stretch([-1])
    w.validate()


def test_a_removed_particle_loses_its_constraints_and_stays_put(world_type):
    w = cloth(world_type)
    n = w.num_constraints()
    x = w.positions()[14].copy()
    w.remove_particle(14)  # an inner particle: 4 stretch constraints
    assert w.num_constraints() == n - 4
    assert w.inverse_masses()[14] == 0.0
    for _ in range(5):
        w.step()
    assert np.array_equal(w.positions()[14], x)


def test_add_cloth_adds_the_grid_and_its_edges(world_type):
    w = world_type()
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    body = w.add_cloth(resolution=5, size=2.0, mass=2.5, origin=(1.0, 0.0, 3.0), stretch_set=s)
    assert (body.first_particle, body.num_particles) == (0, 25)
    assert body.triangles.shape == (32, 3)
    assert w.num_constraints() == 2 * 5 * 4 + 16  # rows, columns, diagonals
    x = w.positions()
    assert np.allclose(x[24], (3.0, 2.0, 3.0))
    assert list(np.flatnonzero(w.inverse_masses() == 0)) == [20, 24]  # the corners at y = origin.y + size
    assert np.allclose(1 / w.inverse_masses()[0], 0.1)
    del x
    with pytest.raises(ValueError, match='pin must be "none", "corners" or "edge", got "top"'):
        w.add_cloth(pin="top")


def test_add_rope_and_add_grains(world_type):
    w = world_type()
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    rope = w.add_rope(particles=10, length=0.9, end_mass=5.0, stretch_set=s)
    assert (rope.first_particle, rope.num_particles, w.num_constraints()) == (0, 10, 9)
    assert w.inverse_masses()[0] == 0.0 and w.inverse_masses()[9] == pytest.approx(0.2)
    grains = w.add_grains(count=(2, 3, 4), spacing=0.2, origin=(0.0, 0.0, 1.0), seed=7)
    assert (grains.first_particle, grains.num_particles) == (10, 24)
    again = world_type()
    again.add_grains(count=(2, 3, 4), spacing=0.2, origin=(0.0, 0.0, 1.0), seed=7)
    assert np.array_equal(again.positions(), w.positions()[10:])  # the same seed gives the same bits


def test_add_mesh_adds_a_generated_mesh_with_its_constraints(world_type):
    positions, triangles = pbd.icosphere_mesh(1, 0.5)
    assert positions.shape == (42, 3) and triangles.shape == (80, 3)
    w = world_type()
    s = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    v = w.add_constraint_set(pbd.Stiffness.pbd_k(1.0))
    body = w.add_mesh(positions, triangles, origin=(0.0, 0.0, 2.0), stretch=s, volume=v,
                      pressure=pbd.PressureSchedule(1.0, 1.5, 1.0))
    assert (body.num_particles, w.num_constraints()) == (42, 120 + 1)
    assert np.allclose(w.positions().mean(axis=0), (0.0, 0.0, 2.0))
    bad = triangles.copy()
    bad[5, 1] = 99
    with pytest.raises(pbd.Error):
        w.add_mesh(positions, bad, stretch=s)
    assert w.num_particles == 42  # a bad mesh adds nothing
    for make in (lambda: pbd.grid_mesh(3, 1.0), lambda: pbd.dodecahedron_mesh(1.0),
                 lambda: pbd.tube_mesh(6, 3, 0.2, 1.0, capped=True)):
        x, t = make()
        assert x.shape[1] == 3 and t.shape[1] == 3 and t.max() < len(x)


def test_load_scene_by_name_is_the_built_in_scene():
    by_name = pbd.load_scene("cloth")
    by_path = pbd.load_scene(SCENES / "cloth.json")
    assert by_name.name == by_path.name == "cloth"
    assert pbd.position_hash(pbd.build_world(by_name)) == pbd.position_hash(pbd.build_world(by_path))
    assert "cloth" in pbd.scene_names() and (pbd.data_dir() / "scenes" / "cloth.json").is_file()
    with pytest.raises(pbd.Error, match="no-such-scene"):
        pbd.load_scene("no-such-scene")


def test_the_data_folder_comes_from_pbd_data_dir_first(monkeypatch, tmp_path):
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "mine.json").write_text((SCENES / "rope.json").read_text())
    monkeypatch.setenv("PBD_DATA_DIR", str(tmp_path))
    assert pbd.data_dir() == tmp_path and pbd.scene_names() == ["mine"]
    assert pbd.load_scene("mine").name == "rope"
    monkeypatch.setenv("PBD_DATA_DIR", str(tmp_path / "nowhere"))
    with pytest.raises(pbd.Error, match=re.escape(f"no scenes folder at {tmp_path / 'nowhere' / 'scenes'}")):
        pbd.load_scene("cloth")


def test_frame_series_writes_vtu_frames_and_their_pvd(tmp_path, world_type):
    scene = pbd.load_scene("rope")
    w = pbd.build_world(scene) if world_type is pbd.World else pbd.build_world_double(scene)
    series = pbd.FrameSeries(tmp_path, "rope", "vtu")
    for step in range(3):
        series.write(w, step, scene=scene if step == 0 else None)
        w.step()
    series.finish()
    assert series.frames_written == 3 and series.frame_file(2) == tmp_path / "rope_00002.vtu"
    files = [d.get("file") for d in ET.parse(series.pvd_file).getroot().iter("DataSet")]
    assert files == ["rope_00000.vtu", "rope_00001.vtu", "rope_00002.vtu"]
    # Times are step × dt; the scene's dt in double gives 90 steps of 1/60 s as 1.5 s in both precisions.
    (tmp_path / "timed").mkdir()
    timed = pbd.FrameSeries(tmp_path / "timed", "rope", "vtu", dt=scene.dt)
    timed.write(w, 90)
    timed.finish()
    assert scene.dt == 1.0 / 60.0
    assert [d.get("timestep") for d in ET.parse(timed.pvd_file).getroot().iter("DataSet")] == ["1.5"]
    with pytest.raises(pbd.Error):
        pbd.FrameSeries(tmp_path, "rope", "vtu", dt=0.0)
    with pytest.raises(pbd.Error):
        pbd.FrameSeries(tmp_path, "a/b", "vtu")
    with pytest.raises(pbd.Error):
        pbd.FrameSeries(tmp_path, "rope", "png")


def test_frame_series_writes_no_non_finite_frame_and_never_into_a_fifo(tmp_path, world_type):
    scene = pbd.load_scene("rope")
    w = pbd.build_world(scene) if world_type is pbd.World else pbd.build_world_double(scene)
    series = pbd.FrameSeries(tmp_path, "rope", "vtu")
    series.write(w, 0, scene=scene)
    x = w.positions()
    x[3, 1] = np.nan
    with pytest.raises(pbd.Error, match="rope_00001.vtu: particle 3 has a non-finite position"):
        series.write(w, 1)
    del x
    series.finish()
    assert sorted(os.listdir(tmp_path)) == ["rope.pvd", "rope_00000.vtu"]
    # A FIFO that took a frame's name is refused, not opened (a writer would wait for a reader forever; the reader
    # held here makes such a writer fail this test instead of hanging it).
    (tmp_path / "fifo").mkdir()
    fifo = tmp_path / "fifo" / "rope_00000.obj"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        w2 = pbd.build_world(scene) if world_type is pbd.World else pbd.build_world_double(scene)
        with pytest.raises(pbd.Error, match="rope_00000.obj: cannot write: it is not a regular file"):
            pbd.FrameSeries(tmp_path / "fifo", "rope", "obj").write(w2, 0, scene=scene)
    finally:
        os.close(reader)


def test_write_obj_frame_writes_every_particle_and_triangle(tmp_path, world_type):
    positions, triangles = pbd.icosphere_mesh(0, 1.0)
    w = world_type()
    w.add_mesh(positions, triangles)
    pbd.write_obj_frame(tmp_path / "ball.obj", w, triangles=triangles)
    lines = (tmp_path / "ball.obj").read_text().splitlines()
    assert sum(line.startswith("v ") for line in lines) == 12 and sum(line.startswith("f ") for line in lines) == 20
    with pytest.raises(TypeError, match="world must be a pbd.World or pbd.WorldDouble"):
        pbd.write_obj_frame(tmp_path / "x.obj", "world")
