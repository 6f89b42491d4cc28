#include "analysis/circle_law.hpp"

#include <algorithm>
#include <boost/multiprecision/float128.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rotleak {

namespace {

using Q = boost::multiprecision::float128;

const Q kPi = acos(Q(-1));

/// Gauss-Legendre on n points, its nodes and weights on [-1, 1] in Q (Newton on P_n from Tricomi's guesses; Boost's
/// gauss<> does not compile for float128 under C++20).
struct Legendre {
  static constexpr int n = 20;
  Q x[n], w[n];
  Legendre() {
    for (int i = 0; i < n; ++i) {
      Q z = cos(kPi * (Q(i) + Q(0.75)) / (Q(n) + Q(0.5))), dp = 0;
      for (int it = 0; it < 100; ++it) {
        Q p0 = 1, p1 = z;  // P_0, P_1, then up to P_n by Bonnet's recurrence
        for (int k = 2; k <= n; ++k) {
          const Q p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const Q dz = p1 / dp;
        z -= dz;
        if (abs(dz) < 1e-33) break;
      }
      x[i] = z, w[i] = 2 / ((1 - z * z) * dp * dp);
    }
  }
  template <class F>
  Q integrate(F f, const Q& a, const Q& b) const {
    const Q h = (b - a) / 2, c = (a + b) / 2;
    Q sum = 0;
    for (int i = 0; i < n; ++i) sum += w[i] * f(c + h * x[i]);
    return sum * h;
  }
};

Q frac(const Q& x) { return x - floor(x); }

/// The law's quantities at one p.
struct At {
  Q l, eps, advance;  ///< chord, step in the leak's frame, the collision point's advance (turns)
};

At at(double rho, double omega, const Q& p) {
  At a;
  a.l = 2 * Q(rho) * sqrt(1 - p * p);
  a.advance = Q(0.5) - asin(p) / kPi;
  const Q beta = a.advance - Q(omega) * a.l;
  a.eps = beta - round(beta);
  return a;
}

/// The share of the s circle that survives K collisions: all of them in the gap g.
Q survives(std::int64_t K, const Q& eps, const Q& g) {
  if (K <= 0) return 1;
  return std::max(Q(0), g - Q(K - 1) * abs(eps));
}

/// The first p in [a, b] where the increasing f(p) reaches y (bisection to the last bit of Q).
template <class F>
Q crossing(F f, Q a, Q b, const Q& y) {
  for (int i = 0; i < 200 && a < b; ++i) {
    const Q m = (a + b) / 2;
    if (m <= a || m >= b) break;
    (f(m) < y ? a : b) = m;
  }
  return b;
}

}  // namespace

CircleLeakLaw::CircleLeakLaw(double rho, double lambda, double omega, double s_leak, double p_lo, double p_hi,
                             double tau_lo, double tau_hi)
    : rho_(rho),
      lambda_(lambda),
      omega_(omega),
      s_leak_(s_leak),
      p_lo_(p_lo),
      p_hi_(p_hi),
      tau_lo_(tau_lo),
      tau_hi_(tau_hi) {
  const auto refuse = [](const std::string& why) { throw std::invalid_argument("CircleLeakLaw: " + why); };
  if (!(rho > 0)) refuse("rho must be > 0");
  if (!(lambda > 0 && lambda < 1)) refuse("lambda must lie in (0, 1)");
  if (!(p_lo > 0 && p_lo < p_hi && p_hi < 1)) refuse("needs 0 < p_lo < p_hi < 1");
  if (!(tau_lo <= tau_hi)) refuse("needs tau_lo <= tau_hi");
  // |eps| increasing on the band (so the longest lives sit at p_lo), below lambda (no jump over the leak): eps has
  // one sign, and d beta / d theta = -1/pi + 2 omega rho sin theta keeps its sign, where sin theta = 1 / (2 pi omega
  // rho) is outside the band
  const Q e_lo = at(rho, omega, Q(p_lo)).eps, e_hi = at(rho, omega, Q(p_hi)).eps;
  const double turn = omega * rho > 0 ? 1 / (2 * M_PI * omega * rho) : 2.0;
  if (turn >= p_lo && turn <= p_hi) refuse("eps is not monotone in p on the band");
  if (e_lo == 0 || e_lo * e_hi <= 0 || abs(e_hi) <= abs(e_lo)) refuse("needs |eps| > 0 and increasing on the band");
  if (abs(e_hi) >= Q(lambda)) refuse("needs |eps| < lambda on the band (a collision could jump the leak)");
}

CircleLeakLaw::End CircleLeakLaw::escape(double s, double p, double tau) const {
  const At a = at(rho_, omega_, Q(p));
  const Q g = 1 - Q(lambda_);
  // the first collision's place in the leak's frame, from the leak's upper end: in the leak iff v >= g (or v = 0)
  const Q v = frac(Q(s) + a.advance - Q(s_leak_) - Q(omega_) * (Q(tau) + a.l) - Q(lambda_) / 2);
  std::uint64_t k = 1;
  if (v > 0 && v < g) {
    const Q m = a.eps < 0 ? ceil(v / abs(a.eps)) : ceil((g - v) / a.eps);
    k = 1 + static_cast<std::uint64_t>(m);
  }
  return {static_cast<double>(Q(tau) + Q(k) * a.l), k};
}

double CircleLeakLaw::sup_time() const {
  const At a = at(rho_, omega_, Q(p_lo_));
  const Q r = (1 - Q(lambda_)) / abs(a.eps);
  // the most collisions survived with a share > 0: (K - 1) |eps| < g
  const Q K = ceil(r);
  return static_cast<double>(Q(tau_hi_) + (K + 1) * a.l);
}

double CircleLeakLaw::survival(double t_d) const {
  const Q t = t_d, g = 1 - Q(lambda_), lo = tau_lo_, hi = tau_hi_;
  const bool spread = tau_hi_ > tau_lo_;
  // the tau-average of the surviving share at p: K(tau) = floor((t - tau) / l) collisions by t (0 before creation)
  const auto G = [&](const Q& p) {
    const At a = at(rho_, omega_, p);
    if (!spread) return survives(t < lo ? 0 : static_cast<std::int64_t>(floor((t - lo) / a.l)), a.eps, g);
    Q sum = std::max(Q(0), hi - std::max(lo, t - a.l));  // K = 0
    const auto k_lo = std::max<std::int64_t>(1, static_cast<std::int64_t>(floor((t - hi) / a.l)));
    const auto k_hi = static_cast<std::int64_t>(floor((t - lo) / a.l));
    for (std::int64_t k = k_lo; k <= k_hi; ++k) {
      const Q from = std::max(lo, t - Q(k + 1) * a.l), to = std::min(hi, t - Q(k) * a.l);
      if (to > from) sum += (to - from) * survives(k, a.eps, g);
    }
    return sum / (hi - lo);
  };
  // the pieces: where t - k l(p) meets tau_lo or tau_hi, and where (k - 1) |eps(p)| meets g
  const Q p0 = p_lo_, p1 = p_hi_;
  std::vector<Q> cuts{p0, p1};
  const Q l_min = at(rho_, omega_, p1).l;
  const auto e = [&](const Q& p) { return abs(at(rho_, omega_, p).eps); };
  const Q e0 = e(p0), e1 = e(p1);
  const auto k_top = static_cast<std::int64_t>(floor((t - lo) / l_min)) + 1;
  for (std::int64_t k = 1; k <= k_top; ++k) {
    for (const Q& tau : {lo, hi}) {
      const Q c = (t - tau) / (2 * Q(rho_) * Q(k));  // cos theta at the cut
      if (c > 0 && c < 1) cuts.push_back(sqrt(1 - c * c));
    }
    if (k >= 2) {
      const Q y = g / Q(k - 1);
      if (e0 < y && e1 > y) cuts.push_back(crossing(e, p0, p1, y));
    }
  }
  std::sort(cuts.begin(), cuts.end());
  static const Legendre rule;
  Q total = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const Q a = std::max(p0, cuts[i]), b = std::min(p1, cuts[i + 1]);
    if (b > a) total += rule.integrate(G, a, b);
  }
  return static_cast<double>(total / (p1 - p0));
}

}  // namespace rotleak
