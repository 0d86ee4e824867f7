#pragma once
// Hierarchical position based dynamics (private; Müller 2008, "Hierarchical Position Based Dynamics", VRIPHYS).
//
// Gauss-Seidel moves a correction one constraint per sweep, so a long chain or a fine cloth needs as many sweeps as
// it has constraints across. The hierarchy gives every sub-step a coarse-to-fine pass first: corrections computed on
// a few coarse particles reach the whole body in one pass, and the usual sweeps then only fix what is local.
//
// What is cooked (build_hierarchy, once per change of the model: keyed by Model::edits, the number of constraint
// sets and the settings; held by Model::hierarchy, shared and never changed once built):
//   level 0      the particles of the stretch constraints, joined by them (no constraints of its own: those are the
//                sweeps' stretch constraints). Between two particles the shortest rest length counts. Constraints
//                of compliant sets (XPBD α > 0) take part only with StepParams::hierarchy.compliant: the pass moves
//                positions but not the sweeps' λ, which start from 0 each sub-step, and XPBD's sweeps converge to
//                positions x with x − M⁻¹∇Cᵀλ equal to where they started. A pass that moved the start from the
//                prediction therefore moves the answer: a compliant chain settles shorter than α·T. At α = 0 the
//                answer is C = 0 whatever the start, and the coarse constraints are inactive there.
//   level l + 1  a subset of level l, chosen in particle index order, so the same model gives the same levels:
//                  1. pinned particles (inverse mass 0) are in every level, so they stay pinned;
//                  2. a greedy independent set: each particle not yet decided joins, its undecided neighbours not;
//                  3. each particle left out with fewer than k (StepParams::hierarchy.parents) neighbours in the
//                     coarse level joins it too.
//                So every particle left out has >= k neighbours in level l + 1: its parents. Its weights are
//                ∝ 1 / (rest length to the parent), normalized (the nearer parent counts more).
//                Two coarse particles are joined when they are joined in level l, or both neighbour one particle
//                left out; the rest length is the shortest such path over level l's rest lengths (one or two
//                edges). A path's length bounds the particles' distance from above whenever the finer constraints
//                hold, so a coarse constraint never asks more than the fine ones do: it is one-sided (only pulls
//                when longer than its rest length) and inactive at a solution of the fine level. Its rest length is
//                the path's times 1 + Hierarchy::slack (0.1% by default): the pass removes the large stretch that the
//                sweeps are slow to, and leaves them the small residual they keep at steady state. Correcting that
//                residual too, every sub-step, is not harmless: the interpolation (b. below) is not a projection
//                of the fine constraints, so its correction distorts fine edges, the sweeps turn the distortion into
//                velocity, and the next pass corrects again. On a resting cloth at many sub-steps (h small, so
//                little damping per sub-step) with deep levels that loop gains energy and crumples the cloth
//                (docs/performance.md). Its compliance is the sum of the path's compliances (XPBD α; a PBD set's
//                edge counts as α = 0): springs in series.
//                Masses (Müller 2008 §4): each coarse particle keeps its own mass and gains w·m of every particle
//                left out that names it a parent with weight w, so a level carries the body's whole mass.
//                Levels stop at StepParams::hierarchy.levels or when one keeps more than 90% of the particles.
//                Each level's constraints are graph-colored (graph_coloring, the model's coloring options) and
//                stored color by color.
// What runs (run_hierarchy, each sub-step after prediction and contact generation, before the sweeps, whatever the
// solver): p is copied (scratch, `start`); then from the coarsest level L down to level 1:
//   a. `sweeps` sweeps over the level's constraints, color by color, each color a loop (a color writes no
//      particle twice, and a pinned particle never), with an XPBD λ per constraint starting at 0 each sub-step;
//   b. every particle of level l − 1 left out of level l moves by its parents' weighted corrections since `start`
//      (p_f += Σ w_j (p_j − start_j)): it has not moved before, so it gets every coarser level's correction at once.
// Each loop's items are independent, so the bits do not depend on the thread count or on how a loop is cut; the
// loops are the step's runner's (fork/join, or the thread team that runs a whole step: substep.cpp). The pass runs
// once per sub-step (not per sweep), on p: the sweeps after it keep their own order and padded copy.
#include "pbd/step_params.hpp"
#include "pbd/detail/model.hpp"
#include "scratch.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace pbd::detail {

/// One coarse level: its particles, constraints (color by color) and the interpolation of the particles of the finer
/// level that it leaves out.
template <class Real> struct HierarchyLevel {
  std::vector<Index> particles;                ///< this level's particles (world indices), ascending
  std::vector<std::array<Index, 2>> pairs;     ///< its constraints' particles (world indices), color by color
  std::vector<std::array<Real, 2>> w;          ///< their inverse masses at this level (0: pinned)
  std::vector<Real> rest;                      ///< rest lengths (shortest path over the finer level's), m
  std::vector<Real> compliance;                ///< α, the sum of the path's compliances, m/N
  std::vector<Index> color_offsets;            ///< color c is [color_offsets[c], color_offsets[c + 1])
  std::vector<Index> fine;                     ///< particles of the finer level left out of this one (world indices)
  std::vector<Index> parent_offsets;           ///< fine[i]'s parents are [parent_offsets[i], parent_offsets[i + 1])
  std::vector<Index> parents;                  ///< world indices, each in `particles`
  std::vector<Real> weights;                   ///< per parent, summing to 1 per fine particle
};

/// The cooked hierarchy of a model: levels[0] is level 1 (the coarsest is levels.back()).
template <class Real> struct HierarchyModel {
  std::vector<HierarchyLevel<Real>> levels;
  Index fine_particles = 0;     ///< particles of level 0 (those of the stretch constraints)
  std::uint64_t edits = 0;      ///< Model::edits it was built at
  std::size_t num_sets = 0;     ///< constraint sets it was built with
  Hierarchy settings;           ///< the settings it was built with
};

/// Builds the hierarchy of `m`'s stretch constraints (the design note above). Deterministic.
template <class Real> HierarchyModel<Real> build_hierarchy(const Model<Real>& m, const Hierarchy& settings);

/// Builds Model::hierarchy anew unless the one there matches the model and the settings.
template <class Real> void ensure_hierarchy(Model<Real>& m, const Hierarchy& settings);

/// The invariants: nested levels; every particle left out has >= min(k, its neighbours) parents, all in the coarser
/// level, with positive weights summing to 1; pinned particles are in every level, with w = 0 in every constraint;
/// no color names a movable particle twice; rest lengths ≥ 0 and, when `x` is given (3 × N, the rest shape), ≥ the
/// distance there. Returns the first violation, or an empty string.
template <class Real>
std::string validate_hierarchy(const HierarchyModel<Real>& h, const Model<Real>& m, const Matrix3X<Real>* x = nullptr);

/// Sizes `scratch` for passes over `hm` on n particles (called before a step's sub-steps: a team's members never
/// resize it).
template <class Real> void prepare_hierarchy(const HierarchyModel<Real>& hm, HierarchyScratch<Real>& scratch, Index n);

/// One-sided XPBD projection of constraints [b, e) of one color of `level` on p (3 per particle), their λ at
/// lambda[b, e): only a pair longer than its rest length is pulled together, and λ never pushes (λ ≤ 0).
template <class Real>
void project_level(const HierarchyLevel<Real>& level, Real inv_h2, Real* p, Real* lambda, Index b, Index e);

/// Particles [b, e) of level.fine move by their parents' corrections since the pass began (p − start).
template <class Real>
void interpolate_level(const HierarchyLevel<Real>& level, const Real* start, Real* p, Index b, Index e);

/// The coarse-to-fine pass on p (3 × n) for a sub-step of length `h` (the design note above). `loop(id, begin, end,
/// body)` runs each of its loops, body(b, e) over parts of [begin, end), and returns when the whole loop is done (or,
/// on a thread team, when the team's next shared loop will have waited for it): fork/join with partitioner `id`, or a
/// team's loop (substep.cpp). Every loop's items are independent, so any cut gives the same bits.
template <class Real, class Loop>
void run_hierarchy(const HierarchyModel<Real>& hm, HierarchyScratch<Real>& k, Real* p, Index n, Real h,
                   const Loop& loop) {
  if (hm.levels.empty()) return;
  Real* const start = k.start.data();
  Real* const lambda = k.lambda.data();
  std::size_t id = 0;
  loop(id++, Index(0), Index(3 * n), [&](Index b, Index e) { std::copy(p + b, p + e, start + b); });
  loop(id++, Index(0), Index(k.lambda.size()), [&](Index b, Index e) { std::fill(lambda + b, lambda + e, Real(0)); });
  const Real inv_h2 = Real(1) / (h * h);
  for (std::size_t l = hm.levels.size(); l-- > 0;) {
    const HierarchyLevel<Real>& level = hm.levels[l];
    Real* const level_lambda = lambda + k.lambda_offsets[l];
    for (int sweep = 0; sweep < hm.settings.sweeps; ++sweep)
      for (std::size_t c = 0; c + 1 < level.color_offsets.size(); ++c)
        loop(id++, level.color_offsets[c], level.color_offsets[c + 1],
             [&](Index b, Index e) { project_level(level, inv_h2, p, level_lambda, b, e); });
    loop(id++, Index(0), Index(level.fine.size()), [&](Index b, Index e) { interpolate_level(level, start, p, b, e); });
  }
}

}  // namespace pbd::detail
