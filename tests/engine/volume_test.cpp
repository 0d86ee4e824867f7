// Volume constraint: gradient, momentum, the target schedule, inflation of the dodecahedron under every solver,
// and the guards (open, flat, inverted, collapsed, all pinned).
#include "pbd/constraints/volume.hpp"
#include "pbd/io/mesh_body.hpp"
#include "pbd/io/mesh_generators.hpp"
#include "pbd/constraints/volume.hpp"
#include "pbd/world.hpp"

#include <gtest/gtest.h>

#include <random>

namespace pbd {
namespace {

// ∇_i (6V) at every particle of constraint 0, from the rows' rings (what the projection uses).
Matrix3X<double> ring_gradient(const VolumeConstraints<double>& v, const Matrix3X<double>& x) {
  Matrix3X<double> g = Matrix3X<double>::Zero(3, x.cols());
  const auto& c = v.items[0];
  for (Index r = c.row_begin; r < c.row_end; ++r)
    for (Index k = v.ring_offsets[r]; k < v.ring_offsets[r + 1]; ++k)
      g.col(v.particles[r]) += Vec3<double>(x.col(v.ring[k][0])).cross(Vec3<double>(x.col(v.ring[k][1])));
  return g;
}

// A randomly perturbed icosphere in a world with one volume constraint.
World<double> blob(unsigned seed, int level = 1) {
  World<double> w;
  TriangleMesh m = icosphere_mesh(level, 0.5);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (Eigen::Index i = 0; i < m.positions.cols(); ++i) m.positions.col(i) += Eigen::Vector3d(u(rng), u(rng), u(rng));
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  add_mesh(w, m, {}, sets);
  return w;
}

// The projection finds a ring corner's p − o by its row (VolumeConstraints::ring_rows): for every constraint of a
// table of several meshes (rows relative to each constraint's first), that row holds the corner's particle; and a
// world of two meshes validates.
TEST(Volume, RingRowsNameEachCornersRowInItsOwnConstraint) {
  VolumeConstraints<double> v;
  const TriangleMesh a = icosphere_mesh(1, 0.5), b = icosphere_mesh(2, 0.3);
  const Index offset = Index(a.positions.cols());
  std::vector<std::array<Index, 3>> tb;
  for (const auto& t : b.triangles) tb.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  v.add(a.triangles, 0, 1.0, {});
  v.add(tb, 0, 1.0, {});
  ASSERT_EQ(v.ring_rows.size(), v.ring.size());
  for (const auto& c : v.items)
    for (Index r = c.row_begin; r < c.row_end; ++r)
      for (Index k = v.ring_offsets[r]; k < v.ring_offsets[r + 1]; ++k)
        for (int j = 0; j < 2; ++j) {
          ASSERT_LT(v.ring_rows[k][j], c.row_end - c.row_begin);
          EXPECT_EQ(v.particles[c.row_begin + v.ring_rows[k][j]], v.ring[k][j]) << "corner " << k;
        }
  World<double> w = blob(4);
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  add_mesh(w, icosphere_mesh(2, 0.3), {}, sets);
  EXPECT_NO_THROW(w.validate());
}

TEST(Volume, GradientMatchesFiniteDifferences) {
  for (unsigned seed : {1u, 2u, 3u}) {
    World<double> w = blob(seed);
    const auto& v = w.volumes();
    Matrix3X<double> x = w.positions();
    x.colwise() += Eigen::Vector3d(0.3, -2, 1);  // away from the origin
    const Matrix3X<double> g = ring_gradient(v, x);
    const double h = 1e-6;
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      for (int d = 0; d < 3; ++d) {
        Matrix3X<double> plus = x, minus = x;
        plus(d, i) += h;
        minus(d, i) -= h;
        const double fd = (six_volume<double>(v.triangles, plus) - six_volume<double>(v.triangles, minus)) / (2 * h);
        EXPECT_NEAR(g(d, i), fd, 1e-6 * (1 + std::abs(fd))) << i << " " << d;
      }
  }
}

TEST(Volume, SixVolumeOfTheGeneratedSolidsIsSixTimesTheirVolume) {
  const double pi = 3.14159265358979323846;
  const TriangleMesh s = icosphere_mesh(5, 1.0);
  EXPECT_NEAR(six_volume<double>(s.triangles, s.positions) / 6.0, 4.0 / 3.0 * pi, 0.01 * 4.0 / 3.0 * pi);
  const TriangleMesh t = tube_mesh(64, 3, 1.0, 2.0, true);
  EXPECT_NEAR(six_volume<double>(t.triangles, t.positions) / 6.0, 2.0 * pi, 0.01 * 2.0 * pi);
  const TriangleMesh d = dodecahedron_mesh(1.0);  // volume of a regular dodecahedron with circumradius 1: 2.785
  EXPECT_NEAR(six_volume<double>(d.triangles, d.positions) / 6.0, 2.78516386, 1e-6);
}

TEST(Volume, ConservesLinearMomentumWithEqualAndUnequalMasses) {
  for (unsigned seed : {4u, 5u}) {
    World<double> w = blob(seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> mass(0.01, 100.0);
    VectorX<double> inv(w.num_particles());
    for (Index i = 0; i < w.num_particles(); ++i) inv[i] = seed == 4 ? 2.0 : 1.0 / mass(rng);
    Matrix3X<double> p = w.positions();
    const Matrix3X<double> before = p;
    std::vector<double> lambda(1, 0.0);
    VolumeScratch<double> scratch;
    scratch.target = {2.0 * w.volumes().items[0].rest};
    const SolveCoefficients<double> coeff[1] = {{1, 0}};
    project_volumes<double>(w.volumes(), coeff, p.data(), inv.data(), lambda, scratch);
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
    double scale = 0;
    for (Index i = 0; i < w.num_particles(); ++i) {
      momentum += (p.col(i) - before.col(i)) / inv[i];
      scale += (p.col(i) - before.col(i)).norm() / inv[i];
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_LT(momentum.norm(), 1e-9 * scale);
  }
}

TEST(Volume, PressureScheduleRampsThenHolds) {
  const PressureSchedule s{1.0, 3.0, 2.0};
  EXPECT_DOUBLE_EQ(s.at(-1.0), 1.0);
  EXPECT_DOUBLE_EQ(s.at(0.0), 1.0);
  EXPECT_DOUBLE_EQ(s.at(1.0), 2.0);
  EXPECT_DOUBLE_EQ(s.at(2.0), 3.0);
  EXPECT_DOUBLE_EQ(s.at(50.0), 3.0);
  EXPECT_DOUBLE_EQ((PressureSchedule{1.0, 2.0, 0.0}.at(0.0)), 2.0);
}

// The inflate scene's set-up: dodecahedron, soft stretch, bending, hard volume from 1× to 3× over 1 s, no gravity.
template <class Real> World<Real> inflating_dodecahedron(Solver solver) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.stretch = w.add_constraint_set(Stiffness::xpbd_compliance(1e-3));
  sets.bending = w.add_constraint_set(Stiffness::pbd_k(0.1));
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.pressure = {1.0, 3.0, 1.0};
  add_mesh(w, dodecahedron_mesh(0.3), {}, sets);
  StepParams<Real> p;
  p.gravity.setZero();
  p.substeps = 4;
  p.iterations = 5;
  p.damping = Real(1);
  p.solver = solver;
  w.set_params(p);
  return w;
}

TEST(Volume, DodecahedronReachesItsTargetWithinOnePercentAndStaysThere) {
  for (Solver s : kSolvers) {
    World<float> w = inflating_dodecahedron<float>(s);
    const auto& v = w.volumes();
    const double v0 = v.items[0].rest;
    double worst = 0;
    for (int k = 0; k < 180; ++k) {  // 3 s
      w.step();
      ASSERT_TRUE(w.positions().allFinite()) << name(s);
      const double target = v0 * v.items[0].pressure.at(w.time());
      if (w.time() >= 1.0)
        worst = std::max(worst, std::abs(double(six_volume<float>(v.triangles, Matrix3X<float>(w.positions()))) / target - 1));
    }
    // Every solver, Jacobi included, projects the volume in place after the other constraints in every sweep.
    EXPECT_LT(worst, 0.01) << name(s);
  }
}

TEST(VolumeGuards, OpenNonManifoldAndMisorientedMeshesAreRejectedNamingTheEdge) {
  World<double> w;
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  const TriangleMesh m = icosphere_mesh(0, 1.0);
  w.add_particles(m.positions, VectorX<double>::Ones(m.num_vertices()));
  auto expect = [&](std::vector<std::array<Index, 3>> tris, const char* what) {
    try {
      w.add_volume(tris, set);
      ADD_FAILURE() << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("edge ("), std::string::npos) << e.what();
    }
  };
  auto open = m.triangles;
  open.pop_back();
  expect(open, "open");
  auto flipped = m.triangles;
  std::swap(flipped[3][1], flipped[3][2]);
  expect(flipped, "consistently oriented");
  auto doubled = m.triangles;
  doubled.insert(doubled.end(), m.triangles.begin(), m.triangles.begin() + 1);
  doubled.push_back({m.triangles[0][1], m.triangles[0][0], m.triangles[0][2]});
  expect(doubled, "manifold");
  EXPECT_TRUE(w.volumes().empty());
}

TEST(VolumeGuards, FlatAndInsideOutMeshesAreRejected) {
  World<double> w;
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  TriangleMesh m = icosphere_mesh(1, 1.0);
  TriangleMesh flat = m;
  flat.positions.row(2).setZero();
  Index first = w.add_particles(flat.positions, VectorX<double>::Ones(flat.num_vertices()));
  auto shifted = [&](const TriangleMesh& mesh) {
    std::vector<std::array<Index, 3>> t = mesh.triangles;
    for (auto& tri : t)
      for (Index& i : tri) i += first;
    return t;
  };
  EXPECT_THROW(w.add_volume(shifted(flat), set), Error);
  first = w.add_particles(m.positions, VectorX<double>::Ones(m.num_vertices()));
  auto inverted = shifted(m);
  for (auto& t : inverted) std::swap(t[1], t[2]);
  try {
    w.add_volume(inverted, set);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("inside out"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(w.add_volume(shifted(m), set));
}

// Runs a few steps of a world whose ball was flattened, mirrored (inverted) or collapsed after it was built.
template <class Real> void squash_and_step(const char* how, Solver solver) {
  World<Real> w;
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  add_mesh(w, icosphere_mesh(2, 0.5), {}, sets);
  StepParams<Real> p;
  p.gravity.setZero();
  p.solver = solver;
  w.set_params(p);
  auto x = w.positions();
  const std::string h = how;
  if (h == "flat") x.row(2).setZero();
  if (h == "inverted") x.row(0) *= Real(-1);
  if (h == "collapsed") x.colwise() = Vec3<Real>(1, 2, 3);
  const Real before = six_volume<Real>(w.volumes().triangles, Matrix3X<Real>(x));
  for (int k = 0; k < 5; ++k) w.step();
  ASSERT_TRUE(w.positions().allFinite()) << how << " " << name(solver);
  const Real after = six_volume<Real>(w.volumes().triangles, Matrix3X<Real>(w.positions()));
  const Real rest = w.volumes().items[0].rest;
  if (h == "collapsed") {
    EXPECT_EQ(after, before) << "nothing can move a mesh collapsed to a point";
  } else {
    EXPECT_NEAR(after / rest, 1.0, 0.01) << how << " " << name(solver) << ": pushed back to its target";
  }
}

TEST(VolumeGuards, FlattenedInvertedOrCollapsedMeshesStayFinite) {
  for (Solver s : {Solver::serial, Solver::colored, Solver::jacobi})
    for (const char* how : {"flat", "inverted", "collapsed"}) {
      squash_and_step<float>(how, s);
      squash_and_step<double>(how, s);
    }
}

TEST(VolumeGuards, AllPinnedMovesNothing) {
  World<double> w;
  MeshConstraintSets sets;
  sets.volume = w.add_constraint_set(Stiffness::pbd_k(1.0));
  sets.pressure = {2.0, 2.0, 0.0};
  MeshBodyOptions o;
  for (Index i = 0; i < 12; ++i) o.pinned.push_back(i);
  add_mesh(w, icosphere_mesh(0, 0.5), o, sets);
  const Matrix3X<double> before = w.positions();
  for (Solver s : {Solver::serial, Solver::colored, Solver::jacobi}) {
    StepParams<double> p;
    p.solver = s;
    w.set_params(p);
    w.step();
    EXPECT_EQ(Matrix3X<double>(w.positions()), before) << name(s);
  }
}

TEST(VolumeGuards, OneCentimetreTetrahedronIsKept) {
  // An absolute epsilon makes tiny volumes do nothing (see docs); ours is relative. 1 cm tetrahedron, squeezed.
  World<double> w;
  const double s = 0.01;
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(s, 0, 0), Eigen::Vector3d(0, s, 0),
                                   Eigen::Vector3d(0, 0, s)})
    w.add_particle(q, 0.001);
  const Index set = w.add_constraint_set(Stiffness::pbd_k(1.0));
  const std::vector<std::array<Index, 3>> tris = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  w.add_volume(tris, set);
  w.positions()(2, 3) = 0.5 * s;  // half the volume
  StepParams<double> p;
  p.gravity.setZero();
  w.set_params(p);
  w.step();
  EXPECT_NEAR(six_volume<double>(tris, w.positions()) / w.volumes().items[0].rest, 1.0, 1e-3);
}

}  // namespace
}  // namespace pbd
