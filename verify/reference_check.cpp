// Checking a build against the reference: every tier within its error model through its horizon, every
// engine ending each case as the reference does.
#include "verify/reference.hpp"

#include <omp.h>

#include <exception>
#include <limits>
#include <optional>

#include "numeric/input.hpp"
#include "numeric/tier.hpp"
#include "sim/engine/engine.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "verify/reference_detail.hpp"

namespace rotleak {

using namespace reference_detail;

namespace {

/// An interval tier: its enclosures must contain the reference wherever they answer, and answer through
/// the collisions its width allows (where the reference's own enclosure, scaled to these bits, is below
/// the horizon tolerance and every leak margin is wider than it).
void check_interval_tier(const RefCase& c, const Tier& tier, const std::vector<ParsedStep>& ref, double L,
                         TierCheck& out) {
  const double scale = std::ldexp(1.0, static_cast<int>(c.bits - tier.bits));
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    const RefStep& st = c.steps[i];
    const double w = kErrorModelSafety * st.radius * scale;
    if (w > kHorizonTolerance || std::abs(st.margin) * L <= w || ref[i].junction <= w) break;
    out.must_reach = st.k;
  }
  bool contained = true;
  with_tier(tier, [&](auto) {
    const Model<Mpfi> model = model_of<Mpfi>(c.scene);
    try {
      trace(model, c.draw, c.steps.size(), [&](const TraceStep<Mpfi>& st) {
        const std::size_t i = st.k - 1;
        const double slack = c.steps[i].radius + ref[i].resolution;
        auto inside = [&](const Mpfi& x, const Big& r, double stretch) {
          Big lo, hi;
          mpfr_set(lo.v, &x.data()->left, MPFR_RNDD);
          mpfr_set(hi.v, &x.data()->right, MPFR_RNDU);
          return mpfr_cmp(lo.v, r.v) <= 0 ? (mpfr_cmp(r.v, hi.v) <= 0 || distance(r, hi) * stretch <= slack)
                                          : distance(lo, r) * stretch <= slack;
        };
        contained = st.piece == c.steps[i].piece && st.in_leak == c.steps[i].in_leak && inside(st.t, ref[i].t, 1) &&
                    inside(model.stadium.s_of(st.piece, st.q), ref[i].s, L) &&
                    inside(model.stadium.birkhoff_p(st.piece, st.q, st.v), ref[i].p, 1);
        if (contained) out.matched_through = st.k;
        return contained;
      });
    } catch (const UncertainDecision&) {
      out.stopped = "undecided branch at collision " + std::to_string(out.matched_through + 1);
    }
    return 0;
  });
  out.bits = "not stored";
  out.pass = contained && out.matched_through >= out.must_reach;
  if (!contained) out.first_wrong_decision = out.matched_through + 1;
}

/// A tier's trajectory hashes against the fingerprints the reference stores for it, collision by collision.
struct BitsCompare {
  const std::vector<std::pair<std::size_t, std::uint64_t>>* stored = nullptr;  ///< null: none compared
  std::size_t next = 0, last_match = 0;
  std::optional<std::size_t> differ;

  void see(std::size_t k, std::uint64_t hash) {
    if (!stored || next >= stored->size() || (*stored)[next].first != k) return;
    if ((*stored)[next].second == hash) {
      if (!differ) last_match = k;
    } else if (!differ) {
      differ = k;
    }
    ++next;
  }
  void verdict(bool check_bits, TierCheck& out) const {
    out.bits_compared = stored != nullptr;
    if (!check_bits) {
      out.bits = "not checked";
    } else if (!stored) {
      out.bits = "not stored";
    } else if (differ) {
      out.bits =
          "differ by collision " + std::to_string(*differ) + " (identical through " + std::to_string(last_match) + ")";
      out.bits_ok = false;
    } else if (next < stored->size()) {
      out.bits = "trajectory shorter than the reference";
      out.bits_ok = false;
    } else {
      out.bits = "identical";
    }
  }
};

/// A point tier (IEEE, double-double, __float128, MPFR): within its error model through its horizon,
/// every required escape decision reproduced, and (check_bits) the bits of the build that made the set.
void check_point_tier(const RefCase& c, const Tier& tier, const std::vector<ParsedStep>& ref, double L, double omega,
                      bool check_bits, TierCheck& out) {
  const double u = unit_roundoff(out.tier);
  out.must_reach = horizon(c, ref, u);
  const auto fp = c.fingerprints.find(out.tier);
  BitsCompare bits;
  if (check_bits && fp != c.fingerprints.end()) bits.stored = &fp->second;
  bool matching = true;
  with_tier(tier, [&](auto type) {
    using R = typename decltype(type)::type;
    follow<R>(c.scene, c.draw, c.steps.size(), [&](std::size_t k, const Seen& seen, const auto&, const auto&) {
      const RefStep& st = c.steps[k - 1];
      const ParsedStep& r = ref[k - 1];
      const double d =
          seen.piece == st.piece ? divergence(seen, r.t, r.s, r.p, L) : std::numeric_limits<double>::infinity();
      const bool required = k <= out.must_reach && decision_required(st, u, L, omega);
      if (required) {
        ++out.decisions_required;
        if (seen.in_leak == st.in_leak)
          ++out.decisions_reproduced;
        else if (!out.first_wrong_decision)
          out.first_wrong_decision = k;
      }
      // the error over the model, the reference's own uncertainty included: at 300 or 1024 bits the tier
      // is finer than the reference's radius, and d / (u W_k) alone read 6.9e10 and 6.1e228 beside "pass"
      const double allowed = kErrorModelSafety * u * st.gain + st.radius + r.resolution;
      if (k <= out.must_reach && allowed > 0)
        out.worst_ratio = std::max(out.worst_ratio, kErrorModelSafety * d / allowed);
      matching = matching && d <= allowed && (!required || seen.in_leak == st.in_leak);
      if (matching) out.matched_through = k;
      bits.see(k, seen.hash);
      return true;
    });
    return 0;
  });
  bits.verdict(check_bits, out);
  out.pass = out.matched_through >= out.must_reach && !out.first_wrong_decision && out.bits_ok;
}

}  // namespace

TierCheck check_tier(const RefCase& c, const std::string& tier, bool check_bits) {
  TierCheck out;
  out.tier = tier;
  out.case_name = c.name;
  out.collisions = c.steps.size();
  const double L = perimeter(c.scene), omega = omega_of(c.scene);
  const std::vector<ParsedStep> ref = parse_steps(c, L);
  const auto parsed = Tier::parse(tier);
  if (!parsed || parsed->automatic()) throw std::invalid_argument(tier);
  if (parsed->interval())
    check_interval_tier(c, *parsed, ref, L, out);
  else
    check_point_tier(c, *parsed, ref, L, omega, check_bits, out);
  return out;
}

namespace {

/// Where an engine's double run of case c must end: the first escape within double's horizon (provided
/// every decision before it is one double resolves), or the collision h after which t_max is put (with
/// collisions h and h + 1 further apart than double's error there). Says in out.expected why not when the
/// case cannot be decided in double.
struct EngineTarget {
  std::size_t horizon = 0;
  std::optional<std::size_t> escape;
};

std::optional<EngineTarget> engine_target(const RefCase& c, const std::vector<ParsedStep>& ref, double u, double L,
                                          double omega, EngineCheck& out) {
  EngineTarget target;
  std::size_t h = std::min(horizon(c, ref, u), c.steps.size() > 0 ? c.steps.size() - 1 : 0);
  for (std::size_t k = 1; k <= h; ++k) {
    const RefStep& st = c.steps[k - 1];
    if (!decision_required(st, u, L, omega)) {
      out.expected = "not decidable in double: collision " + std::to_string(k) + " lies " +
                     std::to_string(std::abs(st.margin)) + " (in s) from the leak's edge";
      return std::nullopt;
    }
    if (st.in_leak) {
      target.escape = k;
      break;
    }
  }
  // t_max goes between collisions h and h + 1: they must be further apart than double's error there
  while (h > 0 && target.escape != h) {
    Big a, b;
    parse_big(a, c.steps[h - 1].t);
    parse_big(b, c.steps[h].t);
    if (distance(a, b) / 2 > kErrorModelSafety * u * c.steps[h].gain) break;
    --h;
  }
  if (h == 0) {
    out.expected = "not decidable in double: no collision within its horizon";
    return std::nullopt;
  }
  target.horizon = h;
  return target;
}

/// The case's particle alone, through the engine, to just past the target.
EscapeRecord run_case(const RefCase& c, const std::vector<ParsedStep>& ref, const EngineTarget& target, Engine engine,
                      bool fast_forward, double& t_max) {
  Scene sc = c.scene;
  sc.particles = 1;
  sc.tier = Tier::double_;
  sc.collision_density.reset();
  sc.escape_records = true;
  sc.fast_forward = fast_forward;
  const std::size_t h = target.horizon;
  const double t_h = mpfr_get_d(ref[h - 1].t.v, MPFR_RNDN), t_next = mpfr_get_d(ref[h].t.v, MPFR_RNDN);
  sc.t_max = t_max = target.escape ? t_next + 1 : (t_h + t_next) / 2;
  std::vector<InitialDraw> draws{c.draw};
  RunOptions opt;
  opt.threads = 1;
  opt.engine = engine;
  opt.draws = &draws;
  return run_ensemble(sc, opt).records.at(0);
}

}  // namespace

EngineCheck check_engine(const RefCase& c, Engine engine, bool fast_forward) {
  EngineCheck out;
  out.engine = to_string(engine) + (fast_forward ? "+ff" : "");
  out.case_name = c.name;
  const double u = unit_roundoff("double"), L = perimeter(c.scene), omega = omega_of(c.scene);
  const std::vector<ParsedStep> ref = parse_steps(c, L);
  if (engine == Engine::simd && !simd::available()) {
    out.expected = "not run: this CPU has no AVX2 and FMA";
    return out;
  }
  const std::optional<EngineTarget> target = engine_target(c, ref, u, L, omega, out);
  if (!target) return out;
  out.checked = true;
  out.horizon = target->horizon;
  double t_max = 0;
  const EscapeRecord rec = run_case(c, ref, *target, engine, fast_forward, t_max);
  char buf[200];
  if (const auto escape = target->escape) {
    const RefStep& st = c.steps[*escape - 1];
    const double tol = kErrorModelSafety * u * st.gain + st.radius + ref[*escape - 1].resolution;
    Big t;
    mpfr_set_d(t.v, rec.t, MPFR_RNDN);
    const double dt = distance(t, ref[*escape - 1].t);
    std::snprintf(buf, sizeof buf, "escape at collision %zu, t within %.3g of %.17g", *escape, tol,
                  mpfr_get_d(ref[*escape - 1].t.v, MPFR_RNDN));
    out.expected = buf;
    std::snprintf(buf, sizeof buf, "%s at collision %llu, t = %.17g",
                  rec.fate == Fate::escaped ? "escape" : "no escape", static_cast<unsigned long long>(rec.collisions),
                  rec.t);
    out.got = buf;
    out.pass = rec.fate == Fate::escaped && rec.collisions == *escape && dt <= tol;
  } else {
    std::snprintf(buf, sizeof buf, "alive after %zu collisions at t_max = %.17g", target->horizon, t_max);
    out.expected = buf;
    std::snprintf(buf, sizeof buf, "%s after %llu collisions",
                  rec.fate == Fate::survived  ? "alive"
                  : rec.fate == Fate::escaped ? "escaped"
                                              : "stuck",
                  static_cast<unsigned long long>(rec.collisions));
    out.got = buf;
    out.pass = rec.fate == Fate::survived && rec.collisions == target->horizon;
  }
  return out;
}

namespace {

/// Each code's first proven orbit (d = 2, r = 1) through the point tiers of opt.tiers and the engines.
void replay_orbits(const VerifyOptions& opt, VerifyReport& rep) {
  const ExactReal d = ExactReal::parse("2"), r = ExactReal::parse("1");
  std::vector<std::string> tiers;
  for (const std::string& t : opt.tiers)
    if (const auto tier = Tier::parse(t); tier && !tier->interval() && !tier->automatic()) tiers.push_back(t);
  std::vector<ProvenOrbit> orbits;
  for (const std::string& text : opt.orbit_codes) {
    CodeOrbits got = code_orbits(d, r, parse_orbit_code(text, "--orbit"), OrbitOptions{});
    if (got.orbits.empty()) throw InputError("--orbit", text, "a code with a proven orbit (rotleak orbits --code)");
    for (const std::string& t : tiers) rep.orbits.push_back(replay_orbit(d, r, got.orbits[0], t));
    orbits.push_back(std::move(got.orbits[0]));
  }
  for (const auto& [engine, ff] : opt.engines)  // engine-major, as the reference cases' rows
    for (const ProvenOrbit& o : orbits) {
      const OrbitEngineReplay e = replay_orbit_engine(d, r, o, engine, ff);
      EngineCheck c;
      c.engine = e.engine;
      c.case_name = "orbit " + e.code;
      c.expected = e.expected;
      c.got = e.got;
      c.checked = true;
      c.pass = e.pass;
      rep.engines.push_back(c);
    }
}

}  // namespace

VerifyReport verify_reference(const ReferenceSet& set, const VerifyOptions& opt) {
  VerifyReport rep;
  rep.provenance_json = set.provenance_json;
  rep.cases = set.cases.size();
  const std::size_t n = set.cases.size();
  rep.tiers.resize(opt.tiers.size() * n);
  rep.engines.resize(opt.engines.size() * n);
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const std::size_t jobs = rep.tiers.size() + rep.engines.size();
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t j = 0; j < jobs; ++j) {
    try {
      if (j < rep.tiers.size()) {
        rep.tiers[j] = check_tier(set.cases[j % n], opt.tiers[j / n], opt.check_bits);
      } else {
        const std::size_t e = j - rep.tiers.size();
        rep.engines[e] = check_engine(set.cases[e % n], opt.engines[e / n].first, opt.engines[e / n].second);
      }
    } catch (...) {
#pragma omp critical(rotleak_verify_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  replay_orbits(opt, rep);
  for (const TierCheck& t : rep.tiers) rep.pass = rep.pass && t.pass;
  for (const EngineCheck& e : rep.engines) rep.pass = rep.pass && e.pass;
  for (const OrbitReplay& o : rep.orbits) rep.pass = rep.pass && o.pass;
  return rep;
}

std::vector<std::string> default_orbit_codes() { return {"TRBL", "RRL", "RRLRLLB", "TRRBLLTRBL"}; }

}  // namespace rotleak
