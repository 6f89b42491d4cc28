#include "sim/engine/ic_splitting.hpp"

#include <Random123/philox.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "geometry/stadium.hpp"
#include "numeric/tiers.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

namespace {

/// The Philox stream of the sampler's draws (InitialConditions' are 0, the split copies' their own).
constexpr std::uint64_t kStreamIcSplit = 0x1c5;
/// The pilot's replicate index in the counter: no replicate's.
constexpr std::uint64_t kPilot = ~std::uint64_t(0);

double unit(std::uint64_t bits) { return InitialConditions::unit(bits); }

/// Four uniform doubles for draw `k` of chain `chain` of stage `stage` of replicate r.
void words(std::uint64_t seed, std::uint64_t r, std::uint64_t stage, std::uint64_t chain, std::uint64_t k, double* u) {
  r123::Philox4x64 gen;
  const r123::Philox4x64::key_type key = {{seed, kStreamIcSplit}};
  const r123::Philox4x64::ctr_type ctr = {{r, stage, chain, k}};
  const auto w = gen(ctr, key);
  for (int i = 0; i < 4; ++i) u[i] = unit(w[i]);
}

/// A start whose escape time is known: what a stage holds.
struct State {
  IcPoint x;
  double T = 0;
  int thin = 0;              ///< roulette halvings on its way: it stands for 2^thin states
  std::uint64_t origin = 0;  ///< the stage-0 start its chain descends from (the genealogy's diagnostic)
};

struct Stage {
  std::vector<State> states;
  std::uint64_t collisions = 0, stuck = 0, proposals = 0, accepted = 0;
  /// By halving j: the accepted moves that changed T by more than `moved_by` (what a window is centred on)
  std::vector<std::uint64_t> moved;
};

/// A move "moved" where it changed T by more than this (one time unit: another escape, not the same one shifted by
/// the step in tau), or by more than the last gap between two levels where that is less (near a supremum of T,
/// where the levels close in and every move changes T by less than a time unit).
constexpr double kMoved = 1;

IcEnd timed(const EscapeClock& clock, const IcPoint& x, Stage& st) {
  const IcEnd e = clock(x);
  st.collisions += e.collisions;
  st.stuck += e.stuck ? 1 : 0;
  return e;
}

/// The threads a stage runs on: spec.threads, or OpenMP's default.
int stage_threads(const IcSplitSpec& spec) { return spec.threads > 0 ? spec.threads : omp_get_max_threads(); }

/// Stage 0: `spec.starts` independent draws.
Stage first_stage(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, std::uint64_t seed,
                  std::uint64_t r) {
  const std::uint64_t n = spec.starts;
  const int threads = stage_threads(spec);
  Stage out;
  out.states.resize(n);
  std::vector<Stage> by_thread(static_cast<std::size_t>(threads));
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
  for (std::uint64_t i = 0; i < n; ++i) {
    Stage& mine = by_thread[static_cast<std::size_t>(omp_get_thread_num())];
    double u[4];
    words(seed, r, 0, i, 0, u);
    const IcPoint x = stratum.at(u[0], u[1], u[2]);
    out.states[i] = {x, timed(clock, x, mine).t, 0, i};
  }
  for (const Stage& s : by_thread) out.collisions += s.collisions, out.stuck += s.stuck;
  return out;
}

/// The range of s - drift tau (packed, mod the s length) over the elites: the length of the circle less its largest
/// gap between two of them (the s length where they are all at one value, or drift is 0).
double circular_range(const IcStratum& stratum, const Stage& st, const std::vector<std::size_t>& elites) {
  const double L = stratum.s_length();
  if (stratum.drift == 0 || elites.size() < 2) return L;
  std::vector<double> v;
  v.reserve(elites.size());
  for (std::size_t k : elites) {
    const IcPoint& x = st.states[k].x;
    const double a = stratum.s_packed(x.s) - stratum.drift * x.tau;
    v.push_back(a - L * std::floor(a / L));
  }
  std::sort(v.begin(), v.end());
  double gap = L - v.back() + v.front();
  for (std::size_t i = 1; i < v.size(); ++i) gap = std::max(gap, v[i] - v[i - 1]);
  return L - gap > 0 ? L - gap : L;
}

/// The extents of the starts `elites` of `st` in each coordinate (the stratum's where they all sit at one value): a
/// level's scales in the pilot.
IcScales extents(const IcStratum& stratum, const Stage& st, const std::vector<std::size_t>& elites) {
  IcScales sc;
  sc.s = stratum.s_length(), sc.p = stratum.p_length(), sc.tau = stratum.tau_hi - stratum.tau_lo;
  if (elites.size() < 2) return sc;
  const auto coords = [&](std::size_t k) {
    const IcPoint& x = st.states[elites[k]].x;
    return std::array<double, 3>{stratum.s_packed(x.s), stratum.p_packed(x.p), x.tau};
  };
  std::array<double, 3> lo = coords(0), hi = lo;
  for (std::size_t k = 1; k < elites.size(); ++k) {
    const std::array<double, 3> c = coords(k);
    for (std::size_t i = 0; i < 3; ++i) lo[i] = std::min(lo[i], c[i]), hi[i] = std::max(hi[i], c[i]);
  }
  if (hi[0] > lo[0]) sc.s = hi[0] - lo[0];
  if (hi[1] > lo[1]) sc.p = hi[1] - lo[1];
  if (hi[2] > lo[2]) sc.tau = hi[2] - lo[2];
  sc.u = circular_range(stratum, st, elites);
  return sc;
}

/// The starts of `st` that outlive `level`, in order.
std::vector<std::size_t> outliving(const Stage& st, double level) {
  std::vector<std::size_t> e;
  for (std::size_t i = 0; i < st.states.size(); ++i)
    if (st.states[i].T > level) e.push_back(i);
  return e;
}

/// Stage j + 1 from the starts `elites` of stage j (those that outlive `level`): a chain of length[k] states from
/// elite k, its moves accepted where the proposal lies in the stratum and outlives the level (Metropolis for the
/// uniform law on {T > level} with a symmetric proposal).
Stage next_stage(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, const Stage& before,
                 const std::vector<std::size_t>& elites, const std::vector<std::uint64_t>& length, double level,
                 const IcScales& scales, std::uint64_t stage, std::uint64_t seed, std::uint64_t r,
                 const IcPropose& propose, double moved_by = kMoved) {
  std::vector<std::uint64_t> at_k(elites.size() + 1, 0);
  for (std::size_t k = 0; k < elites.size(); ++k) at_k[k + 1] = at_k[k] + length[k];
  if (at_k.back() > kIcPopulationCap * spec.starts)
    throw std::runtime_error("splitting over initial conditions: a stage of " + std::to_string(at_k.back()) +
                             " starts past level " + std::to_string(level) + ", more than " +
                             std::to_string(kIcPopulationCap) + " times the " + std::to_string(spec.starts) +
                             " of stage 0: the levels are closer than the pilot saw them (more starts)");
  const int threads = stage_threads(spec);
  const auto halvings = static_cast<std::size_t>(std::max(0, scales.halvings)) + 1;
  Stage out;
  out.states.resize(at_k.back());
  out.moved.assign(halvings, 0);
  std::vector<Stage> by_thread(static_cast<std::size_t>(threads));
  for (Stage& s : by_thread) s.moved.assign(halvings, 0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < elites.size(); ++k) {
    Stage& mine = by_thread[static_cast<std::size_t>(omp_get_thread_num())];
    State at = before.states[elites[k]];
    for (std::uint64_t j = 0; j < length[k]; ++j) {
      for (int move = 0; move < spec.moves; ++move) {
        double u[4];
        words(seed, r, stage, k, j * static_cast<std::uint64_t>(spec.moves) + static_cast<std::uint64_t>(move), u);
        const IcPoint y = propose(stratum, scales, at.x, u);
        ++mine.proposals;
        if (stratum.contains(y)) {
          const double T = timed(clock, y, mine).t;
          if (T > level) {
            if (std::abs(T - at.T) > moved_by)
              ++mine.moved[static_cast<std::size_t>(std::max(0, ic_move(stratum, scales, u[0]).halving))];
            at.x = y, at.T = T, ++mine.accepted;
          }
        }
      }
      out.states[at_k[k] + j] = at;
    }
  }
  for (const Stage& s : by_thread) {
    out.collisions += s.collisions, out.stuck += s.stuck, out.proposals += s.proposals, out.accepted += s.accepted;
    for (std::size_t j = 0; j < halvings; ++j) out.moved[j] += s.moved[j];
  }
  return out;
}

/// Fixed effort: n states from e elites, floor(n / e) each and one more for the first n mod e.
std::vector<std::uint64_t> even_lengths(std::size_t elites, std::uint64_t n) {
  std::vector<std::uint64_t> l(elites, elites ? n / elites : 0);
  for (std::size_t k = 0; k < elites && k < n % elites; ++k) ++l[k];
  return l;
}

/// Splitting factor f: floor(f) or floor(f) + 1 states from each elite, the latter with probability frac(f) (drawn
/// from counter word 3 = ~0, no chain step's), so that each elite's expected length is f exactly.
std::vector<std::uint64_t> random_lengths(std::size_t elites, double f, std::uint64_t seed, std::uint64_t r,
                                          std::uint64_t stage) {
  const double whole = std::floor(f), frac = f - whole;
  std::vector<std::uint64_t> l(elites, static_cast<std::uint64_t>(whole));
  for (std::size_t k = 0; k < elites; ++k) {
    double u[4];
    words(seed, r, stage, k, ~std::uint64_t(0), u);
    if (u[0] < frac) ++l[k];
  }
  return l;
}

/// Elites past a stage's budget (kIcThinAbove starts after splitting) thinned by roulette: each kept with probability
/// 1/2 and then standing for twice as many, pass after pass (counter word 3 = ~1 - pass), until within it. Each
/// elite's expected weight is kept, so the estimator stays unbiased; its states count 2^-thin each.
void thin_elites(std::vector<std::size_t>& e, Stage& st, double factor, std::uint64_t budget, std::uint64_t seed,
                 std::uint64_t r, std::uint64_t stage) {
  // never past one elite: a pass forced on a lone elite until it is gone would kill it with probability 1 (a budget
  // below one elite's chain, starts < factor), where roulette must keep its expected weight
  for (std::uint64_t pass = 0; e.size() > 1 && static_cast<double>(e.size()) * factor > static_cast<double>(budget);
       ++pass) {
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < e.size(); ++k) {
      double u[4];
      words(seed, r, stage, e[k], ~std::uint64_t(1) - pass, u);
      if (u[0] < 0.5) kept.push_back(e[k]), ++st.states[e[k]].thin;
    }
    e.swap(kept);
  }
}

/// The distinct stage-0 starts a stage's states descend from.
std::uint64_t ancestors(const Stage& st) {
  std::vector<std::uint64_t> o;
  o.reserve(st.states.size());
  for (const State& s : st.states) o.push_back(s.origin);
  std::sort(o.begin(), o.end());
  return static_cast<std::uint64_t>(std::unique(o.begin(), o.end()) - o.begin());
}

/// The T that a share 1 / factor of the states outlive (the largest such T among them), or t_max when at least
/// that share survives.
double quantile_level(const Stage& st, int factor, double t_max) {
  std::vector<double> T;
  T.reserve(st.states.size());
  for (const State& s : st.states) T.push_back(s.T);
  const std::size_t keep = std::max<std::size_t>(1, T.size() / static_cast<std::size_t>(factor));
  std::nth_element(T.begin(), T.end() - static_cast<std::ptrdiff_t>(keep), T.end());
  const double q = *(T.end() - static_cast<std::ptrdiff_t>(keep));
  // the level is just below the keep-th largest T: those `keep` outlive it
  return q >= t_max ? t_max : std::nextafter(q, 0.0);
}

}  // namespace

double IcSplitRun::unresolved_from() const {
  for (std::size_t j = 0; j < scales.size() && j < levels.size(); ++j)
    if (!scales[j].resolved(stratum, j >= handover ? ic_tier_bits(spec.deep_tier) : 53)) return levels[j];
  return std::numeric_limits<double>::infinity();
}

double IcSplitRun::P(std::size_t r, std::size_t i) const {
  const IcReplicate& rep = replicates[r];
  double d = static_cast<double>(spec.starts);
  for (int j = 0; j < rep.stage[i]; ++j) d *= factors[static_cast<std::size_t>(j)];
  return rep.alive_w[i] / d;
}

double IcSplitRun::mean(std::size_t i) const {
  double sum = 0;
  for (std::size_t r = 0; r < replicates.size(); ++r) sum += P(r, i);
  return sum / static_cast<double>(replicates.size());
}

double IcSplitRun::error(std::size_t i) const {
  const std::size_t n = replicates.size();
  if (n < 2) return 0;
  const double m = mean(i);
  double ss = 0;
  for (std::size_t r = 0; r < n; ++r) ss += (P(r, i) - m) * (P(r, i) - m);
  return std::sqrt(ss / static_cast<double>(n - 1) / static_cast<double>(n));
}

int IcSplitRun::nonzero(std::size_t i) const {
  int k = 0;
  for (const IcReplicate& rep : replicates) k += rep.alive[i] > 0 ? 1 : 0;
  return k;
}

IcSplitRun::LevelChains IcSplitRun::chains(std::size_t k) const {
  LevelChains c;
  std::uint64_t sum = 0;
  for (const IcReplicate& r : replicates)
    if (k + 1 < r.ancestors.size()) {
      c.proposals += r.stage_proposals[k + 1], c.accepted += r.stage_accepted[k + 1];
      c.fewest = c.reached ? std::min(c.fewest, r.ancestors[k + 1]) : r.ancestors[k + 1];
      sum += r.ancestors[k + 1], ++c.reached;
    }
  if (c.reached) c.mean_ancestors = static_cast<double>(sum) / static_cast<double>(c.reached);
  return c;
}

std::pair<std::uint64_t, double> IcSplitRun::fewest_ancestors() const {
  std::pair<std::uint64_t, double> out{0, 0};
  for (const IcReplicate& x : replicates)
    for (std::size_t k = 1; k < x.ancestors.size() && k <= levels.size(); ++k)
      if (out.first == 0 || x.ancestors[k] < out.first) out = {x.ancestors[k], levels[k - 1]};
  return out;
}

std::uint64_t IcSplitRun::collisions() const {
  std::uint64_t c = pilot_collisions;
  for (const IcReplicate& rep : replicates) c += rep.collisions;
  return c;
}

namespace {

/// The hand-over to the deep clock at `level`: the starts `e` of `st` outliving it in double timed again by `deep`,
/// those it finds not to outlive it dropped. Returns the collisions; counts the starts and the disagreements.
std::uint64_t hand_over(const EscapeClock& deep, const IcSplitSpec& spec, Stage& st, std::vector<std::size_t>& e,
                        double level, std::uint64_t& handed, std::uint64_t& disagreed) {
  const int threads = stage_threads(spec);
  std::vector<Stage> by_thread(static_cast<std::size_t>(threads));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < e.size(); ++k) {
    Stage& mine = by_thread[static_cast<std::size_t>(omp_get_thread_num())];
    State& x = st.states[e[k]];
    x.T = timed(deep, x.x, mine).t;
  }
  std::uint64_t c = 0;
  for (const Stage& b : by_thread) c += b.collisions, st.stuck += b.stuck;
  handed += e.size();
  std::vector<std::size_t> kept;
  for (std::size_t k : e)
    if (st.states[k].T > level) kept.push_back(k);
  disagreed += e.size() - kept.size();
  e.swap(kept);
  return c;
}

/// A fixed-effort run (every stage `starts` states, the chains spread evenly over the starts outliving the level) in
/// replicate stream r: `level_of(j, stage)` names level j + 1 (NaN: stop) and `scales_of(j, stage, elites)` its
/// chains' scales; from the first j that `go_deep(j, scales)` says (with a deep clock) the deep clock times them, its
/// elites handed over first; `elites(j, stage, e)` sees the starts outliving the level and `after(j, chains)` the
/// stage its chains made. Returns the collisions.
template <class LevelOf, class ScalesOf, class GoDeep, class Elites, class After>
std::uint64_t fixed_effort(const EscapeClock& clock, const EscapeClock& deep, const IcStratum& stratum,
                           const IcSplitSpec& spec, std::uint64_t seed, std::uint64_t r, const IcPropose& propose,
                           LevelOf level_of, ScalesOf scales_of, GoDeep go_deep, Elites elites, After after) {
  Stage st = first_stage(clock, stratum, spec, seed, r);
  std::uint64_t c = st.collisions, handed = 0, disagreed = 0;
  bool deep_on = false;
  double before = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; !st.states.empty(); ++j) {
    const double level = level_of(j, st);
    if (std::isnan(level)) break;
    const double moved_by = std::min(kMoved, level - before);
    before = level;
    std::vector<std::size_t> e = outliving(st, level);
    if (e.empty()) break;
    const IcScales sc = scales_of(j, st, e);
    if (!deep_on && deep && go_deep(j, sc)) {
      deep_on = true;
      c += hand_over(deep, spec, st, e, level, handed, disagreed);
      if (e.empty()) break;
    }
    elites(j, st, e);
    st = next_stage(deep_on ? deep : clock, stratum, spec, st, e, even_lengths(e.size(), spec.starts), level, sc, j + 1,
                    seed, r, propose, moved_by);
    c += st.collisions;
    after(j, st);
  }
  return c;
}

/// The window of 2 w + 1 halvings centred at c, within 0 .. top.
void centre(IcScales& sc, int c, int w, int top) {
  sc.halvings = top;
  sc.lo = std::max(0, c - w);
  const int hi = std::min(top, c + w);
  sc.lo = std::min(sc.lo, hi);
  sc.halvings = hi;
}

}  // namespace

namespace {

/// The first pilot: levels at the 1 / factor quantile, each level's extents from the starts outliving it, its window
/// moved to where its chains moved most (the next level's chains start from there); the hand-over frozen at the first
/// level it timed with the deep clock, or whose frozen window falls below 2^handover_bits double ulps.
IcPilot first_pilot(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, double t_max,
                    std::uint64_t seed, const IcPropose& propose, const EscapeClock& deep) {
  const int top = std::max(0, spec.scale_halvings), w = std::max(0, spec.window);
  IcPilot out;
  std::size_t first_deep = std::numeric_limits<std::size_t>::max();
  const auto falls = [&](const IcScales& sc) { return !sc.holds(stratum, 53, spec.handover_bits); };
  int at = -1;  // the centre the next level's chains try; -1: every halving
  // the first level whose window is centred where chains moved (every later one is): a window over every halving is
  // no step's, so only centred ones decide the hand-over
  std::size_t first_centred = std::numeric_limits<std::size_t>::max();
  out.collisions = fixed_effort(
      clock, deep, stratum, spec, seed, kPilot, propose,
      [&](std::size_t, const Stage& st) {
        if (static_cast<int>(out.levels.size()) >= spec.max_levels) return std::nan("");
        const double level = quantile_level(st, spec.factor, t_max);
        if (level >= t_max || (!out.levels.empty() && level <= out.levels.back())) return std::nan("");
        out.levels.push_back(level);
        return level;
      },
      [&](std::size_t, const Stage& st, const std::vector<std::size_t>& e) {
        IcScales sc = extents(stratum, st, e);
        if (at < 0)
          sc.lo = 0, sc.halvings = top;
        else
          centre(sc, at, w, top);
        if (at >= 0) first_centred = std::min(first_centred, out.scales.size());
        out.scales.push_back(sc);
        return sc;
      },
      [&](std::size_t j, const IcScales& sc) {
        if (j < first_centred || !falls(sc)) return false;
        first_deep = std::min(first_deep, j);
        return true;
      },
      [](std::size_t, const Stage&, const std::vector<std::size_t>&) {},
      [&](std::size_t j, const Stage& chains) {
        // the halving that moved most (the shallowest of equals); none moved: the window stays
        const auto best = std::max_element(chains.moved.begin(), chains.moved.end());
        if (best == chains.moved.end() || *best == 0) return;
        at = static_cast<int>(best - chains.moved.begin());
        centre(out.scales[j], at, w, top);
        first_centred = std::min(first_centred, j);
      });
  out.scales.resize(out.levels.size());
  out.handover = out.levels.size();
  if (deep)
    for (std::size_t j = 0; j < out.levels.size(); ++j)
      if (j >= first_deep || (j >= first_centred && falls(out.scales[j]))) {
        out.handover = j;
        break;
      }
  return out;
}

}  // namespace

IcPilot ic_pilot(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, double t_max,
                 std::uint64_t seed, const IcPropose& propose, const EscapeClock& deep) {
  IcPilot out = first_pilot(clock, stratum, spec, t_max, seed, propose, deep);
  // second, on the frozen levels, scales and hand-over, in a stream of its own (kPilot - 1): each level's share
  // outliving it (the levels past the last it reaches are never reached: the replicates' stages die out there)
  std::uint64_t c = fixed_effort(
      clock, deep, stratum, spec, seed, kPilot - 1, propose,
      [&](std::size_t j, const Stage&) { return j < out.levels.size() ? out.levels[j] : std::nan(""); },
      [&](std::size_t j, const Stage&, const std::vector<std::size_t>&) { return out.scales[j]; },
      [&](std::size_t j, const IcScales&) { return j >= out.handover; },
      [&](std::size_t, const Stage& st, const std::vector<std::size_t>& e) {
        // at most 4 factor: the level sits at the first pilot's 1 / factor quantile, so a share below a quarter of
        // that is the second pilot's noise, whose inverse would grow a replicate's stages without end where the
        // share is larger
        out.factors.push_back(
            std::min(4.0 * spec.factor, static_cast<double>(st.states.size()) / static_cast<double>(e.size())));
      },
      [](std::size_t, const Stage&) {});
  out.collisions += c;
  out.levels.resize(out.factors.size());
  out.scales.resize(out.factors.size());
  out.handover = std::min(out.handover, out.levels.size());
  return out;
}

IcReplicate ic_replicate(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                         const IcPilot& pilot, const std::vector<double>& t, std::uint64_t seed, std::uint64_t r,
                         const IcPropose& propose, const EscapeClock& deep) {
  const std::vector<double>& levels = pilot.levels;
  const std::vector<double>& factors = pilot.factors;
  if (factors.size() < levels.size() || pilot.scales.size() < levels.size())
    throw std::invalid_argument("ic_replicate: a factor and scales for every level");
  IcReplicate out;
  out.stage.assign(t.size(), 0);
  out.alive.assign(t.size(), 0);
  out.alive_w.assign(t.size(), 0.0);
  Stage st = first_stage(clock, stratum, spec, seed, r);
  for (std::size_t j = 0;; ++j) {
    out.population.push_back(st.states.size());
    out.stage_proposals.push_back(st.proposals), out.stage_accepted.push_back(st.accepted);
    out.ancestors.push_back(ancestors(st));
    out.collisions += st.collisions, out.stuck += st.stuck;
    out.proposals += st.proposals, out.accepted += st.accepted;
    // the grid times this stage answers: from its level to the next
    const double from = j == 0 ? -std::numeric_limits<double>::infinity() : levels[j - 1];
    const double to = j < levels.size() ? levels[j] : std::numeric_limits<double>::infinity();
    // by roulette class, each sorted, so that each grid time's count is one search a class; the weighted count
    // sum_k n_k 2^-k added from the thinnest class up (a fixed order)
    int classes = 0;
    for (const State& s : st.states) classes = std::max(classes, s.thin + 1);
    std::vector<std::vector<double>> T(static_cast<std::size_t>(classes));
    for (const State& s : st.states) T[static_cast<std::size_t>(s.thin)].push_back(s.T);
    for (auto& c : T) std::sort(c.begin(), c.end());
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t[i] < from || t[i] >= to) continue;
      out.stage[i] = static_cast<int>(j);
      out.alive[i] = 0, out.alive_w[i] = 0;
      for (int k = classes - 1; k >= 0; --k) {
        const auto& c = T[static_cast<std::size_t>(k)];
        const auto n = static_cast<std::uint64_t>(c.end() - std::upper_bound(c.begin(), c.end(), t[i]));
        out.alive[i] += n, out.alive_w[i] += std::ldexp(static_cast<double>(n), k);
      }
    }
    if (j == levels.size()) break;
    std::vector<std::size_t> e = outliving(st, levels[j]);
    if (deep && j == pilot.handover)
      out.collisions += hand_over(deep, spec, st, e, levels[j], out.handed_over, out.handover_disagreed);
    thin_elites(e, st, factors[j], kIcThinAbove * spec.starts, seed, r, j + 1);
    if (e.empty()) {  // died out: every later time reads 0 at the next stage
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t[i] >= to) out.stage[i] = static_cast<int>(j + 1), out.alive[i] = 0, out.alive_w[i] = 0;
      break;
    }
    st = next_stage(deep && j >= pilot.handover ? deep : clock, stratum, spec, st, e,
                    random_lengths(e.size(), factors[j], seed, r, j + 1), levels[j], pilot.scales[j], j + 1, seed, r,
                    propose);
  }
  return out;
}

SurvivalCurve ic_curve(const IcSplitRun& run) {
  SurvivalCurve c;
  c.t = run.t;
  c.weighted = c.replicated = true;
  c.particles = run.spec.starts;
  c.replicates = static_cast<int>(run.replicates.size());
  for (std::size_t i = 0; i < run.t.size(); ++i) {
    std::uint64_t alive = 0;
    for (const IcReplicate& r : run.replicates) alive += r.alive[i];
    c.survivors.push_back(alive);
    c.P_w.push_back(run.mean(i));
    c.E.push_back(run.error(i));
    c.replicates_nonzero.push_back(run.nonzero(i));
  }
  running_replicate_variance(c);
  return c;
}

IcSplitRun ic_split(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                    const std::vector<double>& t, double t_max, std::uint64_t seed,
                    const std::function<void(int, int)>& progress, const IcPropose& propose, const EscapeClock& deep) {
  if (spec.starts == 0 || spec.factor < 2 || spec.replicates < 1)
    throw std::invalid_argument("ic_split: needs starts > 0, factor >= 2 and replicates >= 1");
  IcSplitRun run;
  run.spec = spec;
  run.stratum = stratum;
  run.t = t;
  const IcPilot pilot = ic_pilot(clock, stratum, spec, t_max, seed, propose, deep);
  run.levels = pilot.levels, run.factors = pilot.factors, run.scales = pilot.scales, run.handover = pilot.handover;
  run.pilot_collisions = pilot.collisions;
  for (int r = 0; r < spec.replicates; ++r) {
    run.replicates.push_back(
        ic_replicate(clock, stratum, spec, pilot, t, seed, static_cast<std::uint64_t>(r), propose, deep));
    if (progress) progress(r + 1, spec.replicates);
  }
  return run;
}

IcSplitRun run_start_splitting(const Scene& scene, int threads, const std::function<void(int, int)>& progress) {
  const StartSplitSpec& g = scene.start_splitting;
  IcSplitSpec spec;
  spec.starts = scene.particles, spec.replicates = g.replicates, spec.factor = g.factor, spec.moves = g.moves;
  spec.scale_halvings = g.halvings, spec.window = g.window, spec.threads = threads;
  spec.deep_tier = g.deep_tier, spec.handover_bits = g.handover_bits;
  const EscapeClock deep = g.deep_tier == TierKind::double_ ? EscapeClock{} : scene_clock(scene, g.deep_tier);
  return ic_split(scene_clock(scene), ic_stratum(scene, g.p_lo, g.p_hi, g.edges), spec, survival_times(scene),
                  scene.t_max, scene.seed, progress, symmetric_proposal, deep);
}

}  // namespace rotleak
