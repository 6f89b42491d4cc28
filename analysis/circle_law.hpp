// An exact reference for samplers of the escape time: the circle, integrable, with one leak turning round it
// (docs/model.md, "An exact reference: the circle with a turning leak"). On a circle of radius rho a start keeps its
// angle theta = asin p: each flight is a chord of length l = 2 rho cos theta and moves the collision point by
// (pi - 2 theta) / 2 pi of the boundary, so in the frame of a leak turning at omega the k-th collision sits at
// u_1 + (k - 1) eps, eps = (pi - 2 theta) / 2 pi - omega l (mod 1). Where |eps| < lambda the progression cannot jump
// the leak, so a start survives K collisions iff all of them fit in the gap g = 1 - lambda: the starts that do are a
// share (g - (K - 1) |eps|)^+ of the s circle. P(T > t) is then an integral over p and tau of a piecewise-smooth
// function whose pieces are known: Gauss-Legendre on each, in __float128.
#pragma once

#include <cstdint>

namespace rotleak {

/// The law of T for starts uniform in s on [0, 1), p in [p_lo, p_hi] (one sign, 0 < p_lo < p_hi < 1) and tau in
/// [tau_lo, tau_hi] (equal: every start then), on the circle of radius rho with a leak of width lambda (a share of the
/// boundary, in (0, 1)) whose centre turns at omega turns per unit time towards +s (rotleak's conventions:
/// docs/model.md). The constructor refuses a band where the law above does not hold: |eps| >= lambda somewhere, eps
/// zero or not monotone in p on it.
class CircleLeakLaw {
 public:
  CircleLeakLaw(double rho, double lambda, double omega, double s_leak, double p_lo, double p_hi, double tau_lo,
                double tau_hi);

  /// The escape time of the start (s, p, tau) in closed form (p in the band), and its collision.
  struct End {
    double t = 0;
    std::uint64_t collision = 0;
  };
  End escape(double s, double p, double tau) const;
  /// P(T > t) for the band's uniform law.
  double survival(double t) const;
  /// The supremum of T over the band: P(T > t) > 0 exactly below it.
  double sup_time() const;

 private:
  double rho_, lambda_, omega_, s_leak_, p_lo_, p_hi_, tau_lo_, tau_hi_;
};

}  // namespace rotleak
