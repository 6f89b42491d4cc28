// The selection hook of the shared physics formulas (geometry/formulas.hpp, leak/leak_formulas.hpp), for one
// number of any tier. The formulas are written once over a number type T and its comparison result (a
// bool here); the vectorised kernel (sim/kernel/simd_pack.ipp) defines the same names for its packs of
// lanes and lane masks, and argument-dependent lookup picks them there.
// - select(c, a, b): a where c holds, else b; both already computed (cheap, comparison-free operands).
// - choose(c, a, b): a() where c holds, else b(); for one number only the branch taken is evaluated, so
//   an MPFR tier pays for one and an interval tier never evaluates (or compares) the other. A pack
//   evaluates both and selects per lane (no branch on data).
// - both(c, f): c and then f(); for one number f() is not called when c is false (the interval tier's
//   comparison inside f() could be undecided where c already answers).
// - none(c): c holds for no lane, so what follows may be skipped (one number: !c).
// An interval type's comparison throws when its answer is not certain (numeric/mpfr_real.hpp), so a
// certified run through these formulas still refuses every undecided branch.
#pragma once

#include <type_traits>

#include "numeric/device.hpp"

namespace rotleak {

template <class T>
ROTLEAK_HD inline T select(bool c, const T& a, const std::type_identity_t<T>& b) {
  return c ? a : b;
}

template <class F, class G>
ROTLEAK_HD inline auto choose(bool c, const F& a, const G& b) -> decltype(a()) {
  if (c) return a();
  return b();
}

template <class F>
ROTLEAK_HD inline bool both(bool c, const F& f) {
  return c && f();
}

/// Whether c holds for no lane: for one number, !c (a pack: no lane of its mask).
ROTLEAK_HD inline bool none(bool c) { return !c; }

/// What comparing two T gives: bool for a number, a lane mask for a pack.
template <class T>
using mask_of = decltype(std::declval<const T&>() < std::declval<const T&>());

}  // namespace rotleak
