// The particle contacts (particle_contacts.hpp): cooking the contact bodies, and generate_particle_contacts, which
// runs the broad phase's phases (phases.hpp) in their order.
#include "particle_contacts.hpp"

#include "budget.hpp"
#include "phases.hpp"
#include "simd/cpu.hpp"

#include <algorithm>

namespace pbd::detail {

template <class Real> void cook_contact_bodies(Model<Real>& m) {
  ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  if (c.cooked && c.body_of.size() == std::size_t(n)) return;
  c.body_of.assign(n, ContactBodies<Real>::kNone);
  c.radius = VectorX<Real>::Zero(n);
  c.material.assign(n, ContactMaterial<Real>{});
  c.max_radius = 0;
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    const ContactBody<Real>& body = c.bodies[b];
    for (Index i = body.first; i < body.first + body.count; ++i) {
      c.body_of[i] = Index(b);
      c.radius[i] = body.radius;
      c.material[i] = body.material;
    }
    for (Index i : body.interior) c.radius[i] = Real(0);  // points: out of the grid (`active`)
    c.max_radius = std::max(c.max_radius, body.radius);
  }
  c.active.clear();
  for (Index i = 0; i < n; ++i)
    if (c.radius[i] > Real(0)) c.active.push_back(i);
  c.cooked = true;
}

template <class Real>
void generate_particle_contacts(const Model<Real>& m, const Matrix3X<Real>& x, const Matrix3X<Real>& p,
                                const Matrix3X<Real>& v, Real margin, bool parallel, ParticleGrid<Real>& g,
                                std::vector<ParticleContact<Real>>& out) {
  using namespace contact;
  const ContactBodies<Real>& c = m.contact;
  const Index n = m.num_particles();
  if (!c.particle_contacts() || n == 0) return;
  Call<Real> call{m, x, p, v, margin, parallel, g};
  // 1. the particles joined by a constraint, when the model changed (cook_contact_bodies has run)
  for (const auto& b : c.bodies) call.any_self = call.any_self || (b.self_collision && b.radius > Real(0));
  if (call.any_self && (g.joined_edits != m.edits || g.joined_bodies != c.bodies.size() ||
                        g.joined_offsets.size() != std::size_t(n) + 1))
    build_exclusions(m, x, g);
  const Index count = Index(c.active.size());
  if (count == 0) return;
  call.limit = contact::contact_limit(std::size_t(count));
  // 2. swept boxes in a frame that moves with a mean path: the last sub-step's when there was one with as many
  // particles, else this one's, from a pass of its own. With the last sub-step's cell widths known as well, level 0's
  // cells are found in the same pass. The frame and the widths change only which pairs are tested, never the result.
  call.known = g.known == count;
  call.frame = call.known ? g.frame : mean_path(call);
  Eigen::Vector3d width = g.width;
  sweep_boxes(call);
  if (!call.known) width = g.width;
  call.avx2 = avx2_enabled();
  // 3.–4. level by level: the grid, then its pairs; the large boxes form the next level
  for (std::size_t level = 0;; ++level) {
    if (g.levels.size() < level + 2) g.levels.resize(level + 2);
    Level<Real>& lv = g.levels[level];
    const Index members = Index(lv.members.size());
    if (members <= kBruteForce) {  // few left: each with each
      pair_each_with_each(call, lv);
      break;
    }
    const Vec3<Real> inv = width.cwiseInverse().template cast<Real>();
    if (level > 0 || !call.known) find_cells(call, lv, inv);  // level 0's were found with the boxes when known
    const LevelGrid<Real> grid = build_grid(call, lv);
    walk_entries(call, lv, grid);
    query_large(call, lv, grid, inv);
    const Index large = Index(lv.large.size());
    if (large == 0) break;
    // the large boxes form the next level, with cells at least twice as wide and as wide as they are on average
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index ch = 0; ch < std::min<Index>(kChunks, members); ++ch) sum += lv.extent[ch];
    width = (2.0 * width).cwiseMax(kCellScale * sum / double(large));
    g.levels[level + 1].members.swap(lv.large);
  }
  // the budget (budget.hpp): every list's pairs, repeats included, whatever the threads
  std::size_t found = 0;
  for (std::size_t l = 0; l < call.lists; ++l) found += g.lists[l].size();
  if (found > call.limit)
    fail_too_many_contacts<Real>(c, std::span(g.lists.data(), call.lists), found, call.limit, margin);
  // 5. in the order of the pairs
  order_contacts(call, out);
}

template void cook_contact_bodies(Model<float>&);
template void cook_contact_bodies(Model<double>&);
template void generate_particle_contacts(const Model<float>&, const Matrix3X<float>&, const Matrix3X<float>&,
                                         const Matrix3X<float>&, float, bool, ParticleGrid<float>&,
                                         std::vector<ParticleContact<float>>&);
template void generate_particle_contacts(const Model<double>&, const Matrix3X<double>&, const Matrix3X<double>&,
                                         const Matrix3X<double>&, double, bool, ParticleGrid<double>&,
                                         std::vector<ParticleContact<double>>&);

}  // namespace pbd::detail
