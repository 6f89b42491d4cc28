#include "verify/orbit_replay.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "verify/reference_detail.hpp"
#include "verify/trace.hpp"

namespace rotleak {

namespace {

using reference_detail::Big;

/// The orbit's bounces in Birkhoff coordinates (s, p), at the precision the orbit was proven with.
struct Truth {
  std::vector<std::unique_ptr<Big>> s, p;
};

Truth truth_of(const ExactReal& d, const ExactReal& r, const ProvenOrbit& o, long bits) {
  const MpfrPrecision guard(bits);
  const std::vector<Mpfr> u = box_midpoint(o.box);
  Truth t;
  for (std::size_t i = 0; i < o.code.size(); ++i) {
    // named values: mpfr_set is a statement-expression macro, and a temporary passed to it dies before it is read
    const auto [s, p] = orbit_bounce_birkhoff(d, r, o.code, u, i);
    t.s.push_back(std::make_unique<Big>());
    t.p.push_back(std::make_unique<Big>());
    mpfr_set(t.s.back()->v, s.data(), MPFR_RNDN);
    mpfr_set(t.p.back()->v, p.data(), MPFR_RNDN);
  }
  return t;
}

}  // namespace

std::vector<std::string> replay_tiers() { return {"float", "double", "long_double", "dd", "float128", "mpfr:256"}; }

OrbitReplay replay_orbit(const ExactReal& d, const ExactReal& r, const ProvenOrbit& orbit, const std::string& tier,
                         const ReplayOptions& opt) {
  OrbitReplay out;
  out.tier = tier;
  out.code = orbit_code_text(orbit.code);
  out.period = orbit.code.size();
  const long bits = 2 * tier_bits(tier) + 64;
  ProvenOrbit truth;
  {
    const MpfrPrecision guard(bits);
    if (!prove_orbit(d, r, orbit.code, box_midpoint(orbit.box), bits, truth))
      throw std::runtime_error("orbit " + out.code + ": not proven again at " + std::to_string(bits) + " bits");
    out.log_multiplier = truth.log_multiplier();
  }
  const Truth tr = truth_of(d, r, truth, bits);
  out.unit_roundoff = std::ldexp(1.0, -static_cast<int>(tier_bits(tier)));
  const double n = static_cast<double>(out.period);
  out.predicted = n * std::log(opt.tolerance / out.unit_roundoff) / out.log_multiplier;
  out.low = out.predicted - n * std::log(opt.a_max) / out.log_multiplier;
  out.high = out.predicted - n * std::log(opt.a_min) / out.log_multiplier + 1;
  const double L = Stadium<double>(d, r).perimeter();
  with_tier(tier, [&](auto id) {
    using R = typename decltype(id)::type;
    if constexpr (std::is_same_v<R, Mpfi>) {
      throw std::invalid_argument("an orbit replay follows a point tier, not " + tier);
    } else {
      Model<R> model(d, r, ExactReal::parse("0"), ExactReal::parse("0"), ExactReal::parse("0"), 1e300);
      // the start: bounce 0 rounded into R, leaving along the orbit
      ParticleState<R> ps;
      const BoundaryPoint<R> b = model.stadium.at(num_traits<R>::from_mpfr(tr.s[0]->v));
      ps.q = b.q;
      ps.v = model.stadium.velocity(b, num_traits<R>::from_mpfr(tr.p[0]->v));
      const R kick = R(opt.reflection_kick);
      trace_from(model, ps, opt.max_periods * out.period, [&](const TraceStep<R>& st) {
        if (opt.reflection_kick != 0) st.v.x = st.v.x + kick * st.v.x;
        const std::size_t i = st.k % out.period;
        Big s, p;
        num_traits<R>::to_mpfr(s.v, model.stadium.s_of(st.piece, st.q));
        num_traits<R>::to_mpfr(p.v, model.stadium.birkhoff_p(st.piece, st.q, st.v));
        const double div =
            std::max(L * reference_detail::distance(s, *tr.s[i], true), reference_detail::distance(p, *tr.p[i]));
        if (div > opt.tolerance) {
          out.departure = st.k;
          return false;
        }
        if (st.piece != orbit.code[i] && out.wrong_piece == 0) out.wrong_piece = st.k;
        return true;
      });
    }
  });
  const double k = static_cast<double>(out.departure);
  out.pass = out.departure > 0 && out.wrong_piece == 0 && k >= out.low && k <= out.high;
  return out;
}

OrbitEngineReplay replay_orbit_engine(const ExactReal& d, const ExactReal& r, const ProvenOrbit& orbit, Engine engine,
                                      bool fast_forward) {
  OrbitEngineReplay out;
  out.engine = to_string(engine) + (fast_forward ? "+ff" : "");
  out.code = orbit_code_text(orbit.code);
  const std::size_t n = orbit.code.size();
  if (engine == Engine::simd && !simd::available()) {
    out.expected = out.got = "not run: this CPU has no AVX2 and FMA";
    out.pass = true;
    return out;
  }
  const double length = num_traits<Mpfi>::to_double(orbit.length);
  Scene sc =
      parse_scene("[stadium]\nd = \"" + d.text() + "\"\nr = \"" + r.text() +
                  "\"\n[leak]\nwidth = \"1e-6\"\nstart = \"" + orbit_digits(orbit.s0) +
                  "\"\nomega = \"0\"\n[ensemble]\nparticles = 1\n[run]\nt_max = " + shortest(1.5 * length) + "\n");
  sc.tier = Tier::double_;
  sc.escape_records = true;
  sc.fast_forward = fast_forward;
  const std::vector<InitialDraw> draws{
      InitialDraw{num_traits<Mpfi>::to_double(orbit.s0), num_traits<Mpfi>::to_double(orbit.p0), 0, 0, 0, 0, false}};
  RunOptions opt;
  opt.threads = 1;
  opt.engine = engine;
  opt.draws = &draws;
  const EscapeRecord rec = run_ensemble(sc, opt).records.at(0);
  char buf[200];
  std::snprintf(buf, sizeof buf, "escape at collision %zu, t = %.15g (within 1e-9)", n, length);
  out.expected = buf;
  std::snprintf(buf, sizeof buf, "%s at collision %llu, t = %.15g", rec.fate == Fate::escaped ? "escape" : "no escape",
                static_cast<unsigned long long>(rec.collisions), rec.t);
  out.got = buf;
  out.pass = rec.fate == Fate::escaped && rec.collisions == n && std::abs(rec.t - length) < 1e-9;
  return out;
}

}  // namespace rotleak
