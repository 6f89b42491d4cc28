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
};

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

/// The proposal scales of the chains seeded by `elites`: their extent in each coordinate (the stratum's where they
/// all sit at one value).
IcScales spread(const IcStratum& stratum, const Stage& st, const std::vector<std::size_t>& elites,
                const IcSplitSpec& spec) {
  IcScales sc;
  sc.halvings = spec.scale_halvings;
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
                 std::uint64_t stage, std::uint64_t seed, std::uint64_t r, const IcPropose& propose) {
  std::vector<std::uint64_t> at_k(elites.size() + 1, 0);
  for (std::size_t k = 0; k < elites.size(); ++k) at_k[k + 1] = at_k[k] + length[k];
  if (at_k.back() > kIcPopulationCap * spec.starts)
    throw std::runtime_error("splitting over initial conditions: a stage of " + std::to_string(at_k.back()) +
                             " starts past level " + std::to_string(level) + ", more than " +
                             std::to_string(kIcPopulationCap) + " times the " + std::to_string(spec.starts) +
                             " of stage 0: the levels are closer than the pilot saw them (more starts)");
  const IcScales scales = spread(stratum, before, elites, spec);
  const int threads = stage_threads(spec);
  Stage out;
  out.states.resize(at_k.back());
  std::vector<Stage> by_thread(static_cast<std::size_t>(threads));
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
          if (T > level) at.x = y, at.T = T, ++mine.accepted;
        }
      }
      out.states[at_k[k] + j] = at;
    }
  }
  for (const Stage& s : by_thread)
    out.collisions += s.collisions, out.stuck += s.stuck, out.proposals += s.proposals, out.accepted += s.accepted;
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
  const int j = std::min(scales.halvings, static_cast<int>(u[0] * (scales.halvings + 1)));
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

std::vector<double> ic_pilot_levels(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                                    double t_max, std::uint64_t seed, std::uint64_t* collisions,
                                    const IcPropose& propose) {
  // fixed effort: every stage `starts` states, its level the T a share 1 / factor of them outlive
  std::vector<double> levels;
  Stage st = first_stage(clock, stratum, spec, seed, kPilot);
  std::uint64_t c = st.collisions;
  while (static_cast<int>(levels.size()) < spec.max_levels && !st.states.empty()) {
    const double level = quantile_level(st, spec.factor, t_max);
    if (level >= t_max || (!levels.empty() && level <= levels.back())) break;
    levels.push_back(level);
    const std::vector<std::size_t> e = outliving(st, level);
    st = next_stage(clock, stratum, spec, st, e, even_lengths(e.size(), spec.starts), level, levels.size(), seed,
                    kPilot, propose);
    c += st.collisions;
  }
  if (collisions) *collisions = c;
  return levels;
}

std::vector<double> ic_level_factors(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                                     const std::vector<double>& levels, std::uint64_t seed, std::uint64_t* collisions,
                                     const IcPropose& propose) {
  // fixed effort again, on the frozen levels, in a stream of its own (kPilot - 1): each level's share outliving it
  const std::uint64_t r = kPilot - 1;
  std::vector<double> f;
  Stage st = first_stage(clock, stratum, spec, seed, r);
  std::uint64_t c = st.collisions;
  for (std::size_t j = 0; j < levels.size(); ++j) {
    const std::vector<std::size_t> e = outliving(st, levels[j]);
    if (e.empty()) break;  // the levels past here are never reached: the replicates' later stages die out
    // at most 4 factor: the level sits at the first pilot's 1 / factor quantile, so a share below a quarter of that is
    // the second pilot's noise, whose inverse would grow a replicate's stages without end where the share is larger
    f.push_back(std::min(4.0 * spec.factor, static_cast<double>(st.states.size()) / static_cast<double>(e.size())));
    st = next_stage(clock, stratum, spec, st, e, even_lengths(e.size(), spec.starts), levels[j], j + 1, seed, r,
                    propose);
    c += st.collisions;
  }
  if (collisions) *collisions = c;
  return f;
}

IcReplicate ic_replicate(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                         const std::vector<double>& levels, const std::vector<double>& factors,
                         const std::vector<double>& t, std::uint64_t seed, std::uint64_t r, const IcPropose& propose) {
  if (factors.size() < levels.size()) throw std::invalid_argument("ic_replicate: a factor for every level");
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
    st = next_stage(clock, stratum, spec, st, e, random_lengths(e.size(), factors[j], seed, r, j + 1), levels[j], j + 1,
                    seed, r, propose);
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
  run.levels = ic_pilot_levels(clock, stratum, spec, t_max, seed, &run.pilot_collisions, propose);
  std::uint64_t c = 0;
  run.factors = ic_level_factors(clock, stratum, spec, run.levels, seed, &c, propose);
  run.pilot_collisions += c;
  run.levels.resize(run.factors.size());
  for (int r = 0; r < spec.replicates; ++r) {
    run.replicates.push_back(
        ic_replicate(clock, stratum, spec, run.levels, run.factors, t, seed, static_cast<std::uint64_t>(r), propose));
    if (progress) progress(r + 1, spec.replicates);
  }
  return run;
}

IcSplitRun run_start_splitting(const Scene& scene, int threads, const std::function<void(int, int)>& progress) {
  const StartSplitSpec& g = scene.start_splitting;
  IcSplitSpec spec;
  spec.starts = scene.particles, spec.replicates = g.replicates, spec.factor = g.factor, spec.moves = g.moves;
  spec.scale_halvings = g.halvings, spec.threads = threads;
  return ic_split(scene_clock(scene), ic_stratum(scene, g.p_lo, g.p_hi, g.edges), spec, survival_times(scene),
                  scene.t_max, scene.seed, progress);
}

}  // namespace rotleak
