#include "analysis/regimes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "analysis/continued_fraction.hpp"
#include "geometry/stadium.hpp"

namespace rotleak {

namespace {

double frac(double x) { return x - std::floor(x); }

/// Variance of sum_k u_k ln P(i_k) from the curve's covariance of ln P.
double log_var(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& u) {
  double v = 0;
  for (std::size_t a = 0; a < idx.size(); ++a)
    for (std::size_t b = 0; b < idx.size(); ++b) v += u[a] * u[b] * c.log_cov(idx[a], idx[b]);
  return std::max(0.0, v);
}

}  // namespace

LeakTimes leak_times(const Scene& scene) {
  LeakTimes lt;
  const double r = scene.r.to_double(), lambda = scene.width.to_double();
  const double s0 = scene.start.to_double(), omega = scene.omega.to_double();
  lt.omega_sweep = lambda / (2 * r);
  if (omega == 0) return lt;
  lt.rotating = true;
  const Stadium<double> st(scene.d, scene.r);
  const double lower_start = st.junction(1), lower_end = st.junction(2);  // the lower straight edge, in s
  if (omega > 0) {  // leading edge s_L + lambda/2 moving towards +s
    const double lead = s0 + lambda / 2;
    lt.tau1 = frac(lower_start - lead) / omega;
    lt.tau2 = *lt.tau1 + (lower_end - lower_start) / omega;
  } else {  // leading edge s_L - lambda/2 moving towards -s: it meets the lower edge's end first
    const double lead = s0 - lambda / 2;
    lt.tau1 = frac(lead - lower_end) / -omega;
    lt.tau2 = *lt.tau1 + (lower_end - lower_start) / -omega;
  }
  return lt;
}

std::vector<RateJump> decay_rate_jumps(const SurvivalCurve& c, double window, double min_effective) {
  std::vector<RateJump> out;
  if (c.t.size() < 3) return out;
  const double dt = c.t[1] - c.t[0];
  const std::size_t W = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(window / dt)));
  struct Cand {
    double score;
    std::size_t i;
    RateJump j;
  };
  std::vector<Cand> cands;
  for (std::size_t i = W; i + W < c.t.size(); ++i) {
    const std::size_t a = i - W, b = i, e = i + W;
    if (!(c.P(e) > 0) || c.effective(e) < min_effective) continue;
    const double w = c.t[e] - c.t[b], w0 = c.t[b] - c.t[a];
    const double r1 = (std::log(c.P(a)) - std::log(c.P(b))) / w0, r2 = (std::log(c.P(b)) - std::log(c.P(e))) / w;
    if (!(r2 > 0) || r2 < 2 * r1) continue;
    const double sd = std::sqrt(log_var(c, {a, b, e}, {-1 / w0, 1 / w0 + 1 / w, -1 / w}));
    if (!(r2 - r1 > 3 * sd)) continue;
    cands.push_back({r1 > 0 ? r2 / r1 : 1e300, i, {c.t[i], r1, r2}});
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& x, const Cand& y) { return x.score > y.score; });
  std::vector<std::size_t> taken;
  for (const Cand& k : cands) {
    bool near = false;
    for (std::size_t t : taken) near = near || (k.i > t ? k.i - t : t - k.i) < 2 * W;
    if (near) continue;
    taken.push_back(k.i);
    out.push_back(k.j);
  }
  std::sort(out.begin(), out.end(), [](const RateJump& x, const RateJump& y) { return x.t < y.t; });
  return out;
}

namespace {

/// The regime a tail class implies: stationary for omega = 0, else low (transient), high (persistent), mid.
std::string regime_of(bool rotating, const std::string& tail) {
  if (!rotating) return "stationary";
  return tail == "transient" ? "low" : tail == "persistent" ? "high" : "mid";
}

/// Names the near rational in a regime note: "2 r omega = 2/5 + 4e-05 (omega near 1/5)".
std::string near_text(const NearRational& n) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "2 r omega = %s %c %.3g", n.rational.c_str(), n.eps < 0 ? '-' : '+', std::abs(n.eps));
  std::string out = buf;
  if (!n.omega_rational.empty()) out += " (omega near " + n.omega_rational + ")";
  return out;
}

/// The fate of a tail seen from tc on: "transient" (removed: no survivor where an algebraic continuation
/// would keep 6 effective, or a local exponent above 6 at the end of the resolved range) or "persistent"
/// (with regime "undecided" where the leak had not swept the lower edge by the last survivor).
/// The tail's end as the curve shows it: e, the last resolved grid time after the crossing tc (with at least
/// min_eff effective survivors), a, the start of the last stretch [max(tc, t_e / 1.5), t_e], the local
/// exponent z over it and its error, and the first grid time with no survivor after tc (size() if none).
struct TailEnd {
  std::size_t e = 0, a = 0, zero = 0;
  double z = 0, z_se = 0;
};

TailEnd tail_end_of(const SurvivalCurve& c, double tc, double min_eff) {
  TailEnd end;
  std::size_t& e = end.e;
  end.zero = c.t.size();
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.t[i] < tc) continue;
    if (c.P(i) > 0 && c.effective(i) >= min_eff) e = i;
    if (!(c.P(i) > 0) && end.zero == c.t.size()) end.zero = i;
  }
  if (e == 0 || c.t[e] < tc) e = static_cast<std::size_t>(std::lower_bound(c.t.begin(), c.t.end(), tc) - c.t.begin());
  end.a = e;
  while (end.a > 0 && c.t[end.a - 1] >= std::max(tc, c.t[e] / 1.5)) --end.a;
  if (end.a < e && c.t[end.a] > 0) {
    const double dl = std::log(c.t[e]) - std::log(c.t[end.a]);
    end.z = (std::log(c.P(end.a)) - std::log(c.P(e))) / dl;
    end.z_se = std::sqrt(log_var(c, {end.a, e}, {1 / dl, -1 / dl}));
  }
  return end;
}

/// A persistent tail whose removal the leak could not yet show: the leading edge leaves the lower edge
/// (tau2) only after the last survivor, so whether it removes the tail (low) or not (high) was not observed.
void undecided_if_unswept(const Scene& scene, const SurvivalCurve& c, std::size_t e, TailClass& k) {
  const LeakTimes lt = leak_times(scene);
  std::size_t last = e;  // last time with a survivor
  for (std::size_t i = e; i < c.t.size(); ++i)
    if (c.P(i) > 0) last = i;
  if (k.tail == "persistent" && lt.tau2 && *lt.tau2 > c.t[last]) {
    k.regime = "undecided";
    k.note += "; the leak's leading edge leaves the lower edge only at tau2 = " + std::to_string(*lt.tau2) +
              ", after the last survivor: run longer (t_max > tau2) to see whether the tail is removed";
  }
}

void tail_fate(const Scene& scene, const SurvivalCurve& c, double tc, double min_eff, double steep, TailClass& k) {
  const bool rotating = any_leak_moves(scene);  // any listed leak, not only [leak]'s
  const TailEnd end = tail_end_of(c, tc, min_eff);
  const std::size_t e = end.e, a = end.a, zero = end.zero;
  const double z = end.z;
  k.end_exponent = z;
  if (zero < c.t.size() && c.t[zero] < scene.t_max) {
    const double expected = c.effective(e) * std::pow(c.t[e] / c.t[zero], 3.0);
    if (expected >= 6) {
      k.tail = "transient";
      k.tail_end = c.t[zero];
      k.tail_end_range = std::make_pair(c.t[e], c.t[zero]);
      k.note = "tail removed: no survivor at t = " + std::to_string(c.t[zero]) +
               " where an algebraic continuation (exponent <= 3) would keep >= 6 effective survivors";
      k.regime = regime_of(rotating, k.tail);
      return;
    }
  }
  char note[160];
  if (z - steep > 3 * end.z_se && a < e) {
    k.tail = "transient";
    k.tail_end = c.t[a];
    k.tail_end_range = std::make_pair(c.t[a], c.t[e]);
    std::snprintf(note, sizeof note,
                  "tail removed: the local exponent at the end of the resolved range, %.3g, exceeds %g by 3 standard "
                  "errors",
                  z, steep);
  } else {
    k.tail = "persistent";
    std::snprintf(note, sizeof note,
                  "tail present at the end of the resolved range (local exponent %.3g, not significantly above %g)", z,
                  steep);
  }
  k.note = note;
  k.regime = regime_of(rotating, k.tail);
  undecided_if_unswept(scene, c, e, k);
}

/// classify_tail without the near-rational regime label (the tail class, `near` set where it applies).
/// The first grid index past the kappa window where a tail is seen without alpha: P sigma errors (its own
/// and the fit's extrapolation) above factor x the fit, with at least kSeeTail effective survivors (alpha
/// asks for min_survivors; a tail carried by 58-108 unsplit lines at 82/83 was once called "none" at 10^30
/// times the fit); size() if none.
std::size_t tail_seen_at(const SurvivalCurve& c, const AlphaResult& alpha, const KappaFit& fit) {
  const double min_eff = static_cast<double>(alpha.min_survivors);
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.t[i] <= fit.to || !(c.P(i) > 0) || c.effective(i) < std::min(min_eff, kSeeTail)) continue;
    const double line = alpha.factor * std::exp(fit.log_amplitude - fit.value * c.t[i]);
    const double err = std::hypot(c.P_err(i), line * c.t[i] * fit.std_error);
    if (c.P(i) - line > alpha.sigma * err) return i;
  }
  return c.t.size();
}

/// A tail seen at grid index `seen` whose alpha is not resolved: "unresolved", with about the particles
/// that would keep min_survivors through the fewest effective survivors before it.
TailClass unresolved_tail(const SurvivalCurve& c, const AlphaResult& alpha, const KappaFit& fit, std::size_t seen,
                          bool rotating) {
  TailClass k;
  const double min_eff = static_cast<double>(alpha.min_survivors);
  double fewest = std::numeric_limits<double>::infinity(), at = 0;
  for (std::size_t i = 0; i <= seen; ++i)
    if (c.t[i] >= fit.to && c.effective(i) < fewest) fewest = c.effective(i), at = c.t[i];
  k.tail = "unresolved";
  k.regime = rotating ? "undecided" : "stationary";
  const double scale = std::max(1.0, min_eff / std::max(fewest, 1e-300));
  k.resolve_particles = static_cast<std::uint64_t>(std::ceil(static_cast<double>(c.particles) * scale));
  char note[400];
  std::snprintf(note, sizeof note,
                "a tail is seen (P = %.3g at t = %g more than %g errors above %g x the fit, %.0f effective survivors) "
                "but alpha, P at the first crossing, is not resolved: the effective survivors fall to %.3g at t = %g; "
                "about %.3g particles would keep %g there",
                c.P(seen), c.t[seen], alpha.sigma, alpha.factor, c.effective(seen), fewest, at,
                static_cast<double>(*k.resolve_particles), min_eff);
  k.note = note;
  return k;
}

/// Near a rational: a tail that rose kNearBump times above the fit (and sigma errors) and died, or nothing.
std::optional<TailClass> near_bump(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha,
                                   const KappaFit& fit, double steep) {
  const double min_eff = static_cast<double>(alpha.min_survivors);
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.t[i] <= fit.to || !(c.P(i) > 0) || c.effective(i) < min_eff) continue;
    const double line = std::exp(fit.log_amplitude - fit.value * c.t[i]);
    const double err = std::hypot(c.P_err(i), line * c.t[i] * fit.std_error);
    if (c.P(i) < kNearBump * line || !(c.P(i) - line > alpha.sigma * err)) continue;
    TailClass fate;
    tail_fate(scene, c, c.t[i], min_eff, steep, fate);
    if (fate.tail != "transient") return std::nullopt;
    char note[200];
    std::snprintf(note, sizeof note, "; a tail formed below alpha's factor: P = %.3g times the fit at t = %g",
                  c.P(i) / line, c.t[i]);
    fate.note += note;
    return fate;
  }
  return std::nullopt;
}

/// No tail seen: "none", its regime claimed only when alpha's bound lies below the weakest tail it is meant
/// to exclude (fit.tail_floor; at 2*10^5 particles omega = 2/3 was called mid with a bound above the tail
/// 10^6 particles resolve, 1.9e-4), else undecided with about the particles that would decide it (the bound
/// falls about as 1/N).
TailClass no_tail(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha, bool rotating) {
  TailClass k;
  k.note = "no significant crossing of the exponential fit: no tail";
  k.regime = regime_of(rotating, k.tail);
  if (rotating && (!alpha.upper_bound || *alpha.upper_bound >= scene.tail_floor)) {
    k.regime = "undecided";
    const double scale = alpha.upper_bound ? std::max(1.0, *alpha.upper_bound / scene.tail_floor) : 100.0;
    k.resolve_particles = static_cast<std::uint64_t>(std::ceil(static_cast<double>(c.particles) * scale));
    char note[400];
    std::snprintf(note, sizeof note,
                  "no tail seen, but only alpha < %.3g is excluded, not a tail down to fit.tail_floor = %.3g: "
                  "undecided between mid and high; about %.3g particles would decide it",
                  alpha.upper_bound ? *alpha.upper_bound : 1.0, scene.tail_floor,
                  static_cast<double>(*k.resolve_particles));
    k.note = note;
  }
  return k;
}

/// A flat 1/t stretch measured (fit_amplitude: P above 100 times the fit, t P flat over a factor 2 in t at
/// least, C more than 3 of its errors, stat. and drift, above 0): a tail is seen and its weight resolved.
bool amplitude_resolved(const TailAmplitude* a) {
  return a && a->value && *a->value > 3 * std::hypot(a->std_error, a->drift);
}

/// Where alpha is not resolved but C is: the tail's fate from the start of C's stretch (persistent or
/// transient, with its regime), and the note says its weight is C's.
TailClass tail_from_amplitude(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha,
                              const TailAmplitude& a, double steep) {
  TailClass k;
  tail_fate(scene, c, a.from, static_cast<double>(alpha.min_survivors), steep, k);
  char note[260];
  std::snprintf(note, sizeof note,
                "; alpha, P at the first crossing, is not resolved there, but the tail is: t P is flat at C = %.4g +- "
                "%.2g over [%g, %g] (alpha_C reads its weight)",
                *a.value, std::hypot(a.std_error, a.drift), a.from, a.to);
  k.note += note;
  return k;
}

TailClass classify_tail_from_P(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha,
                               const KappaFit* fit, const TailAmplitude* amplitude) {
  const bool rotating = any_leak_moves(scene);  // any listed leak, not only [leak]'s
  // near a rational other than an integer: a tail that forms and dies is looked for more closely
  std::optional<NearRational> near = rotating ? near_rational(scene) : std::nullopt;
  if (near && near->q < 2) near.reset();
  const double steep = near ? kNearSteep : 6.0;
  const auto with_near = [&](TailClass t) {
    if (t.tail == "transient") t.near = near;
    return t;
  };
  if (!alpha.value && fit && fit->ok) {
    const std::size_t seen = tail_seen_at(c, alpha, *fit);
    if (seen < c.t.size()) {
      // a tail seen and then removed is transient whether or not alpha is resolved (the removal is
      // measured on the resolved points after it: at omega = 1e-4 with 10^5 mupo particles the crossing
      // falls where the uniform share's survivors are too few, the sweep at t ~ 5900 does not)
      TailClass fate;
      tail_fate(scene, c, c.t[seen], static_cast<double>(alpha.min_survivors), steep, fate);
      if (fate.tail != "transient") {
        // one tail verdict: a resolved C is a tail seen with its weight measured, not "unresolved"
        if (amplitude_resolved(amplitude)) return with_near(tail_from_amplitude(scene, c, alpha, *amplitude, steep));
        return unresolved_tail(c, alpha, *fit, seen, rotating);
      }
      fate.note +=
          "; alpha, P at the first crossing, is not resolved (the tail is seen from t = " + std::to_string(c.t[seen]) +
          ")";
      return with_near(fate);
    }
  }
  if (!alpha.value && near && fit && fit->ok)
    if (const std::optional<TailClass> bump = near_bump(scene, c, alpha, *fit, steep)) return with_near(*bump);
  if (!alpha.value && amplitude_resolved(amplitude))
    return with_near(tail_from_amplitude(scene, c, alpha, *amplitude, steep));
  if (!alpha.value) return no_tail(scene, c, alpha, rotating);
  TailClass k;
  tail_fate(scene, c, alpha.crossing_time, static_cast<double>(alpha.min_survivors), steep, k);
  return with_near(k);
}

}  // namespace

std::optional<NearRational> near_rational(const Scene& scene) {
  // 2 r omega is the stadium's one leak's theory (docs/tables.md): none for a list of leaks or another table
  if (scene.on_table() || scene.omega.sign() == 0) return std::nullopt;
  const ExactReal x = ExactReal::parse("2") * scene.r * scene.omega;
  const BestApproximations best = best_approximations(x, mpz_class(kNearRationalQ));
  if (best.list.empty()) return std::nullopt;
  const Fraction& f = best.list.back();
  if (best.expansion_exhausted && (x - ExactReal::rational(f.value())).sign() == 0) return std::nullopt;
  NearRational n;
  n.rational = f.q == 1 ? f.p.get_str() : f.text();
  n.q = f.q.get_si();
  n.eps = (x - ExactReal::rational(f.value())).to_double();
  if (scene.r.is_rational()) {
    const mpq_class w = f.value() / (2 * scene.r.as_rational());
    n.omega_rational = w.get_den() == 1 ? w.get_num().get_str() : w.get_str();
  }
  return n;
}

TailClass classify_tail(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha, const KappaFit* fit,
                        const TailAmplitude* amplitude) {
  TailClass k = classify_tail_from_P(scene, c, alpha, fit, amplitude);
  if (k.tail == "transient" && k.near) {
    k.regime = "near-rational";
    k.note += "; near a rational: " + near_text(*k.near) + ", the leak pattern drifts off it";
  }
  return k;
}

}  // namespace rotleak
