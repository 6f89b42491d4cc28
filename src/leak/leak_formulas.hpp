// The leak's physics, written once (as geometry/formulas.hpp is for the stadium): its centre at time t
// and the test of a boundary coordinate against it, over one number of any tier (Leak<R>) or a pack of
// lanes (the vectorised kernel). Branches go through the selection hook (numeric/select.hpp).
// Header-only, templates only, no other dependency (see geometry/formulas.hpp for why).
#pragma once

#include <cmath>

#include "numeric/select.hpp"

namespace rotleak::formula {

/// Signed distance on the circle s mod 1 from `centre`, in [-1/2, 1/2).
template <class T>
inline T circular_offset(const T& s, const T& centre) {
  using std::floor;
  const T delta = s - centre;
  return delta - floor(delta + T(0.5));
}

/// The leak's centre at time t: frac(start + omega t), omega carried as hi + lo. The product hi t is
/// split exactly, hi t = prod + err, with err = product_error(hi, t, prod) (a true fused multiply-add,
/// or the tier's equivalent), so the phase keeps T's absolute precision however large omega t grows.
template <class T, class ProductError>
inline T leak_phase(const T& hi, const T& lo, const T& start, const T& t, const ProductError& product_error) {
  using std::floor;
  const T prod = hi * t;
  const T err = product_error(hi, t, prod);
  const T whole = floor(prod);
  T c = (prod - whole) + (err + lo * t) + start;
  c = c - floor(c);
  return c;
}

/// Is boundary coordinate s inside the leak of half width `half_width` centred at `centre`?
template <class T>
inline mask_of<T> in_leak(const T& s, const T& centre, const T& half_width) {
  using std::abs;
  return abs(circular_offset(s, centre)) <= half_width;
}

/// How far boundary coordinate s lies from the nearer end of the leak (inside or out).
template <class T>
inline T distance_to_leak_end(const T& s, const T& centre, const T& half_width) {
  using std::abs;
  return abs(T(abs(circular_offset(s, centre)) - half_width));
}

/// Can the leak centred at `centre` touch a piece whose middle is at s = mid? Only within `reach` of it.
template <class T>
inline mask_of<T> may_touch(const T& mid, const T& centre, const T& reach) {
  using std::abs;
  return abs(circular_offset(mid, centre)) <= reach;
}

}  // namespace rotleak::formula
