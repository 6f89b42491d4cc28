// Population splitting in time, so that P(t) can be followed through tens of decades: the ids of a
// block start one line each; every split_every time units each member of a line that the split rule
// picks becomes two of half its weight, the copy's direction turned by an angle in [-delta, delta]
// drawn from (seed, line, level, member index). Weight is conserved at every split, and the roulette
// that caps a line's members (in pairs: one of two goes on at twice its weight) conserves it too, so
// P(t) = (1/N) sum_i Y_i(t) stays unbiased,
// with Y_i(t) the living weight of line i; the lines are independent, and the spread of the Y_i is
// P's error.
//
// A block's lines run breadth first: all members are advanced to the next split time by the engine
// that runs the scene (the vectorised kernel with its fast-forward, or the scalar core), in any order,
// their ends stored by member position; then, line by line in member order, escapes are booked in time
// order, the split rule and the roulette applied, and the next level's members numbered. Nothing
// depends on which engine, lane width or thread ran a member, so the output is byte-identical for any
// of them, and a block is still the unit of threads, ranks, checkpoints and shards.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/engine/plan.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/sampling.hpp"
#include "sim/tally/tally.hpp"

namespace rotleak {

/// One particle of a line at a split time: its state at its last collision before that time (or its
/// creation), its weight w0 2^-level (w0 the starting particle's sampling weight), and its place.
struct Member {
  ParticleState<double> ps;
  std::uint64_t collisions = 0;
  std::uint64_t line = 0;   ///< the starting particle's id
  std::uint64_t index = 0;  ///< rank among the line's members at this level (their canonical order)
  int level = 0;            ///< weight = w0 2^-level
};

/// Which members split, and into how many. A rule by region or by an importance function is another
/// class, not another branch in the population engine.
class SplitRule {
 public:
  virtual ~SplitRule() = default;
  /// 1: the member goes on alone; 2: it and a turned copy go on with half its weight each.
  virtual int copies(const Member& m) const = 0;
  virtual std::string name() const = 0;
};

/// The scene's rule: every member splits in two but those in a bouncing-ball stretch -- on a
/// straight edge with |v_x| < p_bb (the mupo scheme's p_max, 0.05 by default) -- whose copies would
/// stay together for thousands of time units and whose number would grow with the algebraic tail.
/// On any other table (Scene::on_table) every member splits in two ("all").
std::unique_ptr<SplitRule> make_split_rule(const Scene& scene, const Stadium<double>& st);

/// Advances every member to `stop` (a split time, or t_max): ends[i] is member i's end; a member that
/// reaches `stop` ends as survived with its state at its last collision before it (ParticleEnd::last).
using AdvanceMembers = std::function<void(const std::vector<Member>& members, const std::vector<double>& weights,
                                          double stop, std::vector<ParticleEnd>& ends)>;

/// Runs the lines of ids [lo, hi) of the plan's scene to t_max and books them in t: every member's end through
/// Tally::add_end, the lines' weights and the split statistics in its LinesEstimator. table: the model of any other
/// table than the stadium (its starts and the copies' turns), null for the stadium.
void run_lines(const RunPlan& plan, const Sampler& sampler, const SplitRule& rule, std::uint64_t lo, std::uint64_t hi,
               const AdvanceMembers& advance, Tally& t, const TableModel<double>* table = nullptr);

/// run_lines for each range of lines [lo, hi), level by level together: at each split time every range's members go
/// to `advance` as one population (range after range), so that a device advances them in one launch; each range is
/// booked as run_lines books it, into the same t (whose counts, exact sums and maxima take them in any order), so
/// the tallies are those of run_lines called range by range.
void run_lines_together(const RunPlan& plan, const Sampler& sampler, const SplitRule& rule,
                        const std::vector<std::pair<std::uint64_t, std::uint64_t>>& ranges,
                        const AdvanceMembers& advance, Tally& t, const TableModel<double>* table = nullptr);

}  // namespace rotleak
