#include "analysis/tail_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "analysis/continued_fraction.hpp"
#include "analysis/fits.hpp"
#include "geometry/stadium.hpp"
#include "numeric/input.hpp"

namespace rotleak {

double cap_passage_mean() { return 0.75 * std::log(3.0); }

namespace {

/// Orbit phases averaged for C, and for the sweep (where each phase also samples x).
constexpr int kPhasesAmplitude = 2048, kPhasesSweep = 256, kPointsPerGap = 128;

struct Geometry {
  double d = 2, L = 0, lambda = 0.01;
};

Geometry geometry_of(const Scene& scene) {
  const Stadium<double> st(scene.d, scene.r);
  return {scene.d.to_double(), st.perimeter(), scene.width.to_double()};
}

struct Gap {
  double a = 0, b = 0, weight = 1;  ///< x range on the straight edge, and its factor (1, 1 + G, (1 + G) / (1 - G))
};

/// The lattice one rational leaves: top-edge leak positions uT + k / q', bottom-edge ones uB + k / q' (in s, as
/// positions x / L of the orbit on the top edge), sliding at +eps and -eps.
struct Lattice {
  long long q = 1;       ///< q'
  bool averaged = true;  ///< uT uniform over [0, 1 / q') (an orbit's own phase); else uT = start
  double c = 0.5;        ///< uB = c - uT
  double start = 0;
  double eps = 0;
};

/// Free gaps of the straight edge [-d/2, d/2] for lattice offsets uT, uB.
void free_gaps(const Geometry& g, const Lattice& lat, double uT, double uB, std::vector<Gap>& gaps,
               std::vector<std::pair<double, double>>& iv) {
  const double per = 1.0 / static_cast<double>(lat.q), hw = g.lambda * g.L / 2, half = g.d / 2;
  const double lim = (half + hw) / g.L;
  iv.clear();
  for (const double base : {uT, uB}) {
    const double s0 = base - std::floor(base / per) * per;
    for (double k = std::ceil((-lim - s0) / per); s0 + k * per <= lim; k += 1) {
      const double x = (s0 + k * per) * g.L;
      iv.emplace_back(x - hw, x + hw);
    }
  }
  std::sort(iv.begin(), iv.end());
  const double G = cap_passage_mean();
  const auto weight = [&](bool cap_a, bool cap_b) {
    const int caps = int(cap_a) + int(cap_b);
    return caps == 0 ? 1.0 : caps == 1 ? 1 + G : (1 + G) / (1 - G);
  };
  gaps.clear();
  double cur = -half;
  bool cur_cap = true;
  for (const auto& [a, b] : iv) {
    if (b <= -half || a >= half) continue;
    if (a > cur) gaps.push_back({cur, a, weight(cur_cap, false)});
    if (b > cur) {
      cur = b;
      cur_cap = false;
    }
  }
  if (cur < half) gaps.push_back({cur, half, weight(cur_cap, true)});
}

double mod(double v, double per) { return v - std::floor(v / per) * per; }

/// C and the free share: (1 / L) <sum over gaps of weight h^2> over the orbit phases.
std::pair<double, double> amplitude_of(const Geometry& g, const Lattice& lat) {
  const int n = lat.averaged ? kPhasesAmplitude : 1;
  const double per = 1.0 / static_cast<double>(lat.q);
  std::vector<Gap> gaps;
  std::vector<std::pair<double, double>> iv;
  double sum = 0;
  int free = 0;
  for (int i = 0; i < n; ++i) {
    const double uT = lat.averaged ? (i + 0.5) / n * per : lat.start;
    free_gaps(g, lat, uT, lat.c - uT, gaps, iv);
    if (gaps.size() == 1 && gaps[0].a == -g.d / 2 && gaps[0].b == g.d / 2) ++free;  // no leak on the edges
    for (const Gap& gp : gaps) sum += gp.weight * (gp.b - gp.a) * (gp.b - gp.a);
  }
  return {sum / n / g.L, static_cast<double>(free) / n};
}

/// The sweep: each point x of a free gap is removed when the first sliding leak interval reaches it; t P(t) is
/// (1 / L) <sum over gaps of weight h |part of the gap not yet swept at t|>. Returns (removal time, weight) pairs
/// whose weights sum to C.
std::vector<std::pair<double, double>> sweep_samples(const Geometry& g, const Lattice& lat) {
  const int n = lat.averaged ? kPhasesSweep : 1;
  const double per = 1.0 / static_cast<double>(lat.q), speed = std::abs(lat.eps);
  std::vector<Gap> gaps;
  std::vector<std::pair<double, double>> iv, out;
  for (int i = 0; i < n; ++i) {
    const double uT = lat.averaged ? (i + 0.5) / n * per : lat.start, uB = lat.c - uT;
    free_gaps(g, lat, uT, uB, gaps, iv);
    for (const Gap& gp : gaps) {
      const double h = gp.b - gp.a, w = gp.weight * h * (h / kPointsPerGap) / n / g.L;
      for (int j = 0; j < kPointsPerGap; ++j) {
        const double s = (gp.a + (j + 0.5) / kPointsPerGap * h) / g.L, hw = g.lambda / 2;
        // top lattice moves with eps, bottom lattice against it: distance to the first interval coming at s
        const double dT = lat.eps > 0 ? mod(s - uT - hw, per) : mod(uT - s - hw, per);
        const double dB = lat.eps > 0 ? mod(uB - s - hw, per) : mod(s - uB - hw, per);
        out.emplace_back(std::min(dT, dB) / speed, w);
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The first time the remaining weight of the sweep falls to `share` of its total.
double sweep_time(const std::vector<std::pair<double, double>>& samples, double share) {
  double total = 0;
  for (const auto& s : samples) total += s.second;
  double gone = 0;
  for (const auto& [t, w] : samples) {
    gone += w;
    if (total - gone <= share * total) return t;
  }
  return samples.empty() ? 0 : samples.back().first;
}

/// Where C / t meets exp(-kappa0 t), beyond 1 / kappa0 (at 1 / kappa0 itself when C / t already lies above there).
double crossing_of(double C, double kappa0) {
  if (!(C > 0)) return std::numeric_limits<double>::infinity();
  return two_part_crossing(C, 0, kappa0, 2).value_or(1 / kappa0);
}

/// The weight of the sweep not yet removed at t (samples sorted by removal time).
double remaining(const std::vector<std::pair<double, double>>& samples, double t) {
  double left = 0;
  for (auto it =
           std::upper_bound(samples.begin(), samples.end(), std::make_pair(t, std::numeric_limits<double>::infinity()));
       it != samples.end(); ++it)
    left += it->second;
  return left;
}

Lattice lattice_of(const mpq_class& rational, double eps, double start) {
  Lattice lat;
  const mpz_class Q = rational.get_den();
  lat.q = Q % 2 == 0 ? Q.get_si() / 2 : Q.get_si();
  lat.averaged = rational != 0;  // an orbit's phase spreads the lattice unless the rational is 0 (a slow leak)
  lat.c = 0.5 - mod(rational.get_d(), 1.0);
  lat.start = start;
  lat.eps = eps;
  return lat;
}

/// omega < 0 is the mirror image (s -> -s) of |omega| with start -> -start.
double mirrored_start(const Scene& scene) { return (scene.omega.sign() < 0 ? -1 : 1) * scene.start.to_double(); }

std::string fmt(const char* f, double v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

namespace {

/// The candidates of a scene: the tail on each best approximation of 2 r omega that leaves gaps (2 q' lambda
/// < 1), or on 0 for a stationary leak, with the sweep of each (empty on its rational).
struct Candidates {
  std::vector<LatticeTail> tails;
  std::vector<std::vector<std::pair<double, double>>> sweeps;
};

Candidates candidates_of(const Scene& scene, const Geometry& g, double kappa0) {
  Candidates out;
  const int sign = scene.omega.sign();
  const double start = mirrored_start(scene);
  const auto evaluate = [&](const mpq_class& rational, double eps) {
    LatticeTail lt;
    const mpz_class P = rational.get_num(), Q = rational.get_den();
    lt.rational = Q == 1 ? P.get_str() : rational.get_str();
    lt.Q = Q.get_si();
    lt.eps = eps;
    const Lattice lat = lattice_of(rational, eps, start);
    lt.lattice = lat.q;
    const auto [C, free] = amplitude_of(g, lat);
    lt.amplitude = C;
    lt.free_fraction = free;
    lt.crossing = crossing_of(C, kappa0);
    std::vector<std::pair<double, double>> samples;
    if (eps != 0 && C > 0) {
      samples = sweep_samples(g, lat);
      lt.half = sweep_time(samples, 0.5);
      lt.end = sweep_time(samples, 0.1);
    }
    lt.forms = C > 0 && lt.crossing < scene.t_max && (!lt.end || lt.crossing < *lt.end);
    if (C > 0) {
      out.tails.push_back(std::move(lt));
      out.sweeps.push_back(std::move(samples));
    }
  };
  if (sign == 0) {
    evaluate(mpq_class(0), 0);
    return out;
  }
  const ExactReal x =
      sign < 0 ? -(ExactReal::parse("2") * scene.r * scene.omega) : ExactReal::parse("2") * scene.r * scene.omega;
  const mpz_class qmax(static_cast<long>(std::ceil(2 / g.lambda)));
  for (const Fraction& f : best_approximations(x, qmax).list) {
    const double eps = (x - ExactReal::rational(f.value())).to_double() / (2 * scene.r.to_double());
    evaluate(f.value(), eps);
  }
  return out;
}

/// The tail that lives longest among those that form; else the one nearest to forming; null if none.
const LatticeTail* pick_candidate(const std::vector<LatticeTail>& tails, double t_max) {
  const LatticeTail* pick = nullptr;
  const auto life = [&](const LatticeTail& l) { return l.end ? *l.end : std::numeric_limits<double>::infinity(); };
  for (const LatticeTail& l : tails)
    if (l.forms && (!pick || life(l) > life(*pick) || (life(l) == life(*pick) && l.amplitude > pick->amplitude)))
      pick = &l;
  if (!pick)
    for (const LatticeTail& l : tails)
      if (!pick || std::min(life(l), t_max) / l.crossing > std::min(life(*pick), t_max) / pick->crossing) pick = &l;
  return pick;
}

/// The regime the picked tail implies.
std::string predicted_regime(int sign, const TailPrediction& out, const LatticeTail& pick, double t_max) {
  if (sign == 0) return "stationary";
  if (!out.forms) return "mid";
  if (pick.rational == "0") return "low";
  if (out.end && *out.end < t_max) return "near-rational";
  return "high";
}

/// The prediction in one sentence.
std::string prediction_note(const Scene& scene, const TailPrediction& out, const LatticeTail& pick) {
  const int sign = scene.omega.sign();
  std::string n = sign == 0 ? "stationary leak" : "2 r omega = " + pick.rational;
  if (sign != 0 && pick.eps != 0)
    n += (pick.eps < 0 ? " - " : " + ") + fmt("%.3g", std::abs(2 * scene.r.to_double() * pick.eps));
  n += fmt(": C = %.3g", pick.amplitude);
  if (pick.free_fraction > 0)
    n += fmt(" (%.0f%% of orbit phases see no leak on the straight edges)", 100 * pick.free_fraction);
  n += fmt(", crossing the chaotic part at t ~ %.3g", pick.crossing);
  if (pick.end) n += fmt("; the lattice slides off it and the tail is gone by t ~ %.3g", *pick.end);
  n += out.forms                      ? "; a tail forms"
       : pick.crossing >= scene.t_max ? "; no tail before t_max"
                                      : "; no tail: swept before it shows";
  return n;
}

}  // namespace

TailPrediction predict_tail(const Scene& scene) {
  const Geometry g = geometry_of(scene);
  if (!(g.lambda > 0) || g.lambda >= 0.5)
    throw InputError("leak.width", scene.width_text, "the tail model needs 0 < width < 1/2");
  TailPrediction out;
  out.kappa0 = small_hole_rate(scene);
  const int sign = scene.omega.sign();
  Candidates cands = candidates_of(scene, g, out.kappa0);
  out.candidates = std::move(cands.tails);
  const LatticeTail* pick = pick_candidate(out.candidates, scene.t_max);
  if (!pick) {
    out.regime = sign == 0 ? "stationary" : "mid";
    out.note = "no rational of 2 r omega with q' < 1 / (2 lambda): the leak lattices cover the straight edges";
    return out;
  }
  out.forms = pick->forms;
  out.amplitude = pick->amplitude;
  out.end = pick->end;
  out.half = pick->half;
  out.rational = pick->rational;
  out.Q = pick->Q;
  out.eps = pick->eps;
  out.crossing = pick->crossing;
  out.free_fraction = pick->free_fraction;
  if (pick->end && std::isfinite(pick->crossing) && 1.5 * *pick->end > pick->crossing) {
    const double a = std::log(pick->crossing), b = std::log(1.5 * *pick->end);
    const auto& samples = cands.sweeps[static_cast<std::size_t>(pick - out.candidates.data())];
    for (int i = 0; i < 24; ++i) {
      const double t = std::exp(a + (b - a) * i / 23);
      out.curve.emplace_back(t, remaining(samples, t));
    }
  }
  out.regime = predicted_regime(sign, out, *pick, scene.t_max);
  out.note = prediction_note(scene, out, *pick);
  return out;
}

}  // namespace rotleak
