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

double total(const std::vector<std::pair<double, double>>& v) {
  double sum = 0;
  for (const auto& [lo, hi] : v) sum += hi - lo;
  return sum;
}

/// A point's place in a union of intervals laid end to end, and back.
double packed(const std::vector<std::pair<double, double>>& v, double x) {
  double before = 0;
  for (const auto& [lo, hi] : v) {
    if (x < hi) return before + (x - lo);
    before += hi - lo;
  }
  return before;
}
double unpacked(const std::vector<std::pair<double, double>>& v, double a) {
  for (const auto& [lo, hi] : v) {
    if (a < hi - lo) return lo + a;
    a -= hi - lo;
  }
  return v.back().second;  // past the end (rounding): outside, refused
}

bool inside(const std::vector<std::pair<double, double>>& v, double x) {
  for (const auto& [lo, hi] : v)
    if (x >= lo && x < hi) return true;
  return false;
}

/// A start whose escape time is known: what a stage holds.
struct State {
  IcPoint x;
  double T = 0;
  int thin = 0;  ///< roulette halvings on its way: it stands for 2^thin states
};

struct Stage {
  std::vector<State> states;
  std::uint64_t collisions = 0, stuck = 0, proposals = 0, accepted = 0;
  /// By halving j: the accepted moves that changed T by more than kMoved (what a window is centred on)
  std::vector<std::uint64_t> moved;
};

/// A move "moved" where it changed T by more than this (one time unit: another escape, not the same one shifted by
/// the step in tau).
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
    out.states[i] = {x, timed(clock, x, mine).t};
  }
  for (const Stage& s : by_thread) out.collisions += s.collisions, out.stuck += s.stuck;
  return out;
}

/// The extents of the starts `elites` of `st` in each coordinate (the stratum's where they all sit at one value): a
/// level's scales in the pilot.
IcScales extents(const IcStratum& stratum, const Stage& st, const std::vector<std::size_t>& elites) {
  IcScales sc;
  sc.s = total(stratum.s), sc.p = total(stratum.p), sc.tau = stratum.tau_hi - stratum.tau_lo;
  if (elites.size() < 2) return sc;
  const auto coords = [&](std::size_t k) {
    const IcPoint& x = st.states[elites[k]].x;
    return std::array<double, 3>{packed(stratum.s, x.s), packed(stratum.p, x.p), x.tau};
  };
  std::array<double, 3> lo = coords(0), hi = lo;
  for (std::size_t k = 1; k < elites.size(); ++k) {
    const std::array<double, 3> c = coords(k);
    for (std::size_t i = 0; i < 3; ++i) lo[i] = std::min(lo[i], c[i]), hi[i] = std::max(hi[i], c[i]);
  }
  if (hi[0] > lo[0]) sc.s = hi[0] - lo[0];
  if (hi[1] > lo[1]) sc.p = hi[1] - lo[1];
  if (hi[2] > lo[2]) sc.tau = hi[2] - lo[2];
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
                 const IcPropose& propose) {
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
            if (std::abs(T - at.T) > kMoved) ++mine.moved[static_cast<std::size_t>(std::max(0, scales.halving(u[0])))];
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

bool IcStratum::contains(const IcPoint& x) const {
  return inside(s, x.s) && inside(p, x.p) && (tau_lo == tau_hi ? x.tau == tau_lo : (x.tau >= tau_lo && x.tau < tau_hi));
}

double IcStratum::share() const { return total(s) * total(p) / 2; }

IcPoint IcStratum::at(double us, double up, double ut) const {
  return {unpacked(s, us * total(s)), unpacked(p, up * total(p)), tau_lo + (tau_hi - tau_lo) * ut};
}

IcStratum ic_stratum(const Scene& scene, double p_lo, double p_hi, bool edges) {
  if (!(p_lo >= 0 && p_lo < p_hi && p_hi <= 1)) throw std::invalid_argument("ic_stratum: needs 0 <= p_lo < p_hi <= 1");
  IcStratum st;
  if (edges) {
    if (scene.on_table()) throw std::invalid_argument("ic_stratum: the straight edges are the stadium's");
    const Stadium<double> sd(scene.d, scene.r);
    st.s = {{0.0, sd.junction(0)}, {sd.junction(1), sd.junction(2)}, {sd.junction(3), 1.0}};
  } else {
    st.s = {{0.0, 1.0}};
  }
  if (p_lo == 0)
    st.p = {{-p_hi, p_hi}};
  else
    st.p = {{-p_hi, -p_lo}, {p_lo, p_hi}};
  st.tau_lo = 0, st.tau_hi = scene.creation_window;
  return st;
}

namespace {

/// The clock of one model (the stadium's Model or any table's TableModel), shared by every thread that calls it.
template <class M>
EscapeClock model_clock(std::shared_ptr<const M> m) {
  return [m](const IcPoint& x) {
    InitialDraw d;
    d.s = x.s, d.p = x.p, d.tau = x.tau;
    NoCollisionObserver<double> none;
    const ParticleEnd e = run_particle(*m, initial_state(*m, d), none);
    IcEnd out;
    out.collisions = e.collisions;
    if (e.fate != Fate::survived) out.t = e.t, out.stuck = e.fate == Fate::stuck;
    return out;
  };
}

}  // namespace

EscapeClock scene_clock(const Scene& scene) {
  if (scene.on_table())
    return model_clock(std::make_shared<const TableModel<double>>(table_spec(scene), leak_specs(scene), scene.t_max));
  return model_clock(std::make_shared<const Model<double>>(Model<double>::from(scene)));
}

IcPoint symmetric_proposal(const IcStratum& stratum, const IcScales& scales, const IcPoint& x, const double* u) {
  // One halving j for the three coordinates, the step uniform in [-extent 2^-j, extent 2^-j), taken in the
  // coordinates that lay the stratum's intervals end to end (a translation on each: the uniform law's density
  // stays 1, so a symmetric step there is symmetric for it); s wraps round, p and tau do not.
  const int j = scales.halving(u[0]);
  const auto step = [j](double extent, double v) { return std::ldexp(extent, -j) * (2 * v - 1); };
  const double ls = total(stratum.s), lp = total(stratum.p);
  double a = packed(stratum.s, x.s) + step(scales.s, u[1]);
  a = a - ls * std::floor(a / ls);
  const double b = packed(stratum.p, x.p) + step(scales.p, u[2]);
  IcPoint y = x;
  y.s = a < ls ? unpacked(stratum.s, a) : stratum.s.front().first;
  y.p = b < 0 || b >= lp ? 2.0 : unpacked(stratum.p, b);  // 2: outside every stratum, refused
  if (stratum.tau_hi > stratum.tau_lo) y.tau = x.tau + step(scales.tau, u[3]);
  return y;
}

int IcScales::halving(double u0) const {
  return lo + std::min(halvings - lo, static_cast<int>(u0 * (halvings - lo + 1)));
}

double IcScales::step(double extent) const { return std::ldexp(extent, -(lo + halvings) / 2); }

bool IcScales::resolved(const IcStratum& st) const {
  // 2^8 ulps of the largest magnitude in each coordinate
  const auto ulps = [](double extent, double big) {
    return extent == 0 || extent >= std::ldexp(big - std::nextafter(big, 0.0), 8);
  };
  const double s_big = st.s.back().second, p_big = std::max(std::abs(st.p.front().first), std::abs(st.p.back().second));
  return ulps(step(s), s_big) && ulps(step(p), p_big) && ulps(st.tau_hi > st.tau_lo ? step(tau) : 0, st.tau_hi);
}

double IcSplitRun::unresolved_from() const {
  for (std::size_t j = 0; j < scales.size() && j < levels.size(); ++j)
    if (!scales[j].resolved(stratum)) return levels[j];
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

std::uint64_t IcSplitRun::collisions() const {
  std::uint64_t c = pilot_collisions;
  for (const IcReplicate& rep : replicates) c += rep.collisions;
  return c;
}

namespace {

/// A fixed-effort run (every stage `starts` states, the chains spread evenly over the starts outliving the level) in
/// replicate stream r: `level_of(j, stage)` names level j + 1 (NaN: stop) and `scales_of(j, stage, elites)` its
/// chains' scales; `after(j, chains)` sees the stage its chains made. Returns the collisions.
template <class LevelOf, class ScalesOf, class After>
std::uint64_t fixed_effort(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                           std::uint64_t seed, std::uint64_t r, const IcPropose& propose, LevelOf level_of,
                           ScalesOf scales_of, After after) {
  Stage st = first_stage(clock, stratum, spec, seed, r);
  std::uint64_t c = st.collisions;
  for (std::size_t j = 0; !st.states.empty(); ++j) {
    const double level = level_of(j, st);
    if (std::isnan(level)) break;
    const std::vector<std::size_t> e = outliving(st, level);
    if (e.empty()) break;
    const IcScales sc = scales_of(j, st, e);
    st = next_stage(clock, stratum, spec, st, e, even_lengths(e.size(), spec.starts), level, sc, j + 1, seed, r,
                    propose);
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

IcPilot ic_pilot(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, double t_max,
                 std::uint64_t seed, const IcPropose& propose) {
  const int top = std::max(0, spec.scale_halvings), w = std::max(0, spec.window);
  IcPilot out;
  // first: levels at the 1 / factor quantile, each level's extents from the starts outliving it, its window moved to
  // where its chains moved most (the next level's chains start from there)
  int at = -1;  // the centre the next level's chains try; -1: every halving
  out.collisions = fixed_effort(
      clock, stratum, spec, seed, kPilot, propose,
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
        out.scales.push_back(sc);
        return sc;
      },
      [&](std::size_t j, const Stage& chains) {
        // the halving that moved most (the shallowest of equals); none moved: the window stays
        const auto best = std::max_element(chains.moved.begin(), chains.moved.end());
        if (best == chains.moved.end() || *best == 0) return;
        at = static_cast<int>(best - chains.moved.begin());
        centre(out.scales[j], at, w, top);
      });
  out.scales.resize(out.levels.size());
  // second, on the frozen levels and scales, in a stream of its own (kPilot - 1): each level's share outliving it
  std::uint64_t c = fixed_effort(
      clock, stratum, spec, seed, kPilot - 1, propose,
      [&](std::size_t j, const Stage& st) {
        if (j >= out.levels.size()) return std::nan("");
        const std::size_t e = outliving(st, out.levels[j]).size();
        if (e == 0) return std::nan("");  // the levels past here are never reached: the replicates' stages die out
        // at most 4 factor: the level sits at the first pilot's 1 / factor quantile, so a share below a quarter of
        // that is the second pilot's noise, whose inverse would grow a replicate's stages without end where the
        // share is larger
        out.factors.push_back(
            std::min(4.0 * spec.factor, static_cast<double>(st.states.size()) / static_cast<double>(e)));
        return out.levels[j];
      },
      [&](std::size_t j, const Stage&, const std::vector<std::size_t>&) { return out.scales[j]; },
      [](std::size_t, const Stage&) {});
  out.collisions += c;
  out.levels.resize(out.factors.size());
  out.scales.resize(out.factors.size());
  return out;
}

IcReplicate ic_replicate(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                         const IcPilot& pilot, const std::vector<double>& t, std::uint64_t seed, std::uint64_t r,
                         const IcPropose& propose) {
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
    thin_elites(e, st, factors[j], kIcThinAbove * spec.starts, seed, r, j + 1);
    if (e.empty()) {  // died out: every later time reads 0 at the next stage
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t[i] >= to) out.stage[i] = static_cast<int>(j + 1), out.alive[i] = 0, out.alive_w[i] = 0;
      break;
    }
    st = next_stage(clock, stratum, spec, st, e, random_lengths(e.size(), factors[j], seed, r, j + 1), levels[j],
                    pilot.scales[j], j + 1, seed, r, propose);
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
                    const std::function<void(int, int)>& progress, const IcPropose& propose) {
  if (spec.starts == 0 || spec.factor < 2 || spec.replicates < 1)
    throw std::invalid_argument("ic_split: needs starts > 0, factor >= 2 and replicates >= 1");
  IcSplitRun run;
  run.spec = spec;
  run.stratum = stratum;
  run.t = t;
  const IcPilot pilot = ic_pilot(clock, stratum, spec, t_max, seed, propose);
  run.levels = pilot.levels, run.factors = pilot.factors, run.scales = pilot.scales;
  run.pilot_collisions = pilot.collisions;
  for (int r = 0; r < spec.replicates; ++r) {
    run.replicates.push_back(
        ic_replicate(clock, stratum, spec, pilot, t, seed, static_cast<std::uint64_t>(r), propose));
    if (progress) progress(r + 1, spec.replicates);
  }
  return run;
}

IcSplitRun run_start_splitting(const Scene& scene, int threads, const std::function<void(int, int)>& progress) {
  const StartSplitSpec& g = scene.start_splitting;
  IcSplitSpec spec;
  spec.starts = scene.particles, spec.replicates = g.replicates, spec.factor = g.factor, spec.moves = g.moves;
  spec.scale_halvings = g.halvings, spec.window = g.window, spec.threads = threads;
  return ic_split(scene_clock(scene), ic_stratum(scene, g.p_lo, g.p_hi, g.edges), spec, survival_times(scene),
                  scene.t_max, scene.seed, progress);
}

}  // namespace rotleak
