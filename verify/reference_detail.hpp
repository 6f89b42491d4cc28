// What the reference trajectories' builder, files, checks and report share (verify/reference*.cpp):
// MPFR numbers at the comparison precision, the stored decimals and hex doubles, the fingerprint hash,
// one replay of a case in any tier (follow), and the error model's pieces (horizon, decisions).
// Internal to verify/: the public interface is verify/reference.hpp.
#pragma once

#include <gmpxx.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/bytes.hpp"
#include "io/files.hpp"
#include "io/json.hpp"
#include "numeric/tier_dispatch.hpp"
#include "verify/reference.hpp"
#include "verify/trace.hpp"

namespace rotleak::reference_detail {

/// Precision at which reported values are compared (the stored digits need far less).
inline constexpr long kCompareBits = 1024;

inline const char* piece_name(Piece p) {
  switch (p) {
    case Piece::top:
      return "top";
    case Piece::right_arc:
      return "right_arc";
    case Piece::bottom:
      return "bottom";
    case Piece::left_arc:
      return "left_arc";
  }
  return "?";
}

inline Piece piece_of(const std::string& s) {
  for (int k = 0; k < 4; ++k)
    if (s == piece_name(static_cast<Piece>(k))) return static_cast<Piece>(k);
  throw std::runtime_error("unknown piece \"" + s + "\"");
}

/// An MPFR number at kCompareBits (heap: the comparisons are few).
struct Big {
  mpfr_t v;
  Big() { mpfr_init2(v, kCompareBits); }
  Big(const Big&) = delete;
  Big& operator=(const Big&) = delete;
  ~Big() { mpfr_clear(v); }
};

inline void parse_big(Big& out, const std::string& text) {
  if (mpfr_set_str(out.v, text.c_str(), 10, MPFR_RNDN) != 0 && !mpfr_number_p(out.v))
    throw std::runtime_error("not a number: \"" + text + "\"");
}

/// |a - b| rounded up to a double; `circular`: the distance on the circle of length 1.
inline double distance(const Big& a, const Big& b, bool circular = false) {
  Big d;
  mpfr_sub(d.v, a.v, b.v, MPFR_RNDN);
  if (circular) {  // d - round(d)
    Big n;
    mpfr_round(n.v, d.v);
    mpfr_sub(d.v, d.v, n.v, MPFR_RNDN);
  }
  return std::abs(mpfr_get_d(d.v, MPFR_RNDU));
}

inline std::string decimal(mpfr_srcptr x, int digits) {
  char* buf = nullptr;
  mpfr_asprintf(&buf, "%.*Re", digits - 1, x);
  std::string s(buf);
  mpfr_free_str(buf);
  return s;
}

/// Significant digits of a stored decimal.
inline int digits_of(const std::string& s) {
  int n = 0;
  bool started = false;
  for (char ch : s) {
    if (ch == 'e' || ch == 'E') break;
    if (ch >= '1' && ch <= '9') started = true;
    if (ch >= '0' && ch <= '9' && started) ++n;
  }
  return std::max(n, 1);
}

inline double from_hex(const std::string& s, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') throw std::runtime_error(what + ": not a number: \"" + s + "\"");
  return v;
}

// FNV-1a, 64 bits (io/bytes.hpp).
inline void mix(std::uint64_t& h, const void* data, std::size_t n) { h = fnv1a(data, n, h); }
inline constexpr std::uint64_t kHashSeed = kFnvOffset;

/// Mixes the exact value of x (sign, exponent, odd significand in hex): independent of the type's layout.
template <class R>
inline void mix_value(std::uint64_t& h, const R& x) {
  mpfr_t m;
  mpfr_init2(m, 4096);  // exact for every tier here (a double-double's two parts included)
  num_traits<R>::to_mpfr(m, x);
  std::string text = "0";
  if (!mpfr_zero_p(m)) {
    mpz_class z;
    long e = mpfr_get_z_2exp(z.get_mpz_t(), m);
    const mp_bitcnt_t tz = mpz_scan1(z.get_mpz_t(), 0);
    z >>= tz;
    e += static_cast<long>(tz);
    text = z.get_str(16) + "p" + std::to_string(e);
  }
  mpfr_clear(m);
  mix(h, text.data(), text.size());
  mix(h, "|", 1);
}

/// One collision as the replays see it: reported values at kCompareBits.
struct Seen {
  Piece piece;
  bool in_leak;
  Big t, s, p, phase;
  std::uint64_t hash;
};

/// Follows c's particle through at most K collisions in R (the trace of verify/trace.hpp), calling
/// on(k, Seen&, step) after each; stops when on returns false. Interval tiers may throw UncertainDecision.
template <class R, class On>
inline void follow(const Scene& scene, const InitialDraw& draw, std::size_t K, On&& on) {
  const Model<R> model = model_of<R>(scene);
  std::uint64_t h = kHashSeed;
  trace(model, draw, K, [&](const TraceStep<R>& st) {
    Seen seen;
    seen.piece = st.piece;
    seen.in_leak = st.in_leak;
    const R s = model.stadium.s_of(st.piece, st.q);
    const R p = model.stadium.birkhoff_p(st.piece, st.q, st.v);
    const R c = model.leak.schedule().phase(st.t);
    num_traits<R>::to_mpfr(seen.t.v, st.t);
    num_traits<R>::to_mpfr(seen.s.v, s);
    num_traits<R>::to_mpfr(seen.p.v, p);
    num_traits<R>::to_mpfr(seen.phase.v, c);
    const int code = static_cast<int>(st.piece) * 2 + (st.in_leak ? 1 : 0);
    mix(h, &code, sizeof code);
    mix_value(h, st.t);
    mix_value(h, st.q.x);
    mix_value(h, st.q.y);
    mix_value(h, st.v.x);
    mix_value(h, st.v.y);
    seen.hash = h;
    return on(st.k, seen, st, model);
  });
}

inline double perimeter(const Scene& sc) { return Stadium<double>(sc.d, sc.r).perimeter(); }
inline double omega_of(const Scene& sc) { return round_exact<double>(sc.omega); }

/// max(|dt|, L |ds| on the circle, |dp|) between what a tier saw and the reference.
inline double divergence(const Seen& a, const Big& t, const Big& s, const Big& p, double L) {
  return std::max({distance(a.t, t), L * distance(a.s, s, true), distance(a.p, p)});
}

struct ParsedStep {
  Big t, s, p;
  double resolution = 0;  ///< what the stored digits cannot say, in the metric
  double t_abs = 0;
  double junction = 0;  ///< distance along the boundary to the nearest junction (which piece is hit)
};

inline std::vector<ParsedStep> parse_steps(const RefCase& c, double L) {
  std::vector<ParsedStep> out(c.steps.size());
  MpfrPrecision working(kCompareBits);
  const Stadium<Mpfr> stadium(c.scene.d, c.scene.r);
  Big j[4];
  for (int k = 0; k < 4; ++k) mpfr_set(j[k].v, stadium.junction(k).data(), MPFR_RNDN);
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    const RefStep& st = c.steps[i];
    parse_big(out[i].t, st.t);
    parse_big(out[i].s, st.s);
    parse_big(out[i].p, st.p);
    out[i].t_abs = std::abs(mpfr_get_d(out[i].t.v, MPFR_RNDN));
    const int d = std::min({digits_of(st.t), digits_of(st.s), digits_of(st.p)});
    out[i].resolution = std::pow(10.0, 1 - d) * std::max({out[i].t_abs, L, 1.0});
    out[i].junction = L * std::min({distance(out[i].s, j[0], true), distance(out[i].s, j[1], true),
                                    distance(out[i].s, j[2], true), distance(out[i].s, j[3], true)});
  }
  return out;
}

/// The leak margin of a collision, in length, that a run at roundoff u resolves.
inline bool decision_required(const RefStep& st, double u, double L, double omega) {
  return std::abs(st.margin) * L > kErrorModelSafety * u * st.gain * (1 + std::abs(omega) * L);
}

/// The last collision a run at roundoff u can follow: its predicted error below kHorizonTolerance,
/// and every hit so far further from a junction than that error (else which piece it hits is moot).
inline std::size_t horizon(const RefCase& c, const std::vector<ParsedStep>& ref, double u) {
  std::size_t h = 0;
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    const double e = u * c.steps[i].gain;
    if (e > kHorizonTolerance || ref[i].junction <= kErrorModelSafety * e) break;
    h = c.steps[i].k;
  }
  return h;
}

inline double unit_roundoff(const std::string& tier) { return std::ldexp(1.0, -static_cast<int>(tier_bits(tier))); }

inline json error_model_json() {
  return {{"metric", "max(|dt|, L |ds|, |dp|)"},
          {"safety", kErrorModelSafety},
          {"horizon_tolerance", kHorizonTolerance},
          {"gain_bits", std::vector<long>(std::begin(kGainBits), std::end(kGainBits))},
          {"gain_saturation", kGainSaturation}};
}

}  // namespace rotleak::reference_detail
