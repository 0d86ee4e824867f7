#pragma once
// How the sweeps run their parallel loops (private): on a team of threads held for the whole solve (team.hpp), or
// forked per loop (run_range / tbb::parallel_for with an affinity partitioner per loop). Every loop the sweeps run
// gives the same bits however it is cut, so this decides only the time. What it decides:
//   - a loop's parts: under the colors schedule on a team, each member takes, in every color, the constraints of
//     its share of the particles (Model::particle_cuts), so that its particles' cache lines stay with it from color
//     to color; under the block schedule, the same blocks every sweep and, in each boundary color, the constraints
//     filed under its own blocks (block_layout.hpp sorts them so);
//   - which loops are shared at all (small ones run on one thread: a fork, or a team's barrier, costs more than a
//     small color);
//   - the interiors' tasks (block schedule): how many blocks a task takes and whether they run on several threads.
// A copy of SweepLoops belongs to each member of a team (join()), all running the same sweep code.
#include "parallel_range.hpp"
#include "pbd/detail/model.hpp"
#include "scratch.hpp"
#include "team.hpp"

#include <algorithm>

namespace pbd::detail {

template <class Real> class SweepLoops {
public:
  /// blocks: the sweeps run the block schedule (its interiors and boundary cutting apply).
  SweepLoops(const Model<Real>& model, Scratch<Real>& scratch, bool parallel, bool blocks, const ParallelConfig& config)
      : m_(model), k_(scratch), parallel_(parallel), blocks_(blocks), config_(config),
        large_blocks_(blocks && large_blocks(model)), share_interiors_(shares_interiors(model, parallel, blocks)) {}

  /// Blocks hold on average at least this many interior constraints: large (a type with colored interiors wants
  /// them so; its kernel runs a block a color at a time, so a block need not be small to keep the core busy).
  static constexpr std::size_t kLargeBlock = 4096;
  static bool large_blocks(const Model<Real>& m) {
    std::size_t interior = 0;
    for_each_type(m, [&](const TypeStore<Real>& type, std::size_t) {
      interior += type.num_blocks() ? type.color_begin(type.num_blocks()) : 0;
    });
    return m.num_blocks > 0 && interior >= kLargeBlock * std::size_t(m.num_blocks);
  }
  /// The interiors are shared with at least two blocks per thread, or one large block per thread (with fewer small
  /// blocks, the threads mostly trade cache lines instead of sharing the work).
  static bool shares_interiors(const Model<Real>& m, bool parallel, bool blocks) {
    const Index threads = Index(std::max(1, tbb::this_task_arena::max_concurrency()));
    if (!blocks || !parallel) return false;
    return m.num_blocks >= 2 * threads || (m.num_blocks >= threads && large_blocks(m));
  }
  /// A team forms only when some loop has at least this many items (ParallelConfig::inline_below, the loops a fork
  /// would take): sharing small loops moves their cache lines between the threads for nothing.
  static std::size_t team_share_below(const ParallelConfig& cfg) { return std::max<std::size_t>(1, cfg.inline_below); }
  /// Within a team, a loop is shared when each member gets at least ParallelConfig::min_grain items (and always at
  /// team_share_below): a barrier costs less than the wait of the other members while one projects a mid-sized
  /// color alone.
  static std::size_t team_loop_share_below(const ParallelConfig& cfg, int members) {
    return std::max<std::size_t>(1, std::min(cfg.inline_below, cfg.min_grain * std::size_t(members)));
  }

  bool parallel() const { return parallel_; }
  const ParallelConfig& config() const { return config_; }
  bool shares_interiors() const { return share_interiors_; }
  /// Runs the loops as `member` of a team (nullptr: forks per loop again).
  void join(Team::Member* member) { team_ = member; }
  Team::Member* team() const { return team_; }
  /// Constraints in the blocks' interiors (they decide whether the interiors fork) and the most blocks a task of
  /// interiors takes (kInterleave, or a kernel's chains).
  void set_interiors(std::size_t items, Index chains) {
    interior_items_ = items;
    chains_ = chains;
  }

  /// The first partitioner slot of a sweep (slots only hint the cache: any numbering gives the same bits).
  void start_sweep() { slot_ = 0; }
  /// Reserves `n` partitioner slots; returns the first.
  std::size_t slots(std::size_t n) {
    const std::size_t first = slot_;
    slot_ += n;
    return first;
  }

  /// A parallel loop body(b, e) over [begin, end): on the team when there is one (its inline threshold), else
  /// run_range with the affinity partitioner of `slot` (a team's members never touch the pool).
  template <class Body>
  void range(Index begin, Index end, const ParallelConfig& cfg, std::size_t slot, const Body& body) {
    if (team_) {
      team_->loop(begin, end, parallel_ && std::size_t(end - begin) >= team_loop_share_below(cfg, team_->size()),
                  [&](std::size_t b, std::size_t e) { body(Index(b), Index(e)); });
      return;
    }
    run_range(begin, end, parallel_, cfg, k_.partitioners[slot], body);
  }

  /// Stored positions [begin, end) of `type`, a color: under the block schedule on a team, each member takes the
  /// constraints filed under its own blocks (those of its interior tasks); under the colors schedule on a team,
  /// range() cut at the color's particle cuts (`cuts`); otherwise range().
  template <class Body>
  void color(const TypeStore<Real>& type, Index begin, Index end, const Index* cuts, std::size_t slot, const Body& body) {
    if (team_ && !blocks_) return blocks_range(begin, end, 1, config_, slot, body, cuts);
    if (!team_ || !blocks_ || !share_interiors_ || type.num_blocks() == 0) return range(begin, end, config_, slot, body);
    const Index members = Index(team_->size()), blocks = m_.num_blocks;
    const Index tasks = interior_tasks(blocks, chains_);
    const std::span<const std::uint32_t> block(m_.block);
    auto start = [&](int r) -> std::size_t {  // first constraint filed under member r's first block
      const std::uint32_t first = std::uint32_t(task_begin(Index(std::uint64_t(tasks) * Index(r) / members), tasks, blocks));
      return std::size_t(type.boundary_start(begin, end, first, m_.fixed, block));
    };
    // Small blocks: each member takes its own blocks' part of every boundary color, whose particles it keeps in its
    // cache (that pays on a cloth of 100², against one member taking the boundary). Large blocks leave a thin
    // boundary, and a barrier costs more than half of a small color (the pig: 25 colors of ~34 tets a sweep): a
    // color too small for a team loop runs on member 0, the others going on to the next shared loop.
    const bool share = interior_items_ >= team_share_below(config_) &&
                       (!large_blocks_ || std::size_t(end - begin) >= team_loop_share_below(config_, team_->size()));
    team_->loop_parts(begin, end, share, start, [&](std::size_t b, std::size_t e) { body(Index(b), Index(e)); });
  }

  /// range() over [begin, end) cut only at multiples of `block` from begin (the inline threshold and grain still
  /// count items). With a color's particle cuts on a team, member r starts near cut ⌊r·kCutParts/members⌉: where the
  /// color's constraints reach member r's share of the particles, so each thread projects the same particles'
  /// constraints in every color.
  template <class Body>
  void blocks_range(Index begin, Index end, Index block, const ParallelConfig& cfg, std::size_t slot,
                    const Body& body, const Index* cuts = nullptr) {
    const Index n = (end - begin + block - 1) / block;
    const ParallelConfig per = per_block(cfg, block);
    auto blocks = [&](std::size_t b, std::size_t e) { body(begin + Index(b) * block, std::min(end, begin + Index(e) * block)); };
    if (cuts && team_ && team_->size() > 1 && std::size_t(n) >= team_loop_share_below(per, team_->size())) {
      const std::size_t members = std::size_t(team_->size());
      auto start = [&](int r) -> std::size_t {
        const std::size_t j = (std::size_t(r) * kCutParts + members / 2) / members;
        return (std::size_t(cuts[j]) + std::size_t(block) / 2) / std::size_t(block);
      };
      team_->loop_parts(0, n, parallel_, start, blocks);
      return;
    }
    range(0, n, per, slot, [&](Index b, Index e) { blocks(b, e); });
  }

  /// How many tasks the interiors of `blocks` blocks run as, at most `cap` blocks each: a multiple of the threads
  /// when there are blocks enough, so that every thread gets the same number of blocks (task_begin cuts them
  /// evenly). Blocks share no movable particle, so the grouping changes only the time.
  Index interior_tasks(Index blocks, Index cap) const {
    const Index threads = team_ ? Index(team_->size())
                          : share_interiors_ ? Index(std::max(1, tbb::this_task_arena::max_concurrency())) : 1;
    const Index tasks = threads * ((blocks + threads * cap - 1) / (threads * cap));
    return std::max<Index>(1, std::min(tasks, blocks));
  }
  /// First block of task t of `tasks` over `blocks` blocks (contiguous runs whose sizes differ by at most one).
  static Index task_begin(Index t, Index tasks, Index blocks) { return Index(std::uint64_t(t) * blocks / tasks); }

  /// The interiors' tasks, task(first, last) over blocks [first, last): one parallel loop (each task's blocks share
  /// no particle with another's, so any cut gives the same bits), or inline when the interiors are small or one
  /// thread runs.
  template <class Task> void interiors(const Task& task) {
    const std::size_t slot = slots(1);
    const Index blocks = m_.num_blocks, tasks = interior_tasks(blocks, chains_);
    auto run = [&](Index t) { task(task_begin(t, tasks, blocks), task_begin(t + 1, tasks, blocks)); };
    if (team_) {
      team_->loop(0, tasks, share_interiors_ && tasks > 1 && interior_items_ >= team_share_below(config_),
                  [&](std::size_t b, std::size_t e) {
                    for (std::size_t t = b; t < e; ++t) run(Index(t));
                  });
      return;
    }
    const bool fork = share_interiors_ && tasks > 1 && tbb::this_task_arena::max_concurrency() > 1 &&
                      interior_items_ >= config_.inline_below;
    if (!fork) {
      for (Index t = 0; t < tasks; ++t) run(t);
      return;
    }
    tbb::parallel_for(
        tbb::blocked_range<Index>(0, tasks, 1),
        [&](const tbb::blocked_range<Index>& r) {
          for (Index t = r.begin(); t < r.end(); ++t) run(t);
        },
        k_.partitioners[slot]);
  }

private:
  const Model<Real>& m_;
  Scratch<Real>& k_;
  bool parallel_;                   // the solver's loops may run on several threads
  bool blocks_;                     // the block schedule
  const ParallelConfig& config_;
  bool large_blocks_;               // large_blocks(): small boundary colors run on one member
  bool share_interiors_;            // the blocks' interiors run on more than one thread
  std::size_t interior_items_ = 0;  // constraints in the blocks' interiors
  Index chains_ = kInterleave;      // most blocks a task of interiors takes
  std::size_t slot_ = 0;            // next partitioner slot of this sweep
  Team::Member* team_ = nullptr;    // the team this copy runs in (nullptr: forks per loop)
};

}  // namespace pbd::detail
