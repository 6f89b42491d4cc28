#include "sim/engine/population.hpp"

#include <Random123/philox.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>

namespace rotleak {

namespace {

/// Philox stream of the split decisions (the initial draws use stream 0).
constexpr std::uint64_t kStreamSplit = 2;
constexpr std::uint64_t kPurposeTurn = 0;  ///< purpose 1 + r: roulette round r

/// Philox words for member `index` of `line` at split `level`, for a purpose.
r123::Philox4x64::ctr_type split_words(std::uint64_t seed, std::uint64_t line, std::uint64_t level, std::uint64_t index,
                                       std::uint64_t purpose) {
  r123::Philox4x64 gen;
  const r123::Philox4x64::key_type key = {{seed, kStreamSplit}};
  const r123::Philox4x64::ctr_type ctr = {{line, level, index, purpose}};
  return gen(ctr, key);
}

class ChaoticSplit final : public SplitRule {
 public:
  ChaoticSplit(double r, double half_d, double p_bb) : r_(r), half_d_(half_d), p_bb_(p_bb) {}
  int copies(const Member& m) const override {
    const bool straight = (m.ps.q.y == r_ || m.ps.q.y == -r_) && std::abs(m.ps.q.x) <= half_d_;
    return straight && std::abs(m.ps.v.x) < p_bb_ ? 1 : 2;
  }
  std::string name() const override { return "chaotic"; }

 private:
  double r_, half_d_, p_bb_;
};

/// Every member splits: the rule on a table other than the stadium (no bouncing-ball family singled out).
class SplitAll final : public SplitRule {
 public:
  int copies(const Member&) const override { return 2; }
  std::string name() const override { return "all"; }
};

/// v turned by theta (cos c, sin s), the sign of theta flipped where the turn would carry v across the boundary's
/// tangent at a member on the boundary (n its normal there; n = 0: not on the boundary).
Vec2<double> turned_about(const Vec2<double>& v0, double c, double s, const Vec2<double>& n) {
  Vec2<double> v{v0.x * c - v0.y * s, v0.x * s + v0.y * c};
  const double before = v0.x * n.x + v0.y * n.y, after = v.x * n.x + v.y * n.y;
  if ((before > 0 && after <= 0) || (before < 0 && after >= 0)) v = {v0.x * c + v0.y * s, -v0.x * s + v0.y * c};
  return v;
}

/// The copy's direction: v turned by theta, the sign of theta flipped where the turn would point a
/// boundary member out of the stadium (a graze within theta of the tangent).
Vec2<double> turned(const ParticleState<double>& ps, double theta, double r, double half_d) {
  Vec2<double> n{0, 0};  // inward normal where the member sits on the boundary
  if (std::abs(ps.q.x) <= half_d && (ps.q.y == r || ps.q.y == -r))
    n = {0, ps.q.y > 0 ? -1.0 : 1.0};
  else if (std::abs(ps.q.x) > half_d)
    n = {(ps.q.x > 0 ? half_d : -half_d) - ps.q.x, -ps.q.y};
  return turned_about(ps.v, std::cos(theta), std::sin(theta), n);
}

/// The same on any table: a member within the table's slack of a piece (it sits at a collision) keeps to the side
/// of that piece's tangent it points to; one inside the table (a flow start) turns freely.
Vec2<double> turned(const ParticleState<double>& ps, double theta, const Table<double>& table) {
  const auto [k, d] = table.piece_nearest(ps.q);
  Vec2<double> n{0, 0};
  if (d <= table.slack()) {
    const Vec2<double> tg = table.tangent(k, ps.q);
    n = {tg.y, -tg.x};
  }
  return turned_about(ps.v, std::cos(theta), std::sin(theta), n);
}

/// One line's living weight as a function of time, booked as it changes: members alive (in flight,
/// or ended alive: survived to t_max or stuck) counted by level, so the weight w0 sum 2^-level is
/// evaluated from exact counts in one fixed order, whatever order its members were run in.
class LineBook {
 public:
  LineBook(double w0, std::size_t points) : w0_(w0), points_(points), y_(w0) { count_[0] = 1; }

  void add(int level, long n) {
    auto& c = count_[level];
    c = static_cast<std::uint64_t>(static_cast<long>(c) + n);
    if (c == 0) count_.erase(level);
  }
  bool dead() const { return count_.empty(); }

  /// The weight changed at grid index g (it applies from t_g on): the stretch before it is booked.
  void changed(std::size_t g, LinesEstimator& e) {
    const double y = value();
    if (y == y_) return;  // the open stretch goes on
    if (g == since_) {    // two changes in one cell: only the last is seen on the grid
      y_ = y;
      return;
    }
    e.stretch(since_, g, y_, w0_);
    y_ = y;
    since_ = g;
  }
  /// The line is over (no member in flight): its last stretch runs to the end of the grid.
  void close(LinesEstimator& e) { e.stretch(since_, points_, y_, w0_); }

 private:
  double value() const {
    double y = 0;
    for (const auto& [level, n] : count_) y += static_cast<double>(n) * std::ldexp(w0_, -level);
    return y;
  }

  double w0_;
  std::size_t points_;
  std::map<int, std::uint64_t> count_;  ///< members alive by level
  double y_;                            ///< the weight of the open stretch
  std::size_t since_ = 0;               ///< its first grid index
};

/// The lines of ids [lo, hi), level by level: the members advanced to the next split time, then line by
/// line their ends booked (Tally::add_end, in the run's LinesEstimator), the survivors split and thinned.
class LinesRun {
 public:
  LinesRun(const RunPlan& plan, const Sampler& sampler, const SplitRule& rule, std::uint64_t lo, std::uint64_t hi,
           Tally& t, const TableModel<double>* table)
      : scene_(plan.scene()),
        rule_(rule),
        st_(plan.stadium()),
        table_(table),
        lo_(lo),
        t_(t),
        e_(t.as<LinesEstimator>()),
        nbins_(t.escapes_per_bin.size()),
        w0_(hi - lo),
        unsplit_(hi - lo, 1) {
    books_.reserve(hi - lo);
    pop_.reserve(hi - lo);
    for (std::uint64_t id = lo; id < hi; ++id) {
      const InitialDraw d = sampler.draw(id);
      const double w0 = w0_[id - lo] = sampler.weight(d);
      e_.start_line(w0);
      books_.emplace_back(w0, nbins_ + 1);
      pop_.push_back({table ? initial_state(table->table, d) : initial_state(st_, d), 0, id, 0, 0});
    }
  }

  /// Level k's members, their weights and the time they are advanced to (stop()), ready for the engine; false when
  /// no member is left.
  bool prepare(std::uint64_t k) {
    if (pop_.empty()) return false;
    stop_ = std::min(static_cast<double>(k + 1) * scene_.splitting.every, scene_.t_max);
    weights_.resize(pop_.size());
    for (std::size_t i = 0; i < pop_.size(); ++i) weights_[i] = std::ldexp(w0(pop_[i].line), -pop_[i].level);
    ends_.assign(pop_.size(), ParticleEnd{});
    return true;
  }
  const std::vector<Member>& members() const { return pop_; }
  const std::vector<double>& weights() const { return weights_; }
  std::vector<ParticleEnd>& ends() { return ends_; }
  double stop() const { return stop_; }

  /// Level k's ends (ends(), by member) booked line by line; the survivors split and thinned into level k + 1.
  void book(std::uint64_t k) {
    const bool last = !(stop_ < scene_.t_max);
    next_.clear();
    for (std::size_t a = 0; a < pop_.size();) {  // line by line (members are sorted by line, then index)
      std::size_t b = a;
      while (b < pop_.size() && pop_[b].line == pop_[a].line) ++b;
      book_ends(a, b, last);
      if (!last)
        next_level(a, b, k, stop_);
      else
        books_[pop_[a].line - lo_].close(e_);
      a = b;
    }
    pop_.swap(next_);
    if (!pop_.empty()) e_.levels = std::max(e_.levels, k + 1);
    e_.max_population = std::max<std::uint64_t>(e_.max_population, pop_.size());
  }

  void run(const AdvanceMembers& advance) {
    for (std::uint64_t k = 0; prepare(k); ++k) {
      advance(pop_, weights_, stop_, ends_);
      book(k);
    }
  }

 private:
  double w0(std::uint64_t line) const { return w0_[line - lo_]; }
  std::size_t bin_of(double time) const {
    const auto b = static_cast<std::size_t>(time / scene_.survival_dt);
    return b < nbins_ ? b : nbins_ - 1;
  }
  /// The grid index from which a change at `time` is seen (survivors_on_grid's convention).
  std::size_t grid_of(double time) const { return bin_of(time) + 1; }
  /// The line leaves the unsplit stratum from grid index g on (its member escaped or first split).
  void leave_unsplit(std::uint64_t line, std::size_t g) {
    if (!unsplit_[line - lo_]) return;
    unsplit_[line - lo_] = 0;
    e_.leave_unsplit(g, w0(line));
  }

  /// The ends of one line's members pop_[a, b): each member that ended is booked, and its escapes, in
  /// time order (ties: member order), change the line's weight.
  void book_ends(std::size_t a, std::size_t b, bool last) {
    const std::uint64_t line = pop_[a].line;
    LineBook& book = books_[line - lo_];
    order_.clear();
    for (std::size_t i = a; i < b; ++i) {
      const std::uint64_t made = ends_[i].collisions - pop_[i].collisions;
      if (ends_[i].fate == Fate::survived && !last)
        t_.collisions += made;  // goes on to the next level
      else
        t_.add_end(ends_[i].fate, ends_[i].t, made, weights_[i], scene_.survival_dt);
      if (ends_[i].fate == Fate::escaped) order_.push_back(i);
    }
    std::stable_sort(order_.begin(), order_.end(),
                     [&](std::size_t x, std::size_t y) { return ends_[x].t < ends_[y].t; });
    for (std::size_t i : order_) {
      const std::size_t g = grid_of(ends_[i].t);
      book.add(pop_[i].level, -1);
      book.changed(g, e_);
      leave_unsplit(line, g);
      if (book.dead()) ++e_.lines_ended[g];
    }
  }

  /// The members of one line that reached the split time `stop` (level k + 1): split by the rule, then
  /// thinned to the cap by the roulette; the line's stretch booked, and closed if no member goes on.
  void next_level(std::size_t a, std::size_t b, std::uint64_t k, double stop) {
    const std::uint64_t line = pop_[a].line;
    LineBook& book = books_[line - lo_];
    const std::size_t first = next_.size();
    std::uint64_t index = 0;
    for (std::size_t i = a; i < b; ++i) {
      if (ends_[i].fate != Fate::survived) continue;
      Member m{ends_[i].last, ends_[i].collisions, line, 0, pop_[i].level};
      if (rule_.copies(m) != 2) {
        m.index = index++;
        next_.push_back(m);
        continue;
      }
      leave_unsplit(line, grid_of(stop));
      book.add(m.level, -1);
      ++m.level;
      book.add(m.level, 2);
      Member copy = m;
      m.index = index++;
      copy.index = index++;
      const auto w = split_words(scene_.seed, line, k + 1, copy.index, kPurposeTurn);
      const double theta = scene_.splitting.delta * (2 * InitialConditions::unit(w[0]) - 1);
      copy.ps.v = table_ ? turned(m.ps, theta, table_->table) : turned(m.ps, theta, st_.r(), st_.half_d());
      next_.push_back(m);
      next_.push_back(copy);
      e_.split(bin_of(stop));
    }
    e_.max_line = std::max<std::uint64_t>(e_.max_line, next_.size() - first);
    const bool alive_before_roulette = !book.dead();
    roulette(line, first, k, stop);
    book.changed(grid_of(stop), e_);
    if (alive_before_roulette && book.dead()) ++e_.lines_ended[grid_of(stop)];
    // a line with no member in flight (all escaped, stuck, or removed) closes its last stretch
    if (next_.size() == first) book.close(e_);
  }

  /// While the line (next_ from `first`) has more than cap members, its members are thinned in pairs: in
  /// member order, each member and the next one of its level make a pair, of which one, drawn with
  /// probability 1/2, goes on at twice its weight. The line's weight is kept exactly (w + w = 2 w), not only
  /// in expectation, so a line that sits at the cap level after level does not take a multiplicative random
  /// walk in weight (docs/model.md, "Splitting": that walk made the lines' weights heavy-tailed). A round
  /// that finds no pair (every member on its own level) keeps each member with probability 1/2 at twice its
  /// weight instead. After each round the members are renumbered (next_level numbered them in order already).
  void roulette(std::uint64_t line, std::size_t first, std::uint64_t k, double stop) {
    LineBook& book = books_[line - lo_];
    for (std::uint64_t round = 0; next_.size() - first > scene_.splitting.cap; ++round) {
      const std::size_t n = next_.size() - first;
      drop_.assign(n, 0);
      std::map<int, std::size_t> pending;  // level -> the member waiting for its pair
      bool paired = false;
      for (std::size_t i = 0; i < n; ++i) {
        const int level = next_[first + i].level;
        const auto it = pending.find(level);
        if (it == pending.end()) {
          pending.emplace(level, i);
          continue;
        }
        const std::size_t a = it->second;
        pending.erase(it);
        paired = true;
        const auto w = split_words(scene_.seed, line, k + 1, next_[first + a].index, 1 + round);
        const std::size_t keep = (w[0] & 1) ? a : i;
        drop_[keep == a ? i : a] = 1;
        const double weight = std::ldexp(w0(line), -level);
        e_.roulette(false, weight, bin_of(stop));
        e_.roulette(true, weight, bin_of(stop));
        book.add(level, -2);
        book.add(level - 1, 1);
        --next_[first + keep].level;
      }
      if (!paired) {
        for (std::size_t i = 0; i < n; ++i) {
          Member& m = next_[first + i];
          const auto w = split_words(scene_.seed, line, k + 1, m.index, 1 + round);
          book.add(m.level, -1);
          const bool keep = w[0] & 1;
          e_.roulette(keep, std::ldexp(w0(line), -m.level), bin_of(stop));
          if (keep) {
            --m.level;
            book.add(m.level, 1);
          } else {
            drop_[i] = 1;
          }
        }
      }
      std::size_t kept = first;
      for (std::size_t i = 0; i < n; ++i)
        if (!drop_[i]) next_[kept++] = next_[first + i];
      next_.resize(kept);
      for (std::size_t i = first; i < next_.size(); ++i) next_[i].index = i - first;
    }
  }

  const Scene& scene_;
  const SplitRule& rule_;
  const Stadium<double>& st_;
  const TableModel<double>* table_;  ///< any other table (null: the stadium)
  const std::uint64_t lo_;
  Tally& t_;
  LinesEstimator& e_;
  const std::size_t nbins_;
  std::vector<double> w0_;     ///< each line's starting weight
  std::vector<char> unsplit_;  ///< the line's one member has never split
  std::vector<LineBook> books_;
  std::vector<Member> pop_, next_;
  std::vector<double> weights_;
  std::vector<ParticleEnd> ends_;
  double stop_ = 0;  ///< the level's split time (or t_max)
  std::vector<std::size_t> order_;
  std::vector<char> drop_;  ///< the roulette's removals in one round, by member position
};

}  // namespace

std::unique_ptr<SplitRule> make_split_rule(const Scene& scene, const Stadium<double>& st) {
  if (scene.splits_every_member()) return std::make_unique<SplitAll>();
  return std::make_unique<ChaoticSplit>(st.r(), st.half_d(), scene.sampling.p_max);
}

void run_lines(const RunPlan& plan, const Sampler& sampler, const SplitRule& rule, std::uint64_t lo, std::uint64_t hi,
               const AdvanceMembers& advance, Tally& t, const TableModel<double>* table) {
  LinesRun(plan, sampler, rule, lo, hi, t, table).run(advance);
}

void run_lines_together(const RunPlan& plan, const Sampler& sampler, const SplitRule& rule,
                        const std::vector<std::pair<std::uint64_t, std::uint64_t>>& ranges,
                        const AdvanceMembers& advance, Tally& t, const TableModel<double>* table) {
  // range r is started, prepared and booked by thread r % threads into that thread's tally, merged into t at the
  // end (exact merges: the same t for any thread count)
  const auto n = static_cast<std::int64_t>(ranges.size());
  const int threads = std::max(1, std::min(omp_get_max_threads(), static_cast<int>(n)));
  std::vector<Tally> part(static_cast<std::size_t>(threads));
  for (Tally& p : part) p.resize(plan.scene());
  std::vector<std::unique_ptr<LinesRun>> runs(ranges.size());
  const auto each = [&](auto&& f) {  // f(r) for every range, on the thread that owns it
#pragma omp parallel num_threads(threads)
    for (std::int64_t r = omp_get_thread_num(); r < n; r += threads) f(static_cast<std::size_t>(r));
  };
  each([&](std::size_t r) {
    const auto& [lo, hi] = ranges[r];
    runs[r] = std::make_unique<LinesRun>(plan, sampler, rule, lo, hi, part[r % part.size()], table);
  });
  std::vector<Member> members;
  std::vector<double> weights;
  std::vector<ParticleEnd> ends;
  std::vector<char> live(ranges.size());
  std::vector<std::size_t> at(ranges.size() + 1);
  for (std::uint64_t k = 0;; ++k) {
    each([&](std::size_t r) { live[r] = runs[r]->prepare(k); });
    double stop = 0;
    for (std::size_t r = 0; r < runs.size(); ++r) {  // the ranges' members one after the other
      at[r + 1] = at[r] + (live[r] ? runs[r]->members().size() : 0);
      if (live[r]) stop = runs[r]->stop();  // the same for every range: level k's split time
    }
    if (at.back() == 0) break;
    members.resize(at.back()), weights.resize(at.back());
    each([&](std::size_t r) {
      if (!live[r]) return;
      std::copy(runs[r]->members().begin(), runs[r]->members().end(),
                members.begin() + static_cast<std::ptrdiff_t>(at[r]));
      std::copy(runs[r]->weights().begin(), runs[r]->weights().end(),
                weights.begin() + static_cast<std::ptrdiff_t>(at[r]));
    });
    ends.assign(members.size(), ParticleEnd{});
    advance(members, weights, stop, ends);
    each([&](std::size_t r) {
      if (!live[r]) return;
      std::copy_n(ends.begin() + static_cast<std::ptrdiff_t>(at[r]), runs[r]->ends().size(), runs[r]->ends().begin());
      runs[r]->book(k);
    });
  }
  for (const Tally& p : part) t.merge(p);
}

}  // namespace rotleak
