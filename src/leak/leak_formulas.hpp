// The leak's physics, written once (as geometry/formulas.hpp is for the stadium): its centre at time t
// and the test of a boundary coordinate against it, over one number of any tier (Leak<R>) or a pack of
// lanes (the vectorised kernel). Branches go through the selection hook (numeric/select.hpp).
// Header-only, templates only, no other dependency (see geometry/formulas.hpp for why).
#pragma once

#include <cmath>

#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak::formula {

/// Signed distance on the circle s mod 1 from `centre`, in [-1/2, 1/2).
template <class T>
ROTLEAK_HD inline T circular_offset(const T& s, const T& centre) {
  using std::floor;
  const T delta = s - centre;
  return delta - floor(delta + T(0.5));
}

/// The leak's centre at time t: frac(start + omega t), omega carried as hi + lo. The product hi t is
/// split exactly, hi t = prod + err, with err = product_error(hi, t, prod) (a true fused multiply-add,
/// or the tier's equivalent), so the phase keeps T's absolute precision however large omega t grows.
template <class T, class ProductError>
ROTLEAK_HD inline T leak_phase(const T& hi, const T& lo, const T& start, const T& t,
                               const ProductError& product_error) {
  using std::floor;
  const T prod = hi * t;
  const T err = product_error(hi, t, prod);
  const T whole = floor(prod);
  T c = (prod - whole) + (err + lo * t) + start;
  c = c - floor(c);
  return c;
}

/// A cheap leak centre for a first look: start + hi t, neither reduced modulo 1 nor corrected by the exact
/// error of hi t or by lo t. circular_offset(s, it) differs from circular_offset(s, leak_phase(...)) by at
/// most rough_phase_bound(hi, lo, t_max) for 0 <= t <= t_max and start in [0, 1) (docs/model.md, "The
/// moving leak's first look"), so a decision farther than that from an edge is the exact phase's.
template <class T>
ROTLEAK_HD inline T rough_leak_phase(const T& hi, const T& start, const T& t) {
  const T prod = hi * t;
  return prod + start;
}

/// The bound of rough_leak_phase over double: with u = 2^-53, the rough centre is within 3u (|hi| t + 1) of
/// start + omega t (two roundings; omega - hi - lo is below u^2 |hi|), lo t is dropped (|lo| t), the offset's
/// difference s - c rounds once more (u (|hi| t + 2); the subtraction of its floor is exact), and the exact
/// phase and its offset are within 6u of the truth: 4u |hi| t_max + |lo| t_max + 12u, taken twice.
ROTLEAK_HD inline double rough_phase_bound(double hi, double lo, double t_max) {
  using std::abs;
  constexpr double u = 0x1p-53;
  return 2 * (4 * u * abs(hi) * t_max + abs(lo) * t_max + 12 * u);
}

/// Is boundary coordinate s inside the leak of half width `half_width` centred at `centre`?
template <class T>
ROTLEAK_HD inline mask_of<T> in_leak(const T& s, const T& centre, const T& half_width) {
  using std::abs;
  return abs(circular_offset(s, centre)) <= half_width;
}

/// How far boundary coordinate s lies from the nearer end of the leak (inside or out).
template <class T>
ROTLEAK_HD inline T distance_to_leak_end(const T& s, const T& centre, const T& half_width) {
  using std::abs;
  return abs(T(abs(circular_offset(s, centre)) - half_width));
}

/// Can the leak centred at `centre` touch a piece whose middle is at s = mid? Only within `reach` of it.
template <class T>
ROTLEAK_HD inline mask_of<T> may_touch(const T& mid, const T& centre, const T& reach) {
  using std::abs;
  return abs(circular_offset(mid, centre)) <= reach;
}

}  // namespace rotleak::formula
