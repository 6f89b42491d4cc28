#include "verify/shadow.hpp"

#include <omp.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>

#include "io/bytes.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/model/sampling.hpp"
#include "verify/line_fit.hpp"
#include "verify/trace.hpp"

namespace rotleak {

namespace {

/// (t, x, y, vx, vy) of one collision at the truth's precision.
struct State {
  Mpfr v[5];
};

template <class R, class P>
State to_state(const TraceStep<R, P>& st) {
  State s;
  num_traits<R>::to_mpfr(s.v[0].data(), st.t);
  num_traits<R>::to_mpfr(s.v[1].data(), st.q.x);
  num_traits<R>::to_mpfr(s.v[2].data(), st.q.y);
  num_traits<R>::to_mpfr(s.v[3].data(), st.v.x);
  num_traits<R>::to_mpfr(s.v[4].data(), st.v.y);
  return s;
}

/// max |a_i - b_i|, rounded up to a double. The difference is taken at the states' own (stored) precision,
/// whatever precision the calling thread works at: a tier's divergence must not depend on the tier's bits.
double divergence(const State& a, const State& b) {
  double d = 0;
  MpfrPrecision exact(std::max(mpfr_get_prec(a.v[0].data()), mpfr_get_prec(b.v[0].data())));
  Mpfr diff;
  for (int i = 0; i < 5; ++i) {
    mpfr_sub(diff.data(), a.v[i].data(), b.v[i].data(), MPFR_RNDN);
    d = std::max(d, std::abs(mpfr_get_d(diff.data(), MPFR_RNDU)));
  }
  return d;
}

struct Reported {
  double t, s, p;
  bool in_leak, straight;
};

/// Whether a collision lies on a straight piece: the stadium's edges, a table's segments.
bool straight(const Stadium<double>&, Piece p) { return p == Piece::top || p == Piece::bottom; }
bool straight(const Table<double>& table, int k) { return table.piece(k).kind == PieceKind::segment; }

/// The model of tier R the geometry G stands for: the stadium's (Model), or any table's (TableModel).
template <class R>
Model<R> model_for(const Scene& scene, const Stadium<double>&) {
  return model_of<R>(scene);
}
template <class R>
TableModel<R> model_for(const Scene& scene, const Table<double>&) {
  return table_model_of<R>(scene);
}

/// A collision's t, s, p in double, from the geometry in double (the stadium's, or the table's).
template <class G, class R, class P>
Reported report(const G& geometry, const TraceStep<R, P>& step) {
  const Vec2<double> q{num_traits<R>::to_double(step.q.x), num_traits<R>::to_double(step.q.y)};
  const Vec2<double> v{num_traits<R>::to_double(step.v.x), num_traits<R>::to_double(step.v.y)};
  return {num_traits<R>::to_double(step.t), geometry.s_of(step.piece, q), geometry.birkhoff_p(step.piece, q, v),
          step.in_leak, straight(geometry, step.piece)};
}

struct TruthRun {
  std::vector<State> states;
  std::vector<Reported> reported;
};

// One MPFR run at `bits`; states are stored at `store_bits` (>= bits) for comparisons.
template <class G>
TruthRun run_mpfr(const Scene& scene, const InitialDraw& draw, long bits, long store_bits, std::size_t K,
                  bool stop_at_escape, const G& st) {
  TruthRun run;
  MpfrPrecision work(bits);
  const auto model = model_for<Mpfr>(scene, st);
  trace(model, draw, K, [&](const auto& step) {
    {
      MpfrPrecision store(store_bits);
      run.states.push_back(to_state(step));
    }
    run.reported.push_back(report(st, step));
    return !(stop_at_escape && step.in_leak);
  });
  return run;
}

template <class R, class G>
TierShadow run_tier(const std::string& name, const Scene& scene, const InitialDraw& draw, const TruthRun& truth,
                    long truth_bits, const ShadowOptions& opt, const G& st) {
  TierShadow out;
  out.name = name;
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t K = truth.states.size();
  try {
    const auto model = model_for<R>(scene, st);
    trace(model, draw, K, [&](const auto& step) {
      State s;
      {
        MpfrPrecision store(truth_bits);
        s = to_state(step);
      }
      const std::size_t i = step.k - 1;
      const double div = divergence(s, truth.states[i]);
      const Reported r = report(st, step);
      out.divergence.push_back(div);
      out.t.push_back(r.t);
      out.s.push_back(r.s);
      out.p.push_back(r.p);
      if (!out.horizon && div > opt.tolerance) {
        out.horizon = step.k;
        out.horizon_time = truth.reported[i].t;
      }
      if (!out.decision && step.in_leak != truth.reported[i].in_leak) out.decision = step.k;
      if (!out.escape && step.in_leak) {
        out.escape = step.k;
        out.escape_time = r.t;
      }
      return true;
    });
  } catch (const UncertainDecision&) {
    out.stopped = "undecided branch at collision " + std::to_string(out.divergence.size() + 1);
  }
  out.collisions = out.divergence.size();
  // growth of ln(divergence) between 1000 eps of the tier and 1e-4 (before saturation)
  const double floor_div = 1e3 * num_traits<R>::to_double(num_traits<R>::epsilon());
  std::vector<double> k, t, y;
  for (std::size_t i = 0; i < out.divergence.size(); ++i) {
    const double d = out.divergence[i];
    if (d > floor_div && d < 1e-4) {
      k.push_back(static_cast<double>(i + 1));
      t.push_back(truth.reported[i].t);
      y.push_back(std::log(d));
    }
  }
  out.growth_points = y.size();
  if (y.size() >= 3) {
    out.growth_per_collision = least_squares(k, y).slope;
    out.growth_per_time = least_squares(t, y).slope;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

ShadowResult shadow(const Scene& scene, std::uint64_t id, const ShadowOptions& opt) {
  // the particle as the ensemble draws it, by the scene's sampling scheme, with its weight
  const std::unique_ptr<Sampler> sampler = make_sampler(scene);
  ShadowResult res = shadow_from(scene, sampler->draw(id), opt);
  res.id = id;
  res.weight = sampler->weight(res.draw);
  return res;
}

namespace {

/// The truth: MPFR runs at doubling bits until the trace no longer changes beyond truth_tolerance; the
/// run at the bits that agreed, its bits and the agreement in res.truth.
template <class G>
TruthRun find_truth(const Scene& scene, const ShadowOptions& opt, const G& st, ShadowResult& res) {
  const bool until_escape = opt.collisions == 0;
  const std::size_t K0 = until_escape ? opt.max_collisions : std::min(opt.collisions, opt.max_collisions);
  long bits = opt.start_bits;
  TruthRun lower = run_mpfr(scene, res.draw, bits, 2 * bits, K0, until_escape, st);
  const std::size_t K = lower.states.size();
  TruthRun upper;
  for (;;) {
    res.truth.bits_tried.push_back(bits);
    if (2 * bits > opt.max_bits)
      throw std::runtime_error("no truth below " + std::to_string(opt.max_bits) +
                               " bits (raise max_bits or shorten the horizon)");
    upper = run_mpfr(scene, res.draw, 2 * bits, 2 * bits, K, false, st);
    double agree = upper.states.size() == lower.states.size() ? 0 : std::numeric_limits<double>::infinity();
    {
      MpfrPrecision p(2 * bits);
      for (std::size_t i = 0; i < std::min(upper.states.size(), lower.states.size()); ++i)
        agree = std::max(agree, divergence(upper.states[i], lower.states[i]));
    }
    res.truth.agreement = agree;
    if (agree <= opt.truth_tolerance) break;
    bits *= 2;
    lower = std::move(upper);  // the 2B run is the next lower run (stored exactly at its own bits)
  }
  res.truth.bits = 2 * bits;
  res.truth.bits_tried.push_back(2 * bits);
  return upper;
}

/// The truth's reported collisions into res.truth, and which lie in MUPO phases (this and a neighbouring
/// collision on the straight edges with |p| below mupo_p).
void record_truth(const TruthRun& truth, double mupo_p, ShadowResult& res) {
  res.horizon_collisions = truth.states.size();
  for (std::size_t i = 0; i < truth.reported.size(); ++i) {
    const Reported& r = truth.reported[i];
    res.truth.t.push_back(r.t);
    res.truth.s.push_back(r.s);
    res.truth.p.push_back(r.p);
    res.truth.in_leak.push_back(r.in_leak);
    res.truth.straight.push_back(r.straight);
    if (!res.truth.escape && r.in_leak) res.truth.escape = i + 1;
  }
  const std::size_t n = res.truth.t.size();
  res.truth.mupo.assign(n, 0);
  auto small = [&](std::size_t i) { return res.truth.straight[i] && std::abs(res.truth.p[i]) < mupo_p; };
  for (std::size_t i = 0; i < n; ++i)
    res.truth.mupo[i] = small(i) && ((i > 0 && small(i - 1)) || (i + 1 < n && small(i + 1)));
}

}  // namespace

namespace {

/// The shadow on the geometry G in double (the stadium's, or any table's), whose model each tier runs.
template <class G>
ShadowResult shadow_on(const Scene& scene, const InitialDraw& draw, const ShadowOptions& opt, const G& st) {
  ShadowResult res;
  res.draw = draw;
  const TruthRun upper = find_truth(scene, opt, st, res);
  record_truth(upper, opt.mupo_p, res);

  const long truth_bits = res.truth.bits;
  for (const std::string& name : opt.tiers) {
    TierShadow ts = with_tier(name, [&](auto type) {
      return run_tier<typename decltype(type)::type>(name, scene, res.draw, upper, truth_bits, opt, st);
    });
    if (res.truth.escape && ts.escape && *ts.escape == *res.truth.escape)
      ts.escape_exact = std::abs(ts.escape_time - res.truth.t[*res.truth.escape - 1]) <= opt.tolerance;
    res.tiers.push_back(std::move(ts));
  }
  return res;
}

}  // namespace

ShadowResult shadow_from(const Scene& scene, const InitialDraw& draw, const ShadowOptions& opt) {
  for (const auto& n : opt.tiers)
    if (tier_bits(n) == 0) throw std::invalid_argument(n);
  if (scene.on_table()) return shadow_on(scene, draw, opt, Table<double>(table_spec(scene)));
  return shadow_on(scene, draw, opt, Stadium<double>(scene.d, scene.r));
}

std::vector<ShadowResult> shadow_many(const Scene& scene, const std::vector<std::uint64_t>& ids,
                                      const ShadowOptions& opt, int threads,
                                      const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<ShadowResult> runs(ids.size());
  std::atomic<std::size_t> done{0};
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads())
  for (std::size_t i = 0; i < ids.size(); ++i) {
    runs[i] = shadow(scene, ids[i], opt);
    const std::size_t d = ++done;
    if (progress && omp_get_thread_num() == 0) progress(d, ids.size());
  }
  return runs;
}

namespace {

constexpr const char* kShadowsMagic = "rotleak-shadows 1\n";

void put_shadow(ByteWriter& w, const ShadowResult& r) {
  w.word(r.id);
  for (double x : {r.draw.s, r.draw.p, r.draw.x, r.draw.y, r.draw.u, r.draw.tau}) w.real(x);
  w.flag(r.draw.flow);
  w.real(r.weight);
  w.word(r.horizon_collisions);
  const TruthTrace& t = r.truth;
  w.word(static_cast<std::uint64_t>(t.bits));
  w.real(t.agreement);
  w.list(t.bits_tried);
  w.list(t.t);
  w.list(t.s);
  w.list(t.p);
  w.list(t.in_leak);
  w.list(t.straight);
  w.list(t.mupo);
  w.maybe(t.escape);
  w.word(r.tiers.size());
  for (const TierShadow& k : r.tiers) {
    w.text(k.name);
    w.word(k.collisions);
    w.list(k.divergence);
    w.list(k.t);
    w.list(k.s);
    w.list(k.p);
    w.maybe(k.horizon);
    w.real(k.horizon_time);
    w.maybe(k.decision);
    w.maybe(k.escape);
    w.real(k.escape_time);
    w.flag(k.escape_exact);
    w.real(k.growth_per_collision);
    w.real(k.growth_per_time);
    w.word(k.growth_points);
    w.text(k.stopped);
    w.real(k.seconds);
  }
}

ShadowResult get_shadow(ByteReader& r) {
  ShadowResult s;
  s.id = r.word();
  for (double* x : {&s.draw.s, &s.draw.p, &s.draw.x, &s.draw.y, &s.draw.u, &s.draw.tau}) *x = r.real();
  s.draw.flow = r.flag();
  s.weight = r.real();
  s.horizon_collisions = r.word();
  TruthTrace& t = s.truth;
  t.bits = static_cast<long>(r.word());
  t.agreement = r.real();
  r.list(t.bits_tried);
  r.list(t.t);
  r.list(t.s);
  r.list(t.p);
  r.list(t.in_leak);
  r.list(t.straight);
  r.list(t.mupo);
  t.escape = r.maybe();
  const std::uint64_t tiers = r.word();
  if (tiers > 64) throw std::runtime_error(r.where + ": " + std::to_string(tiers) + " tiers in one shadow");
  s.tiers.resize(tiers);
  for (TierShadow& k : s.tiers) {
    k.name = r.text();
    k.collisions = r.word();
    r.list(k.divergence);
    r.list(k.t);
    r.list(k.s);
    r.list(k.p);
    k.horizon = r.maybe();
    k.horizon_time = r.real();
    k.decision = r.maybe();
    k.escape = r.maybe();
    k.escape_time = r.real();
    k.escape_exact = r.flag();
    k.growth_per_collision = r.real();
    k.growth_per_time = r.real();
    k.growth_points = r.word();
    k.stopped = r.text();
    k.seconds = r.real();
  }
  return s;
}

}  // namespace

std::string encode_shadows(const std::vector<ShadowResult>& runs) {
  ByteWriter w;
  w.out = kShadowsMagic;
  w.word(runs.size());
  for (const ShadowResult& r : runs) put_shadow(w, r);
  return w.out;
}

std::vector<ShadowResult> decode_shadows(const std::string& bytes, const std::string& where) {
  const std::size_t magic = std::strlen(kShadowsMagic);
  if (bytes.compare(0, magic, kShadowsMagic) != 0) throw std::runtime_error(where + ": not a list of shadow results");
  ByteReader r{bytes, magic, where + ": shadow results"};
  const std::uint64_t n = r.word();
  if (n > bytes.size()) throw std::runtime_error(where + ": shadow results: " + std::to_string(n) + " results claimed");
  std::vector<ShadowResult> runs(n);
  for (ShadowResult& s : runs) s = get_shadow(r);
  if (r.at != bytes.size()) throw std::runtime_error(where + ": shadow results have trailing data");
  return runs;
}

}  // namespace rotleak
