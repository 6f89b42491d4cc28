#include "numeric/ellipse_exact.hpp"

#include "numeric/carlson.hpp"
#include "numeric/mpfi_ops.hpp"
#include "numeric/tiers.hpp"

namespace rotleak {

void enclose_ellipse_quarter(mpfi_ptr out, mpfi_srcptr a, mpfi_srcptr b) {
  const MpfrPrecision bits(mpfi_get_prec(out));  // the interval tier's steps follow the thread's precision
  Mpfi ia, ib;
  mpfi_set(ia.data(), a), mpfi_set(ib.data(), b);
  const Mpfi q = carlson::ellipse_quarter(sqr(ia), sqr(ib));
  mpfi_set(out, q.data());
}

}  // namespace rotleak
