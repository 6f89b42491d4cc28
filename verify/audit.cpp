#include "verify/audit.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "analysis/fits.hpp"
#include "io/progress.hpp"
#include "numeric/input.hpp"
#include "sim/engine/engine.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/tally/survival.hpp"

namespace rotleak {

namespace {

Quantiles quantiles(std::vector<double> v) {
  Quantiles q;
  q.n = v.size();
  if (v.empty()) return q;
  std::sort(v.begin(), v.end());
  auto at = [&](double f) { return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1) + 0.5)]; };
  q.q10 = at(0.1);
  q.q25 = at(0.25);
  q.median = at(0.5);
  q.q75 = at(0.75);
  q.q90 = at(0.9);
  return q;
}

double abs_enclosure_hi(const ExactReal& x) {
  if (x.is_rational()) return std::abs(x.as_rational().get_d());
  mpfi_t box;
  mpfi_init2(box, 128);
  x.enclose(box, 128);
  mpfr_t m;
  mpfr_init2(m, 128);
  mpfi_mag(m, box);
  const double d = mpfr_get_d(m, MPFR_RNDU);
  mpfr_clear(m);
  mpfi_clear(box);
  return d;
}

struct Ensemble {
  SurvivalCurve curve;
  KappaFit kappa;
  AlphaResult alpha;
};

Ensemble run_tier_ensemble(const Scene& base, const AuditOptions& ao, Tier tier, std::uint64_t n, int threads,
                           AuditReport& rep, Engine engine = Engine::scalar) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene s = base;
  s.tier = tier;
  s.particles = n;
  s.collision_density.reset();
  s.escape_records = false;
  RunOptions opt;
  opt.threads = threads;
  opt.engine = engine;
  opt.progress = progress_on_stderr(
      ao.progress,
      "[rotleak audit] " + std::string(engine == Engine::simd ? "double_simd" : to_string(tier)) + " ensemble");
  const RunResult r = ao.work.ensemble(s, opt);
  Ensemble e{survival_curve(s, r.tally), {}, {}};
  e.kappa = fit_kappa(e.curve, s.kappa_window.from, s.kappa_window.to);
  e.alpha = find_alpha(e.curve, e.kappa);
  rep.ensemble_seconds_by_tier.emplace_back(
      engine == Engine::simd ? "double_simd" : to_string(tier),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return e;
}

std::uint64_t survivors_at(const SurvivalCurve& c, double t) {
  const auto it = std::upper_bound(c.t.begin(), c.t.end(), t);
  return c.survivors[static_cast<std::size_t>(it - c.t.begin()) - 1];
}

StatisticsCheck compare(const std::string& name, const Ensemble& tier, const Ensemble& ref, double t_max) {
  StatisticsCheck c;
  c.tier = name;
  const double edges[] = {0, 100, 300, 1000, 3000, 10000, 1e300};
  for (int i = 0; i + 1 < 7; ++i) {
    const double from = edges[i], to = std::min(edges[i + 1], t_max);
    if (from >= t_max) break;
    WindowTest w{from, to, 0, 0, survivors_at(tier.curve, from), survivors_at(ref.curve, from), 0};
    w.escapes_tier = w.at_risk_tier - survivors_at(tier.curve, to);
    w.escapes_ref = w.at_risk_ref - survivors_at(ref.curve, to);
    if (w.at_risk_tier > 0 && w.at_risk_ref > 0) {
      const double n1 = static_cast<double>(w.at_risk_tier), n2 = static_cast<double>(w.at_risk_ref);
      const double p1 = static_cast<double>(w.escapes_tier) / n1, p2 = static_cast<double>(w.escapes_ref) / n2;
      const double p = (static_cast<double>(w.escapes_tier + w.escapes_ref)) / (n1 + n2);
      const double se = std::sqrt(p * (1 - p) * (1 / n1 + 1 / n2));
      w.z = se > 0 ? (p1 - p2) / se : 0;
    }
    c.max_abs_z = std::max(c.max_abs_z, std::abs(w.z));
    c.windows.push_back(w);
  }
  c.kappa = tier.kappa.value;
  c.kappa_error = tier.kappa.std_error;
  c.kappa_diff = tier.kappa.value - ref.kappa.value;
  c.kappa_diff_error = std::hypot(tier.kappa.std_error, ref.kappa.std_error);
  c.alpha = tier.alpha.value;
  c.alpha_error = tier.alpha.std_error;
  if (tier.alpha.value && ref.alpha.value) {
    c.alpha_diff = *tier.alpha.value - *ref.alpha.value;
    c.alpha_diff_error = std::hypot(tier.alpha.std_error, ref.alpha.std_error);
  }
  c.consistent = ensemble_consistent(c, tier.alpha.value.has_value() == ref.alpha.value.has_value());
  return c;
}

}  // namespace

namespace {

/// The scalar check of one leak (omega, width) over [0, t_max] at a tier.
ScalarCheck leak_scalar_check(const ExactReal& omega, const ExactReal& width, double t_max, const std::string& tier) {
  ScalarCheck c;
  c.tier = tier;
  const long p = tier_bits(tier);
  c.time_ulp_at_tmax = std::ldexp(1.0, static_cast<int>(std::floor(std::log2(t_max))) - static_cast<int>(p) + 1);
  const double omega_abs = abs_enclosure_hi(omega);
  const bool stationary = omega.sign() == 0;
  const double lambda = width.to_double();
  // omega rounded once (single) and as hi + lo (what the engine carries)
  mpfr_t hi;
  mpfr_init2(hi, p);
  omega.round(hi, MPFR_RNDN);
  mpq_class hq;
  mpfr_get_q(hq.get_mpq_t(), hi);
  const ExactReal rest = omega - ExactReal::rational(hq);
  mpfr_t lo;
  mpfr_init2(lo, p);
  rest.round(lo, MPFR_RNDN);
  mpq_class lq;
  mpfr_get_q(lq.get_mpq_t(), lo);
  mpfr_clears(hi, lo, static_cast<mpfr_ptr>(nullptr));
  c.omega_is_rounded = !stationary && rest.sign() != 0;
  c.omega_single_drift = stationary ? 0 : abs_enclosure_hi(rest) * t_max;
  const double split_err = stationary ? 0 : abs_enclosure_hi(rest - ExactReal::rational(lq));
  c.omega_split_drift = split_err * t_max;
  const double single_err = c.omega_single_drift / t_max;
  c.split_matters_after =
      split_err > 0 ? 1e-3 * width.to_double() / split_err : std::numeric_limits<double>::infinity();
  c.single_matters_after =
      single_err > 0 ? 1e-3 * width.to_double() / single_err : std::numeric_limits<double>::infinity();
  // the phase of a time known to half an ulp, plus a few roundings of the phase itself
  c.phase_error_at_tmax =
      stationary ? 0 : omega_abs * c.time_ulp_at_tmax / 2 + 4 * std::ldexp(1.0, 1 - static_cast<int>(p));
  c.phase_resolved = c.phase_error_at_tmax + c.omega_split_drift < 1e-3 * lambda;
  char buf[400];
  if (stationary) {
    std::snprintf(buf, sizeof buf, "stationary leak: no phase to resolve; time resolution at t_max %.2g",
                  c.time_ulp_at_tmax);
  } else {
    std::snprintf(
        buf, sizeof buf,
        "omega*t_max = %.3g; phase error at t_max <= %.2g (%.2g of the leak width); omega held %s, drift over t_max "
        "%.2g rounded once, %.2g as hi+lo (%s; reaches 1e-3 of the leak width after t = %.2g)",
        omega_abs * t_max, c.phase_error_at_tmax, c.phase_error_at_tmax / lambda,
        c.omega_is_rounded ? "as a nearby rational" : "exactly", c.omega_single_drift, c.omega_split_drift,
        c.omega_split_drift < 1e-3 * lambda ? "does not matter" : "matters", c.split_matters_after);
  }
  c.note = buf;
  return c;
}

}  // namespace

ScalarCheck scalar_check(const Scene& scene, const std::string& tier) {
  if (scene.leaks.empty()) return leak_scalar_check(scene.omega, scene.width, scene.t_max, tier);
  // a list of leaks: the one whose phase is resolved least well against its width (the first on a tie)
  ScalarCheck worst;
  double worst_share = -1;
  for (std::size_t k = 0; k < scene.leaks.size(); ++k) {
    const LeakInput& l = scene.leaks[k];
    ScalarCheck c = leak_scalar_check(l.omega.value, l.width.value, scene.t_max, tier);
    const double share = (c.phase_error_at_tmax + c.omega_split_drift) / l.width.value.to_double();
    if (share > worst_share) {
      c.note = "leaks." + std::to_string(k) + " (the least resolved of " + std::to_string(scene.leaks.size()) +
               "): " + c.note;
      worst = std::move(c);
      worst_share = share;
    }
  }
  return worst;
}

std::optional<std::string> scalar_rejection(const Scene& scene, const ScalarCheck& c) {
  if (!c.phase_resolved) return "leak phase not resolved at " + c.tier + ": " + c.note;  // stationary: resolved
  if (c.time_ulp_at_tmax > scene.survival_dt / 100) {
    char b[200];
    std::snprintf(b, sizeof b, "time resolution at t_max %.2g at %s is coarse against survival_dt %g",
                  c.time_ulp_at_tmax, c.tier.c_str(), scene.survival_dt);
    return std::string(b);
  }
  return std::nullopt;
}

namespace {

/// Ids to shadow, stratified by their double escape time (rare strata first, so the common ones
/// fill what is left of the sample).
std::vector<std::uint64_t> stratified_sample(const Scene& scene, const AuditOptions& opt, int threads) {
  Scene strat = scene;
  strat.particles = std::min<std::uint64_t>(opt.stratify_particles, scene.particles);
  strat.escape_records = true;
  strat.collision_density.reset();
  strat.tier = Tier::double_;
  RunOptions ro;
  ro.threads = threads;
  ro.progress = progress_on_stderr(opt.progress, "[rotleak audit] stratification");
  const RunResult sr = opt.work.ensemble(strat, ro);
  std::vector<std::vector<std::uint64_t>> strata(4);  // early (t < 100), middle (< 1000), late, survivor
  for (std::uint64_t i = 0; i < sr.records.size(); ++i) {
    const EscapeRecord& e = sr.records[i];
    const int k = e.fate != Fate::escaped ? 3 : e.t < 100 ? 0 : e.t < 1000 ? 1 : 2;
    strata[static_cast<std::size_t>(k)].push_back(i);
  }
  std::vector<std::uint64_t> ids;
  std::size_t want = opt.sample;
  for (int k = 3; k >= 0; --k) {
    const auto& in = strata[static_cast<std::size_t>(k)];
    const std::size_t take =
        std::min(in.size(), k == 0 ? want : (want + static_cast<std::size_t>(k)) / static_cast<std::size_t>(k + 1));
    for (std::size_t j = 0; j < take; ++j) ids.push_back(in[j * in.size() / take]);
    want -= take;
  }
  return ids;
}

/// Horizons, escape reproduction and growth by class of tier k over the shadow runs.
TierAudit tier_audit(const std::vector<ShadowResult>& runs, std::size_t k, const std::string& name) {
  TierAudit ta;
  ta.name = name;
  std::vector<double> hc, ht, hm, hch;
  std::size_t exact = 0;
  for (const ShadowResult& r : runs) {
    const TierShadow& ts = r.tiers[k];
    if (r.truth.escape) {
      ++ta.escapes_compared;
      exact += ts.escape_exact;
    }
    // A particle that escapes (or reaches the cap) before its tier leaves tolerance says only that
    // the horizon is longer than its life: censored, counted apart, not mixed into the quantiles.
    if (!ts.horizon) {
      ++ta.beyond_horizon;
      continue;
    }
    const std::size_t h = *ts.horizon;
    hc.push_back(static_cast<double>(h));
    ht.push_back(ts.horizon_time - r.draw.tau);
    std::size_t mupo = 0;
    for (std::size_t i = 0; i < std::min(h, r.truth.mupo.size()); ++i) mupo += r.truth.mupo[i];
    (4 * mupo >= h && h > 0 ? hm : hch).push_back(static_cast<double>(h));
  }
  ta.escape_time_exact_fraction =
      ta.escapes_compared ? static_cast<double>(exact) / static_cast<double>(ta.escapes_compared) : 0;
  ta.horizon_collisions = quantiles(hc);
  ta.horizon_time = quantiles(ht);
  ta.horizon_collisions_mupo = quantiles(hm);
  ta.horizon_collisions_chaotic = quantiles(hch);
  ta.growth = class_growth(runs, k);
  return ta;
}

/// The same ids as full ensembles in float, double, long double (and the vectorised engine),
/// each compared with the long double ensemble (long double with double).
void statistics_checks(const Scene& scene, const AuditOptions& opt, std::uint64_t n, int threads, AuditReport& rep) {
  const Ensemble e_ld = run_tier_ensemble(scene, opt, Tier::long_double, n, threads, rep);
  const Ensemble e_d = run_tier_ensemble(scene, opt, Tier::double_, n, threads, rep);
  const Ensemble e_f = run_tier_ensemble(scene, opt, Tier::float_, n, threads, rep);
  rep.statistics.push_back(compare("float", e_f, e_ld, scene.t_max));
  rep.statistics.push_back(compare("double", e_d, e_ld, scene.t_max));
  rep.statistics.push_back(compare("long_double", e_ld, e_d, scene.t_max));
  // the vectorised double engine, as a tier of its own: the same comparison, and whether its
  // survival curve is the scalar double engine's, survivor for survivor
  if (!opt.work.all(simd::available())) return;
  const Ensemble e_v = run_tier_ensemble(scene, opt, Tier::double_, n, threads, rep, Engine::simd);
  StatisticsCheck v = compare("double_simd", e_v, e_ld, scene.t_max);
  v.identical_to_scalar_double = e_v.curve.survivors == e_d.curve.survivors;
  rep.statistics.push_back(v);
}

const StatisticsCheck* statistics_of(const AuditReport& rep, const std::string& tier) {
  for (const StatisticsCheck& s : rep.statistics)
    if (s.tier == tier) return &s;
  return nullptr;
}

const Verdict* verdict_of(const AuditReport& rep, const std::string& tier, const std::string& statistic) {
  for (const Verdict& v : rep.verdicts)
    if (v.tier == tier && v.statistic == statistic) return &v;
  return nullptr;
}

bool trusts(const Verdict* v) { return v && (v->verdict == "trusted" || v->verdict == "trusted as a statistic"); }

using Rejections = std::vector<std::pair<std::string, std::optional<std::string>>>;

/// A statistic's verdict for a tier that passes its scalars and does not reproduce every sampled escape:
/// its ensemble against its reference (which counts only where the reference's scalars pass), or, with no
/// ensemble, the most precise less precise tier that has one, only where that tier is trusted.
Verdict statistic_verdict(const AuditReport& rep, const Rejections& rejection, std::size_t k, const char* stat) {
  const TierAudit& ta = rep.tiers[k];
  Verdict v{ta.name, stat, "", ""};
  if (const StatisticsCheck* st = statistics_of(rep, ta.name)) {
    const std::string ref = ta.name == "long_double" ? "double" : "long_double";
    char b[300];
    std::snprintf(b, sizeof b, "%s (max |z| = %.2f over %zu windows, kappa diff %.2g +- %.1g) against %s",
                  st->consistent ? "ensemble agrees" : "ensemble differs", st->max_abs_z, st->windows.size(),
                  st->kappa_diff, st->kappa_diff_error, ref == "double" ? "double" : "long double");
    const std::string horizon = "; trajectories leave the truth after a median " +
                                std::to_string(static_cast<long>(ta.horizon_collisions.median)) + " collisions";
    std::optional<std::string> ref_out;
    for (const auto& [name, why] : rejection)
      if (name == ref) ref_out = why;
    if (ref_out && st->consistent) {
      v.verdict = "untested";
      v.reason = std::string(b) + ", which is itself not trusted here (" + *ref_out + ")" + horizon;
    } else {
      v.verdict = st->consistent ? "trusted as a statistic" : "not trusted";
      v.reason = std::string(b) + horizon;
    }
    return v;
  }
  const Verdict* base = nullptr;
  for (std::size_t j = k; j-- > 0;)
    if (statistics_of(rep, rep.tiers[j].name)) {
      base = verdict_of(rep, rep.tiers[j].name, stat);
      break;
    }
  if (trusts(base)) {
    v.verdict = "trusted as a statistic";
    v.reason = "no ensemble at this tier; more precise than " + base->tier + ", which is " + base->verdict + " (" +
               base->reason + ")";
  } else {
    v.verdict = "untested";
    v.reason = base ? "no ensemble at this tier, and " + base->tier +
                          ", the most precise tier with one, is not trusted here (" + base->reason + ")"
                    : "no ensemble at this tier, and no less precise tier with one";
  }
  return v;
}

/// The vectorised double engine: the double tier's verdict first, then its own ensemble's comparison.
void engine_verdicts(AuditReport& rep) {
  const StatisticsCheck* simd = statistics_of(rep, "double_simd");
  if (!simd) return;
  for (const char* stat : {"P(t)", "kappa", "alpha"}) {
    const Verdict* d = verdict_of(rep, "double", stat);
    Verdict v{"double_simd", stat, "", ""};
    char b[300];
    std::snprintf(
        b, sizeof b,
        "vectorised double engine: survival curve %s the scalar double engine's; ensemble %s long double (max "
        "|z| = %.2f)",
        simd->identical_to_scalar_double ? "identical to" : "differs from",
        simd->consistent ? "agrees with" : "differs from", simd->max_abs_z);
    if (d && !trusts(d)) {
      v.verdict = d->verdict;
      v.reason = "the double tier's verdict: " + d->reason;
    } else if (simd->identical_to_scalar_double && d) {
      v.verdict = d->verdict;
      v.reason = std::string(b) + "; the double tier is " + d->verdict;
    } else {
      v.verdict = simd->consistent ? "trusted as a statistic" : "not trusted";
      v.reason = b;
    }
    rep.verdicts.push_back(v);
  }
}

}  // namespace

bool trajectories_trusted(const TierAudit& t) {
  return t.escape_time_exact_fraction >= kTrustedEscapeShare && t.escapes_compared > 0;
}

bool ensemble_consistent(const StatisticsCheck& c, bool alpha_presence_agrees) {
  const bool alpha_ok =
      c.alpha_diff ? std::abs(*c.alpha_diff) <= kEnsembleSigmas * c.alpha_diff_error : alpha_presence_agrees;
  return c.max_abs_z < kEnsembleSigmas && std::abs(c.kappa_diff) <= kEnsembleSigmas * c.kappa_diff_error && alpha_ok;
}

void judge(const Scene& scene, AuditReport& rep) {
  Rejections rejection;  // per tier, in order
  for (const TierAudit& ta : rep.tiers) {
    rep.scalars.push_back(scalar_check(scene, ta.name));
    rejection.emplace_back(ta.name, scalar_rejection(scene, rep.scalars.back()));
  }
  for (std::size_t k = 0; k < rep.tiers.size(); ++k) {
    const TierAudit& ta = rep.tiers[k];
    const std::optional<std::string> own = rejection[k].second;
    const bool trajectories = trajectories_trusted(ta);
    char why[300];
    std::snprintf(
        why, sizeof why, "%.1f%% of %zu sampled escape times reproduced; median horizon %.0f collisions (%.0f time)",
        100 * ta.escape_time_exact_fraction, ta.escapes_compared, ta.horizon_collisions.median, ta.horizon_time.median);
    rep.verdicts.push_back({ta.name, "trajectories", trajectories ? "trusted" : "not trusted", why});
    for (const char* stat : {"P(t)", "kappa", "alpha"}) {
      if (own)
        rep.verdicts.push_back({ta.name, stat, "not trusted", *own});
      else if (trajectories)
        rep.verdicts.push_back({ta.name, stat, "trusted", "its trajectories are trusted: " + std::string(why)});
      else
        rep.verdicts.push_back(statistic_verdict(rep, rejection, k, stat));
    }
  }
  engine_verdicts(rep);
}

void check_auditable(const Scene& scene) {
  if (scene.splitting.on)
    throw InputError("run.splitting", "true",
                     "the audit follows single particles through every tier and runs unsplit ensembles: leave "
                     "run.splitting out (the double tier's verdict holds for the split run too)");
}

AuditReport audit(const Scene& scene, const AuditOptions& opt) {
  check_auditable(scene);
  const auto t0 = std::chrono::steady_clock::now();
  auto lap = t0;
  const auto since_lap = [&lap] {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - lap).count();
    lap = now;
    return s;
  };
  AuditReport rep;
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();

  rep.ids = stratified_sample(scene, opt, threads);
  rep.sample = rep.ids.size();
  rep.stratify_seconds = since_lap();

  ShadowOptions so;
  so.tiers = opt.tiers;
  so.max_collisions = opt.max_collisions;
  so.tolerance = opt.tolerance;
  std::function<void(std::size_t, std::size_t)> progress;
  if (opt.progress)
    progress = [](std::size_t d, std::size_t of) {
      std::fprintf(stderr, "\r[rotleak audit] shadows %zu/%zu   ", d, of);
    };
  const std::vector<ShadowResult> runs = opt.work.shadows(scene, rep.ids, so, threads, progress);
  if (opt.progress) std::fprintf(stderr, "\r[rotleak audit] shadows %zu/%zu done\n", rep.sample, rep.sample);
  rep.shadow_seconds = since_lap();
  // the ensembles before the shadows' analysis: under a team every rank runs its share of them
  statistics_checks(scene, opt, std::min<std::uint64_t>(opt.stats_particles, scene.particles), threads, rep);
  if (!opt.work.reports) return AuditReport{};
  rep.ensemble_seconds = since_lap();

  for (const auto& r : runs) rep.max_truth_bits = std::max(rep.max_truth_bits, r.truth.bits);
  for (std::size_t k = 0; k < opt.tiers.size(); ++k) rep.tiers.push_back(tier_audit(runs, k, opt.tiers[k]));

  // Lyapunov exponent both ways (divergence from the most precise non-MPFR tier sampled).
  const InitialConditions ic = initial_conditions(scene);
  rep.lyapunov_tangent = tangent_lyapunov(scene, ic.draw(0), 1000000);
  std::size_t best = 0;
  for (std::size_t k = 0; k < opt.tiers.size(); ++k)
    if (tier_bits(opt.tiers[k]) <= 113 && tier_bits(opt.tiers[k]) >= tier_bits(opt.tiers[best])) best = k;
  rep.lyapunov_divergence = divergence_lyapunov(runs, best, 10, 150);

  judge(scene, rep);
  rep.threads = threads;
  rep.analysis_seconds = since_lap();
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace rotleak
