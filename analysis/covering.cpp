#include "analysis/covering.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

namespace rotleak {

namespace {

constexpr int kApproxBits = 120;

mpz_class to_mpz(u128 v) {
  mpz_class hi(static_cast<unsigned long>(static_cast<std::uint64_t>(v >> 64)));
  mpz_class lo(static_cast<unsigned long>(static_cast<std::uint64_t>(v)));
  return (hi << 64) + lo;
}

u128 to_u128(const mpz_class& z) {
  const mpz_class hi = z >> 64;
  const mpz_class lo = z - (hi << 64);
  return (static_cast<u128>(hi.get_ui()) << 64) | static_cast<u128>(lo.get_ui());
}

// Nearest integer to x * 2^bits (x >= 0), from a correctly rounded value with ample bits.
mpz_class scaled_round(const ExactReal& x, int bits) {
  mpz_class pow = mpz_class(1) << bits;
  const ExactReal y = x * ExactReal::rational(mpq_class(pow));
  mpfr_t v;
  mpfr_init2(v, bits + 64);
  y.round(v, MPFR_RNDN);
  mpz_class z;
  mpfr_get_z(z.get_mpz_t(), v, MPFR_RNDN);
  mpfr_clear(v);
  return z;
}

void check_open_unit(const ExactReal& v, const char* name) {
  if (v.sign() <= 0 || (v - ExactReal::parse("1")).sign() >= 0)
    throw std::invalid_argument(std::string(name) + " = " + v.text() + ": must be in (0, 1)");
}

}  // namespace

namespace {

/// The circle of the leak's centres in integer units: M units a turn, the step A = x M (x = t_c omega mod 1)
/// and the half width H; exact when x and the half width are rationals whose common denominator fits,
/// else rounded at kApproxBits with the bound on the points' error in c.error_bound.
struct UnitCircle {
  u128 M = 0, A = 0, H = 0;
};

UnitCircle unit_circle(const ExactReal& x, const ExactReal& half_width, Covering& c) {
  UnitCircle u;
  const u128 limit = static_cast<u128>(1) << 125;
  c.exact = false;
  if (x.is_rational() && half_width.is_rational()) {
    mpz_class m;
    mpz_lcm(m.get_mpz_t(), x.as_rational().get_den_mpz_t(), half_width.as_rational().get_den_mpz_t());
    if (m < to_mpz(limit)) {
      c.exact = true;
      u.M = to_u128(m);
      u.A = to_u128(x.as_rational().get_num() * (m / x.as_rational().get_den()));
      u.H = to_u128(half_width.as_rational().get_num() * (m / half_width.as_rational().get_den()));
      c.x_text = x.as_rational().get_str();
    }
  }
  if (!c.exact) {
    u.M = static_cast<u128>(1) << kApproxBits;
    u.A = to_u128(scaled_round(x, kApproxBits)) & (u.M - 1);
    u.H = to_u128(scaled_round(half_width, kApproxBits));
    // each point n x is off by <= n/2 units, each half width by <= 1/2 unit
    c.error_bound = std::ldexp(static_cast<double>(c.N) / 2 + 1, -kApproxBits);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", x.to_double());
    c.x_text = buf;
  }
  return u;
}

struct RawSegment {
  u128 from, to;
  std::uint64_t value;
};

/// The K points n A mod M (sorted, into points) and f_L as segments of constant value, by an exact sweep
/// over the leak intervals' ends [p - H, p + H).
std::vector<RawSegment> sweep(const UnitCircle& u, std::size_t K, std::vector<u128>& points) {
  const u128 M = u.M, A = u.A, H = u.H;
  points.assign(K, 0);
  std::vector<u128> starts(K), ends(K);
  std::uint64_t covering_zero = 0;
  u128 p = 0;
  for (std::size_t n = 0; n < K; ++n) {
    points[n] = p;
    starts[n] = p >= H ? p - H : p + M - H;
    ends[n] = p + H < M ? p + H : p + H - M;
    covering_zero += (p < H) || (p + H > M);  // half-open [p - H, p + H) wraps over 0
    p += A;
    if (p >= M) p -= M;
  }
  std::sort(points.begin(), points.end());
  std::sort(starts.begin(), starts.end());
  std::sort(ends.begin(), ends.end());
  std::vector<RawSegment> raw;  // f_L on [pos, next event)
  raw.reserve(2 * K + 1);
  std::uint64_t value = covering_zero;
  u128 pos = 0;
  std::size_t i = 0, j = 0;
  auto emit = [&](u128 to) {
    if (to == pos) return;
    if (!raw.empty() && raw.back().value == value)
      raw.back().to = to;
    else
      raw.push_back({pos, to, value});
    pos = to;
  };
  while (i < K || j < K) {
    const u128 at = (j >= K || (i < K && starts[i] <= ends[j])) ? starts[i] : ends[j];
    emit(at);
    while (i < K && starts[i] == at) ++value, ++i;
    while (j < K && ends[j] == at) --value, ++j;
  }
  emit(M);
  return raw;
}

/// f_L's segments and metrics: min, max, mean, cv, the zero measure, the longest zero gap, the clusters.
void segment_metrics(const std::vector<RawSegment>& raw, const UnitCircle& u, std::size_t K, Covering& c) {
  const double Md = static_cast<double>(u.M);
  c.min = raw.front().value;
  c.max = raw.front().value;
  const double mean = static_cast<double>(K) * static_cast<double>(2 * u.H) / Md;
  double zero = 0, var = 0, longest = 0;
  for (const RawSegment& s : raw) {
    const double len = static_cast<double>(s.to - s.from) / Md;
    c.min = std::min(c.min, s.value);
    c.max = std::max(c.max, s.value);
    if (s.value == 0) {
      zero += len;
      longest = std::max(longest, len);
    }
    var += len * (static_cast<double>(s.value) - mean) * (static_cast<double>(s.value) - mean);
    c.segments.push_back({static_cast<double>(s.from) / Md, static_cast<double>(s.to) / Md, s.value});
  }
  if (raw.size() > 1 && raw.front().value == 0 && raw.back().value == 0)  // a zero gap across s = 0
    longest = std::max(
        longest, static_cast<double>((raw.front().to - raw.front().from) + (raw.back().to - raw.back().from)) / Md);
  c.zero_measure = zero;
  c.max_zero_gap = longest;
  for (std::size_t k = 0; k < raw.size(); ++k)  // a covered arc starts where f_L rises from 0
    c.clusters += raw[k].value > 0 && raw[(k + raw.size() - 1) % raw.size()].value == 0;
  if (c.clusters == 0 && c.min > 0) c.clusters = 1;  // the whole circle
  c.mean = mean;
  c.cv = std::sqrt(var) / mean;
}

/// The star discrepancy of the sorted points.
double star_discrepancy(const std::vector<u128>& points, u128 M) {
  const std::size_t K = points.size();
  long double disc = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const long double x_k = static_cast<long double>(points[k]) / static_cast<long double>(M);
    disc = std::max({disc, static_cast<long double>(k + 1) / K - x_k, x_k - static_cast<long double>(k) / K});
  }
  return static_cast<double>(disc);
}

/// The gaps between neighbouring points (merged within the rounding when not exact) and whether they take
/// at most three lengths, the third the sum of the other two (the three-distance theorem).
void three_distances(const std::vector<u128>& points, u128 M, Covering& c) {
  const std::size_t K = points.size();
  const double Md = static_cast<double>(M);
  std::map<u128, std::uint64_t> gap_count;
  for (std::size_t k = 0; k + 1 < K; ++k) ++gap_count[points[k + 1] - points[k]];
  ++gap_count[M - points[K - 1] + points[0]];
  std::vector<std::pair<u128, std::uint64_t>> merged;
  const u128 tol = c.exact ? 0 : static_cast<u128>(2 * (c.N + 2));
  for (const auto& [len, count] : gap_count) {
    if (!merged.empty() && len - merged.back().first <= tol)
      merged.back().second += count;
    else
      merged.push_back({len, count});
  }
  std::vector<u128> nonzero;
  for (const auto& [len, count] : merged) {
    GapCount g{static_cast<double>(len) / Md, count, ""};
    if (c.exact) {
      mpq_class q(to_mpz(len), to_mpz(M));
      q.canonicalize();
      g.exact = q.get_str();
    }
    c.gaps.push_back(g);
    if (len > tol) nonzero.push_back(len);
  }
  if (nonzero.size() <= 2)
    c.three_distance_holds = true;
  else if (nonzero.size() == 3) {
    const u128 sum = nonzero[0] + nonzero[1];
    const u128 diff = sum > nonzero[2] ? sum - nonzero[2] : nonzero[2] - sum;
    c.three_distance_holds = diff <= 2 * tol;
  }
}

}  // namespace

Covering mupo_covering(const CoveringInput& in) {
  const auto t0 = std::chrono::steady_clock::now();
  check_open_unit(in.delta, "delta");
  check_open_unit(in.lambda, "lambda");
  if (in.d.sign() <= 0) throw std::invalid_argument("d = " + in.d.text() + ": must be > 0");
  if (in.r.sign() <= 0) throw std::invalid_argument("r = " + in.r.text() + ": must be > 0");
  const ExactReal one = ExactReal::parse("1"), two = ExactReal::parse("2");
  Covering c;
  const mpz_class n_max = floor_exact(in.d / (two * in.r * ExactReal::parse("sqrt(" + in.delta.text() + ")")));
  if (n_max > kMaxCoveringPoints)
    throw std::invalid_argument("delta = " + in.delta.text() + ": gives N = " + n_max.get_str() +
                                " reflections, above the limit " + std::to_string(kMaxCoveringPoints) +
                                " (use a larger delta)");
  c.N = n_max.get_ui();
  // x = t_c omega mod 1, with t_c = 2r(1 + delta)
  ExactReal x = two * in.r * (one + in.delta) * in.omega;
  x = x - ExactReal::rational(mpq_class(floor_exact(x)));
  const UnitCircle u = unit_circle(x, in.lambda / two, c);
  const std::size_t K = static_cast<std::size_t>(c.N) + 1;
  std::vector<u128> points;
  segment_metrics(sweep(u, K, points), u, K, c);
  c.discrepancy = star_discrepancy(points, u.M);
  three_distances(points, u.M, c);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

std::vector<double> covering_profile(const Covering& c, std::size_t bins) {
  std::vector<double> out(bins, 0.0);
  const double w = 1.0 / static_cast<double>(bins);
  for (const Segment& s : c.segments) {
    std::size_t b = static_cast<std::size_t>(s.from * static_cast<double>(bins));
    for (double from = s.from; from < s.to && b < bins; ++b) {
      const double bin_end = static_cast<double>(b + 1) * w;
      const double to = std::min(s.to, bin_end);
      out[b] += static_cast<double>(s.value) * (to - from) / w;
      from = to;
    }
  }
  return out;
}

}  // namespace rotleak
