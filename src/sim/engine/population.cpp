#include "sim/engine/population.hpp"

#include <Random123/philox.h>

#include <algorithm>
#include <cmath>
#include <map>
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

/// The copy's direction: v turned by theta, the sign of theta flipped where the turn would point a
/// boundary member out of the stadium (a graze within theta of the tangent).
Vec2<double> turned(const ParticleState<double>& ps, double theta, double r, double half_d) {
  const double c = std::cos(theta), s = std::sin(theta);
  Vec2<double> v{ps.v.x * c - ps.v.y * s, ps.v.x * s + ps.v.y * c};
  Vec2<double> n{0, 0};  // inward normal where the member sits on the boundary
  if (std::abs(ps.q.x) <= half_d && (ps.q.y == r || ps.q.y == -r))
    n = {0, ps.q.y > 0 ? -1.0 : 1.0};
  else if (std::abs(ps.q.x) > half_d)
    n = {(ps.q.x > 0 ? half_d : -half_d) - ps.q.x, -ps.q.y};
  const double before = ps.v.x * n.x + ps.v.y * n.y, after = v.x * n.x + v.y * n.y;
  if ((before > 0 && after <= 0) || (before < 0 && after >= 0)) v = {ps.v.x * c + ps.v.y * s, -ps.v.x * s + ps.v.y * c};
  return v;
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
  void changed(std::size_t g, Tally& t) {
    const double y = value();
    if (y == y_) return;  // the open stretch goes on
    if (g == since_) {    // two changes in one cell: only the last is seen on the grid
      y_ = y;
      return;
    }
    book(g, t);
    y_ = y;
    since_ = g;
  }
  /// The line is over (no member in flight): its last stretch runs to the end of the grid.
  void close(Tally& t) { book(points_, t); }

 private:
  double value() const {
    double y = 0;
    for (const auto& [level, n] : count_) y += static_cast<double>(n) * std::ldexp(w0_, -level);
    return y;
  }
  void book(std::size_t end, Tally& t) {
    if (y_ > 0 && since_ < points_ && end > since_) {
      t.line_in[since_].add(y_);
      t.line2_in[since_].add_square(y_);
      if (end < points_) {
        t.line_out[end].add(y_);
        t.line2_out[end].add_square(y_);
      }
    }
  }

  double w0_;
  std::size_t points_;
  std::map<int, std::uint64_t> count_;  ///< members alive by level
  double y_;                            ///< the weight of the open stretch
  std::size_t since_ = 0;               ///< its first grid index
};

}  // namespace

std::unique_ptr<SplitRule> make_split_rule(const Scene& scene) {
  const Stadium<double> st(scene.d, scene.r);
  return std::make_unique<ChaoticSplit>(st.r(), st.half_d(), scene.sampling.p_max);
}

void run_lines(const Scene& scene, const Sampler& sampler, const SplitRule& rule, std::uint64_t lo, std::uint64_t hi,
               const AdvanceMembers& advance, Tally& t) {
  const Stadium<double> st(scene.d, scene.r);
  const double dt = scene.survival_dt;
  const std::size_t nbins = t.escapes_per_bin.size(), points = nbins + 1;
  const auto bin_of = [&](double time) {
    const auto b = static_cast<std::size_t>(time / dt);
    return b < nbins ? b : nbins - 1;
  };
  // the grid index from which a change at `time` is seen (survivors_on_grid's convention)
  const auto grid_of = [&](double time) { return bin_of(time) + 1; };

  std::vector<LineBook> books;
  std::vector<double> w0(hi - lo);
  std::vector<char> unsplit(hi - lo, 1);  // the line's one member has never split
  // a line leaves the unsplit stratum from grid index g on (its member escaped or first split)
  const auto leave_unsplit = [&](std::uint64_t line, std::size_t g) {
    if (!unsplit[line - lo]) return;
    unsplit[line - lo] = 0;
    const double w = w0[line - lo];
    t.unsplit_left[g * kUnsplitClasses + static_cast<std::uint64_t>(unsplit_class(w))].add(w);
  };
  std::vector<Member> pop;
  books.reserve(hi - lo);
  pop.reserve(hi - lo);
  for (std::uint64_t id = lo; id < hi; ++id) {
    const InitialDraw d = sampler.draw(id);
    w0[id - lo] = sampler.weight(d);
    t.w_start.add(w0[id - lo]);
    t.unsplit_start[static_cast<std::size_t>(unsplit_class(w0[id - lo]))].add(w0[id - lo]);
    books.emplace_back(w0[id - lo], points);
    pop.push_back({initial_state(st, d), 0, id, 0, 0});
  }
  std::vector<double> weights;
  std::vector<ParticleEnd> ends;
  std::vector<Member> next;
  std::vector<std::size_t> order;
  for (std::uint64_t k = 0; !pop.empty(); ++k) {
    const double stop = std::min(static_cast<double>(k + 1) * scene.splitting.every, scene.t_max);
    const bool last = !(stop < scene.t_max);
    weights.resize(pop.size());
    for (std::size_t i = 0; i < pop.size(); ++i) weights[i] = std::ldexp(w0[pop[i].line - lo], -pop[i].level);
    ends.assign(pop.size(), ParticleEnd{});
    advance(pop, weights, stop, ends);
    next.clear();
    // line by line (members are sorted by line, then index)
    for (std::size_t a = 0; a < pop.size();) {
      std::size_t b = a;
      while (b < pop.size() && pop[b].line == pop[a].line) ++b;
      const std::uint64_t line = pop[a].line;
      LineBook& book = books[line - lo];
      // escapes in time order (ties: member order), each a change of the line's weight
      order.clear();
      for (std::size_t i = a; i < b; ++i) {
        t.collisions += ends[i].collisions - pop[i].collisions;
        if (ends[i].fate == Fate::escaped) {
          order.push_back(i);
          t.w_escaped.add(weights[i]);
        }
        if (ends[i].fate == Fate::stuck) ++t.stuck;
        if (ends[i].fate == Fate::survived && last) ++t.survived;
        if (ends[i].fate == Fate::stuck || (ends[i].fate == Fate::survived && last)) t.w_alive_end.add(weights[i]);
      }
      std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return ends[x].t < ends[y].t; });
      for (std::size_t i : order) {
        ++t.escapes_per_bin[bin_of(ends[i].t)];
        ++t.escaped;
        book.add(pop[i].level, -1);
        book.changed(grid_of(ends[i].t), t);
        leave_unsplit(line, grid_of(ends[i].t));
        if (book.dead()) ++t.lines_ended[grid_of(ends[i].t)];
      }
      if (!last) {
        // the members that reached the split time: split by the rule, then thinned to the cap
        const std::size_t first = next.size();
        std::uint64_t index = 0;
        for (std::size_t i = a; i < b; ++i) {
          if (ends[i].fate != Fate::survived) continue;
          Member m{ends[i].last, ends[i].collisions, line, 0, pop[i].level};
          if (rule.copies(m) == 2) {
            leave_unsplit(line, grid_of(stop));
            book.add(m.level, -1);
            ++m.level;
            book.add(m.level, 2);
            Member copy = m;
            m.index = index++;
            copy.index = index++;
            const auto w = split_words(scene.seed, line, k + 1, copy.index, kPurposeTurn);
            const double theta = scene.splitting.delta * (2 * InitialConditions::unit(w[0]) - 1);
            copy.ps.v = turned(m.ps, theta, st.r(), st.half_d());
            next.push_back(m);
            next.push_back(copy);
            ++t.splits;
            ++t.born_per_bin[bin_of(stop)];
          } else {
            m.index = index++;
            next.push_back(m);
          }
        }
        t.max_line = std::max<std::uint64_t>(t.max_line, next.size() - first);
        const bool alive_before_roulette = !book.dead();
        // roulette: while the line has more than cap members, each is kept with probability 1/2 at
        // twice its weight (the line's weight is kept in expectation)
        for (std::uint64_t round = 0; next.size() - first > scene.splitting.cap; ++round) {
          std::size_t kept = first;
          for (std::size_t i = first; i < next.size(); ++i) {
            Member& m = next[i];
            const auto w = split_words(scene.seed, line, k + 1, m.index, 1 + round);
            book.add(m.level, -1);
            const double weight = std::ldexp(w0[line - lo], -m.level);
            if (w[0] & 1) {
              t.w_gained.add(weight);
              --m.level;
              book.add(m.level, 1);
              next[kept++] = m;
            } else {
              t.w_removed.add(weight);
              ++t.culls;
              ++t.culled_per_bin[bin_of(stop)];
            }
          }
          next.resize(kept);
        }
        for (std::size_t i = first; i < next.size(); ++i) next[i].index = i - first;
        book.changed(grid_of(stop), t);
        if (alive_before_roulette && book.dead()) ++t.lines_ended[grid_of(stop)];
        // a line with no member in flight (all escaped, stuck, or removed) closes its last stretch
        if (next.size() == first) book.close(t);
      } else {
        book.close(t);
      }
      a = b;
    }
    pop.swap(next);
    if (!pop.empty()) t.levels = std::max(t.levels, k + 1);
    t.max_population = std::max<std::uint64_t>(t.max_population, pop.size());
  }
}

}  // namespace rotleak
