#include "pbd/io/frame_topology.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/io/tet_mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>

namespace pbd {
namespace {

using detail::message;

// Per world particle, the index of the body holding it (the bodies checked to hold every particle once).
std::vector<Index> particle_bodies(const FrameTopology& t, Index num_particles) {
  std::vector<Index> body(num_particles, 0);
  for (std::size_t b = 0; b < t.bodies.size(); ++b)
    for (Index i = 0; i < t.bodies[b].num_particles; ++i) body[t.bodies[b].first_particle + i] = Index(b);
  return body;
}

// Adds to each body, as lines, the stretch constraints and the fibers with both particles in that body and neither
// on a triangle.
template <class Real> void add_lines(const World<Real>& world, FrameTopology& t) {
  std::vector<std::uint8_t> on_surface(world.num_particles(), 0);
  const std::vector<Index> body_of = particle_bodies(t, world.num_particles());
  for (const FrameBody& body : t.bodies)
    for (const auto& tri : body.triangles)
      for (Index i : tri) on_surface[i] = 1;
  // Each constraint of `view` off the surface and inside one body: a segment in `lines`, its index in `index`.
  auto draw = [&](const auto& view, auto lines, auto index) {
    for (std::size_t k = 0; k < view.size(); ++k) {
      const auto [a, b] = view[k].particles;
      if (on_surface[a] || on_surface[b] || body_of[a] != body_of[b]) continue;
      (t.bodies[body_of[a]].*lines).push_back({a, b});
      (t.bodies[body_of[a]].*index).push_back(Index(k));
    }
  };
  draw(world.template constraints<StretchConstraint<Real>>(), &FrameBody::lines, &FrameBody::line_stretch);
  draw(world.template constraints<FiberConstraint<Real>>(), &FrameBody::fiber_lines, &FrameBody::line_fiber);
}

// Adds to each body the tets of the tet constraints with all four corners in it, each once (frame_topology.hpp):
// the Neo-Hookean constraints first, since they carry the rest shape the strain needs, and a tet volume constraint
// only when no constraint before it named the same four particles.
template <class Real> void add_tets(const World<Real>& world, FrameTopology& t) {
  const std::vector<Index> body_of = particle_bodies(t, world.num_particles());
  std::map<std::array<Index, 4>, std::pair<Index, std::size_t>> drawn;  // sorted corners → (body, its tet)
  auto key_of = [](std::array<Index, 4> corners) {
    std::sort(corners.begin(), corners.end());
    return corners;
  };
  auto add = [&](const std::array<Index, 4>& corners, FrameTetRest rest) {
    const Index b = body_of[corners[0]];
    for (Index p : corners)
      if (body_of[p] != b) return;  // joins two bodies: in neither's cells
    if (!drawn.emplace(key_of(corners), std::pair{b, t.bodies[b].tets.size()}).second) return;
    t.bodies[b].tets.push_back(corners);
    t.bodies[b].tet_rest.push_back(std::move(rest));
  };
  for (const auto& c : world.template constraints<NeoHookeanConstraint<Real>>()) {
    Eigen::Matrix3d inverse_rest;
    inverse_rest << c.inv_rest0.template cast<double>(), c.inv_rest1.template cast<double>(),
        c.inv_rest2.template cast<double>();
    add(c.particles, {double(c.volume), inverse_rest});
  }
  for (const auto& c : world.template constraints<TetVolumeConstraint<Real>>()) add(c.particles, {double(c.rest), {}});
  const auto fibers = world.template constraints<TetFiberConstraint<Real>>();
  for (const auto& c : fibers) add(c.particles, {double(c.volume), {}});  // a body held by its tet fibers alone
  if (fibers.empty()) return;
  for (FrameBody& b : t.bodies) b.tet_fiber.assign(b.tets.size(), FrameBody::kNoTetFiber);
  for (std::size_t k = 0; k < fibers.size(); ++k)
    if (const auto at = drawn.find(key_of(fibers[k].particles)); at != drawn.end())
      t.bodies[at->second.first].tet_fiber[at->second.second] = Index(k);
}

// Drops from b the lines and fiber lines with both ends on its tets.
void drop_lines_in_tets(FrameBody& b) {
  std::vector<std::uint8_t> in_tet(std::size_t(b.num_particles), 0);
  for (const auto& q : b.tets)
    for (Index p : q) in_tet[p - b.first_particle] = 1;
  auto keep = [&](std::vector<std::array<Index, 2>>& lines, std::vector<Index>& index) {
    std::size_t kept = 0;
    for (std::size_t k = 0; k < lines.size(); ++k) {
      if (in_tet[lines[k][0] - b.first_particle] && in_tet[lines[k][1] - b.first_particle]) continue;
      lines[kept] = lines[k];
      index[kept++] = index[k];
    }
    lines.resize(kept);
    index.resize(kept);
  };
  keep(b.lines, b.line_stretch);
  keep(b.fiber_lines, b.line_fiber);
}

}  // namespace

template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<SceneBody>& bodies) {
  // A surface that tore draws its triangles as they are now; once a tear has added particles (at the end of the
  // world, past every body), one body "world" holds them all, with every body's triangles.
  auto triangles_of = [&](const SceneBody& b) {
    if (b.surface == SceneBody::kNoSurface || b.surface >= world.num_surfaces()) return b.triangles;
    const auto now = world.surface(b.surface);
    return std::vector<std::array<Index, 3>>(now.begin(), now.end());
  };
  Index held = 0;
  bool tears = false;
  for (const SceneBody& b : bodies) {
    held += b.num_particles;
    tears = tears || b.surface != SceneBody::kNoSurface;
  }
  if (tears && held < world.num_particles()) {
    std::vector<std::array<Index, 3>> all;
    for (const SceneBody& b : bodies) {
      const auto tris = triangles_of(b);
      all.insert(all.end(), tris.begin(), tris.end());
    }
    return frame_topology(world, all);
  }
  FrameTopology t;
  for (const SceneBody& b : bodies)
    t.bodies.push_back({b.name, b.first_particle, b.num_particles, triangles_of(b), {}, {}, {}, {}, {}, {}, {}});
  check_frame_topology(t, world.num_particles(), "frame_topology");
  add_lines(world, t);
  add_tets(world, t);
  // A body of tets draws the boundary of the tets it has now: the tets torn along broken fibers are gone
  // (traits.hpp: breaks_with_fibers), and the crack's faces show. Before any tear that is the body's own boundary,
  // in the same order (its triangles were made by tet_mesh_surface from the same tets, in the same order).
  // Its stretch constraints and fibers along the tets' edges are drawn as the tets, not as lines.
  for (FrameBody& b : t.bodies)
    if (!b.tets.empty()) {
      b.triangles = tet_mesh_surface(TetMesh{{}, b.tets});
      drop_lines_in_tets(b);
    }
  return t;
}

template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles) {
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (Index p : triangles[i])
      if (p >= world.num_particles())
        throw Error(message("frame_topology: triangle ", i, ": particle index ", p, " out of range (the world has ",
                            world.num_particles(), " particles)"));
  FrameTopology t;
  t.bodies.push_back({"world", 0, world.num_particles(), triangles, {}, {}, {}, {}, {}, {}, {}});
  add_lines(world, t);
  add_tets(world, t);
  return t;
}

void check_frame_topology(const FrameTopology& topology, Index num_particles, const std::string& what) {
  std::uint64_t next = 0;
  for (const FrameBody& b : topology.bodies) {
    if (b.first_particle != next)
      throw Error(message(what, ": body ", b.name, " starts at particle ", b.first_particle, ", expected ", next,
                          " (the bodies must hold every particle once, in order)"));
    next += b.num_particles;
    if (next > num_particles)
      throw Error(message(what, ": body ", b.name, " ends at particle ", next, " but the world has ", num_particles,
                          " particles"));
    auto check = [&](const auto& items, const char* item) {
      for (std::size_t k = 0; k < items.size(); ++k)
        for (Index p : items[k])
          if (p < b.first_particle || p >= next)
            throw Error(message(what, ": body ", b.name, ": ", item, " ", k, ": particle index ", p,
                                " is not one of its particles [", b.first_particle, ", ", next, ")"));
    };
    check(b.triangles, "triangle");
    check(b.lines, "line");
    check(b.fiber_lines, "fiber line");
    check(b.tets, "tet");
    if (b.line_stretch.size() != b.lines.size())
      throw Error(message(what, ": body ", b.name, " has ", b.lines.size(), " lines but ", b.line_stretch.size(),
                          " line_stretch entries"));
    if (b.line_fiber.size() != b.fiber_lines.size())
      throw Error(message(what, ": body ", b.name, " has ", b.fiber_lines.size(), " fiber lines but ",
                          b.line_fiber.size(), " line_fiber entries"));
    if (b.tet_rest.size() != b.tets.size())
      throw Error(message(what, ": body ", b.name, " has ", b.tets.size(), " tets but ", b.tet_rest.size(),
                          " tet_rest entries"));
    if (!b.tet_fiber.empty() && b.tet_fiber.size() != b.tets.size())
      throw Error(message(what, ": body ", b.name, " has ", b.tets.size(), " tets but ", b.tet_fiber.size(),
                          " tet_fiber entries"));
  }
  if (next != num_particles)
    throw Error(message(what, ": the bodies hold ", next, " particles but the world has ", num_particles));
}

template FrameTopology frame_topology(const World<float>&, const std::vector<SceneBody>&);
template FrameTopology frame_topology(const World<double>&, const std::vector<SceneBody>&);
template FrameTopology frame_topology(const World<float>&, const std::vector<std::array<Index, 3>>&);
template FrameTopology frame_topology(const World<double>&, const std::vector<std::array<Index, 3>>&);

}  // namespace pbd
