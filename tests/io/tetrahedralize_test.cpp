// Closed surfaces filled with tets by the tetgen program: the volume, the kept surface, the orientation, the same
// mesh twice; the surfaces and options refused before tetgen runs, and tetgen missing, failing, killed or silent.
// tetgen must be installed (scripts/deps installs it): without it these tests fail, they do not skip.
#include "pbd/closed_mesh.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/error.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/io/obj_loader.hpp"
#include "pbd/io/tetrahedralize.hpp"

#include "error_checks.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <string>

namespace pbd {
namespace {

using test::error_of;
using test::expect_words;

// Sets an environment variable for the object's lifetime (PATH, to hide tetgen or put a fake one first; TMPDIR, to
// see what tetrahedralize leaves behind), then restores it.
class ScopedEnv {
public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = ::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
  const char* name_;
  std::optional<std::string> old_;
};

// The unit cube [0, 1]³, two triangles a face, counter-clockwise seen from outside.
TriangleMesh cube_mesh() {
  TriangleMesh m;
  m.positions.resize(3, 8);
  for (Index v = 0; v < 8; ++v) m.positions.col(v) = Vec3<double>(double(v & 1), double((v >> 1) & 1), double(v >> 2));
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

TriangleMesh pig_mesh() { return load_obj(std::filesystem::path(PBD_TEST_SCENE_DIR) / "meshes" / "pig.obj"); }

double enclosed_volume(const TriangleMesh& m) { return six_volume<double>(m.triangles, m.positions) / 6.0; }

double tet_volume(const TetMesh& m) {
  double v = 0.0;
  for (const auto& t : m.tets)
    v += signed_tet_volume(m.positions.col(t[0]), m.positions.col(t[1]), m.positions.col(t[2]), m.positions.col(t[3]));
  return v;
}

std::array<Index, 3> rotated(const std::array<Index, 3>& t) {
  const auto k = std::min_element(t.begin(), t.end()) - t.begin();
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

// Every check a filled surface must pass: tets positive and not degenerate, filling exactly the enclosed volume, the
// surface's vertices first at exactly their coordinates, and (keep_surface) the boundary exactly its triangles.
void expect_filled(const TriangleMesh& surface, const TetMesh& mesh, bool keep_surface) {
  EXPECT_NO_THROW(check_tet_mesh(mesh, "filled"));
  const double v = enclosed_volume(surface);
  EXPECT_NEAR(tet_volume(mesh), v, 1e-9 * v);
  ASSERT_GE(mesh.num_vertices(), surface.num_vertices());
  for (Index i = 0; i < surface.num_vertices(); ++i)
    ASSERT_EQ(mesh.positions.col(i), surface.positions.col(i)) << "surface vertex " << i;  // exact: no rounding
  auto boundary = tet_mesh_surface(mesh);
  EXPECT_FALSE(closed_mesh_defect(boundary, mesh.num_vertices()).has_value());
  if (keep_surface) {
    std::vector<std::array<Index, 3>> wanted;
    for (const auto& t : surface.triangles) wanted.push_back(rotated(t));
    for (auto& t : boundary) t = rotated(t);
    std::sort(wanted.begin(), wanted.end());
    std::sort(boundary.begin(), boundary.end());
    EXPECT_EQ(boundary, wanted);
  }
}

TEST(Tetrahedralize, TetgenIsInstalled) {
  // The other tests would fail one by one; this one says why.
  const std::string error = [] {
    try {
      tetrahedralize(cube_mesh(), {}, "cube");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_EQ(error, "") << "scripts/deps installs tetgen";
}

TEST(Tetrahedralize, FillsACubeKeepingItsSurface) {
  const TriangleMesh cube = cube_mesh();
  const TetMesh m = tetrahedralize(cube, {}, "cube");
  expect_filled(cube, m, true);
  EXPECT_NEAR(tet_volume(m), 1.0, 1e-12);
}

TEST(Tetrahedralize, FillsAnIcosphereAndADodecahedron) {
  for (const auto& surface : {icosphere_mesh(2, 0.7), icosphere_mesh(3, 1.3)}) {
    const TetMesh m = tetrahedralize(surface, {}, "sphere");
    expect_filled(surface, m, true);
    EXPECT_GT(m.num_vertices(), surface.num_vertices());  // -q adds vertices inside
  }
  const TriangleMesh dodecahedron = dodecahedron_mesh(0.5);
  expect_filled(dodecahedron, tetrahedralize(dodecahedron, {}, "dodecahedron"), true);
}

TEST(Tetrahedralize, SameSurfaceSameMesh) {
  const TriangleMesh sphere = icosphere_mesh(3, 1.0);
  const TetrahedralizeOptions o{.max_radius_edge_ratio = 1.2, .max_volume = 1e-3};
  const TetMesh a = tetrahedralize(sphere, o, "sphere");
  const TetMesh b = tetrahedralize(sphere, o, "sphere");
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.tets, b.tets);
}

TEST(Tetrahedralize, FinerOptionsGiveMoreTets) {
  const TriangleMesh sphere = icosphere_mesh(3, 1.0);
  const std::size_t base = tetrahedralize(sphere, {}, "sphere").tets.size();
  const TetMesh rounder = tetrahedralize(sphere, {.max_radius_edge_ratio = 1.1}, "sphere");
  expect_filled(sphere, rounder, true);
  EXPECT_GT(rounder.tets.size(), base);
  const TetMesh smaller = tetrahedralize(sphere, {.max_volume = 1e-3}, "sphere");
  expect_filled(sphere, smaller, true);
  EXPECT_GT(double(smaller.tets.size()), enclosed_volume(sphere) / 1e-3);
  // Away from the kept surface tetgen can split any tet, so there the volume bound holds; next to it a tet may stay
  // larger. Most tets are within it.
  std::size_t within = 0;
  for (const auto& t : smaller.tets)
    within += signed_tet_volume(smaller.positions.col(t[0]), smaller.positions.col(t[1]),
                                smaller.positions.col(t[2]), smaller.positions.col(t[3])) <= 1e-3;
  EXPECT_GT(within, smaller.tets.size() * 9 / 10);
}

TEST(Tetrahedralize, WithoutKeepingTheSurfaceItMaySplitIt) {
  // The cube's faces are split too, so a volume bound holds for every tet; the 8 corners stay the first vertices.
  const TriangleMesh cube = cube_mesh();
  const TetMesh m = tetrahedralize(cube, {.max_volume = 0.01, .keep_surface = false}, "cube");
  expect_filled(cube, m, false);
  EXPECT_GT(tet_mesh_surface(m).size(), cube.triangles.size());
  for (const auto& t : m.tets)
    EXPECT_LE(signed_tet_volume(m.positions.col(t[0]), m.positions.col(t[1]), m.positions.col(t[2]),
                                m.positions.col(t[3])),
              0.01);
  // With it kept, tetgen cannot split the cube's few large boundary faces' tets.
  EXPECT_LT(tetrahedralize(cube, {.max_volume = 0.01}, "cube").tets.size(), m.tets.size());
}

TEST(Tetrahedralize, FillsThePig) {
  const TriangleMesh pig = pig_mesh();
  const auto start = std::chrono::steady_clock::now();
  const TetMesh m = tetrahedralize(pig, {}, "pig.obj");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  expect_filled(pig, m, true);
  EXPECT_GT(m.tets.size(), 1000u);
  EXPECT_LT(m.tets.size(), 10000u);
  std::cout << "pig: " << pig.num_vertices() << " surface vertices, " << m.num_vertices() << " vertices, "
            << m.tets.size() << " tets in " << seconds << " s\n";
  const TetMesh loose = tetrahedralize(pig, {.keep_surface = false}, "pig.obj");
  expect_filled(pig, loose, false);
}

TEST(Tetrahedralize, RefusesOpenAndInsideOutSurfacesBeforeRunningTetgen) {
  // With PATH empty of tetgen, running it would fail as "not installed": these are refused before.
  const test::TempDir empty("pbd_no_tetgen");
  const ScopedEnv path("PATH", empty.path().string());
  std::string e = error_of([] { tetrahedralize(grid_mesh(4, 1.0), {}, "cloth.obj"); });
  expect_words(e, {"cloth.obj: cannot fill with tets: edge (", "belongs to one triangle only: the mesh is open"});
  TriangleMesh inside_out = icosphere_mesh(2, 1.0);
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  e = error_of([&] { tetrahedralize(inside_out, {}, "ball.obj"); });
  expect_words(e, {"ball.obj: cannot fill with tets: ", "inside out"});
  TriangleMesh mixed = icosphere_mesh(1, 1.0);
  std::swap(mixed.triangles[5][1], mixed.triangles[5][2]);
  e = error_of([&] { tetrahedralize(mixed, {}, "ball.obj"); });
  expect_words(e, {"cannot fill with tets", "not consistently oriented"});
  TriangleMesh stray = cube_mesh();
  stray.positions.conservativeResize(3, 9);
  stray.positions.col(8) = Vec3<double>(0.5, 0.5, 0.5);
  e = error_of([&] { tetrahedralize(stray, {}, "cube.obj"); });
  expect_words(e, {"cannot fill with tets: vertex 8 is on no triangle"});
  TriangleMesh nan = cube_mesh();
  nan.positions(1, 3) = std::nan("");
  e = error_of([&] { tetrahedralize(nan, {}, "cube.obj"); });
  expect_words(e, {"cannot fill with tets: vertex 3 has a non-finite coordinate"});
  TriangleMesh flat = cube_mesh();
  flat.positions.row(2).setZero();
  e = error_of([&] { tetrahedralize(flat, {}, "cube.obj"); });
  expect_words(e, {"cannot fill with tets: the surface is flat"});
}

TEST(Tetrahedralize, RefusesBadOptionsNamingThem) {
  const test::TempDir empty("pbd_no_tetgen");
  const ScopedEnv path("PATH", empty.path().string());
  const TriangleMesh cube = cube_mesh();
  for (double ratio : {-1.0, 0.0, 0.5, 0.999, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const std::string e = error_of([&] { tetrahedralize(cube, {.max_radius_edge_ratio = ratio}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetrahedralize: max_radius_edge_ratio must be finite and >= 1"});
  }
  for (double volume : {-1e-3, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const std::string e = error_of([&] { tetrahedralize(cube, {.max_volume = volume}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetrahedralize: max_volume must be finite and >= 0"});
  }
  const std::string e = error_of([&] { tetrahedralize(cube, {.max_volume = 1e-8}, "cube.obj"); });
  expect_words(e, {"cube.obj: tetrahedralize: max_volume 1e-08 m^3 would ask for more than 10000000 tets"});
}

TEST(Tetrahedralize, RefusesASelfIntersectingSurfaceWithTetgensReason) {
  // Two cubes, each closed and outward, the second overlapping the first: a closed manifold surface that TetGen
  // cannot fill.
  const TriangleMesh cube = cube_mesh();
  TriangleMesh two;
  two.positions.resize(3, 16);
  two.positions.leftCols(8) = cube.positions;
  two.positions.rightCols(8) = cube.positions.colwise() + Vec3<double>(0.5, 0.3, 0.2);
  two.triangles = cube.triangles;
  for (const auto& t : cube.triangles) two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  ASSERT_FALSE(closed_mesh_defect(two.triangles, two.num_vertices()).has_value());
  for (bool keep : {true, false}) {
    const std::string e = error_of([&] { tetrahedralize(two, {.keep_surface = keep}, "cubes.obj"); });
    expect_words(e, {"cubes.obj: cannot fill with tets: the surface intersects itself (tetgen -d: \"Found ",
                     " pairs of faces are intersecting\"; the first pair: triangles "});
    // One triangle of each cube.
    int a = -1, b = -1;
    ASSERT_EQ(std::sscanf(e.c_str() + e.find("triangles "), "triangles %d and %d", &a, &b), 2) << e;
    EXPECT_LT(a, 12);
    EXPECT_GE(b, 12);
  }
}

TEST(Tetrahedralize, SaysWhenTetgenIsMissing) {
  const test::TempDir empty("pbd_no_tetgen");
  const ScopedEnv path("PATH", empty.path().string());
  EXPECT_EQ(error_of([] { tetrahedralize(cube_mesh(), {}, "cube.obj"); }),
            "cube.obj: tetgen is not installed (Debian's package tetgen: apt install tetgen; scripts/deps in a "
            "source tree)");
}

// A directory holding a fake `tetgen` (a shell script with `body`), first on PATH while the object lives.
class FakeTetgen {
public:
  explicit FakeTetgen(const std::string& body) : dir_("pbd_fake_tetgen") {
    const auto file = dir_ / "tetgen";
    std::ofstream(file) << "#!/bin/sh\n" << body << "\n";
    std::filesystem::permissions(file, std::filesystem::perms::owner_all);
    path_.emplace("PATH", dir_.path().string() + ":" + (::getenv("PATH") ? ::getenv("PATH") : ""));
  }

private:
  test::TempDir dir_;
  std::optional<ScopedEnv> path_;
};

TEST(Tetrahedralize, SaysWhenTetgenFailsIsKilledOrWritesNothing) {
  {
    const FakeTetgen fake("echo 'Error:  something went wrong.' >&2; exit 3");
    const std::string e = error_of([] { tetrahedralize(cube_mesh(), {}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetgen exited with status 3 (tetgen -pq1.5MYzQ): Error:  something went wrong."});
  }
  {
    const FakeTetgen fake("kill -9 $$");
    const std::string e = error_of([] { tetrahedralize(cube_mesh(), {}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetgen was killed by signal 9 (Killed)", "no output"});
  }
  {
    const FakeTetgen fake("exit 0");
    const std::string e = error_of([] { tetrahedralize(cube_mesh(), {}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetgen -pq1.5MYzQ wrote no surface.1.node"});
  }
  {
    // Output that is not TetGen's: named with the file and line.
    const FakeTetgen fake("printf '8 3 0 0\\n0 0 0 0\\n' > surface.1.node; printf '0 4 0\\n' > surface.1.ele");
    const std::string e = error_of([] { tetrahedralize(cube_mesh(), {}, "cube.obj"); });
    expect_words(e, {"cube.obj: tetgen's output: ", "surface.1.node:1: 8 points cannot fit"});
  }
}

TEST(Tetrahedralize, LeavesNoTemporaryFiles) {
  const test::TempDir tmp("pbd_tetgen_tmp");
  const ScopedEnv tmpdir("TMPDIR", tmp.path().string());
  tetrahedralize(cube_mesh(), {}, "cube.obj");
  EXPECT_TRUE(std::filesystem::is_empty(tmp.path()));
  {
    const FakeTetgen fake("exit 3");
    EXPECT_THROW(tetrahedralize(cube_mesh(), {}, "cube.obj"), Error);
  }
  EXPECT_TRUE(std::filesystem::is_empty(tmp.path()));
}

}  // namespace
}  // namespace pbd
