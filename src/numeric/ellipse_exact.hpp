// The quarter perimeter of an ellipse enclosed in MPFI (the exact node ExactReal::ellipse_quarter,
// numeric/exact.hpp): Carlson's integrals on intervals (numeric/carlson.hpp), a rigorous enclosure.
#pragma once

#include <mpfi.h>

namespace rotleak {

/// out = an enclosure, at out's precision, of int_0^(pi/2) sqrt(a^2 cos^2 t + b^2 sin^2 t) dt for every a, b in the
/// intervals a, b (both strictly positive).
void enclose_ellipse_quarter(mpfi_ptr out, mpfi_srcptr a, mpfi_srcptr b);

}  // namespace rotleak
