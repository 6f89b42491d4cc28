// MPFR and MPFI numbers whose working precision is per thread (a scoped guard sets it), not a
// process-wide default: Boost 1.74's variable-precision mpfr_float keeps one static default for all
// threads, which an OpenMP audit cannot share. Each new value takes the calling thread's precision.
//
// Interval comparisons are predicates in CGAL's sense: they answer when the enclosures decide, and
// throw UncertainDecision when they overlap, so a generic branch either runs certified or stops.
#pragma once

#include <mpfi.h>
#include <mpfr.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace rotleak {

/// Working precision of new Mpfr / Mpfi values on this thread.
class MpfrPrecision {
 public:
  explicit MpfrPrecision(mpfr_prec_t bits) : saved_(bits_) { bits_ = bits; }
  ~MpfrPrecision() { bits_ = saved_; }
  MpfrPrecision(const MpfrPrecision&) = delete;
  MpfrPrecision& operator=(const MpfrPrecision&) = delete;
  static mpfr_prec_t current() { return bits_; }

 private:
  mpfr_prec_t saved_;
  static inline thread_local mpfr_prec_t bits_ = 256;
};

class Mpfr {
 public:
  Mpfr() { mpfr_init2(v_, MpfrPrecision::current()), mpfr_set_zero(v_, 1); }
  Mpfr(double x) { mpfr_init2(v_, MpfrPrecision::current()), mpfr_set_d(v_, x, MPFR_RNDN); }  // NOLINT: implicit like a built-in
  Mpfr(int x) { mpfr_init2(v_, MpfrPrecision::current()), mpfr_set_si(v_, x, MPFR_RNDN); }     // NOLINT
  Mpfr(long x) { mpfr_init2(v_, MpfrPrecision::current()), mpfr_set_si(v_, x, MPFR_RNDN); }    // NOLINT
  Mpfr(const Mpfr& o) { mpfr_init2(v_, mpfr_get_prec(o.v_)), mpfr_set(v_, o.v_, MPFR_RNDN); }
  Mpfr(Mpfr&& o) noexcept { mpfr_init2(v_, MPFR_PREC_MIN), mpfr_swap(v_, o.v_); }
  Mpfr& operator=(const Mpfr& o) {
    if (this != &o) {
      mpfr_set_prec(v_, mpfr_get_prec(o.v_));
      mpfr_set(v_, o.v_, MPFR_RNDN);
    }
    return *this;
  }
  Mpfr& operator=(Mpfr&& o) noexcept {
    mpfr_swap(v_, o.v_);
    return *this;
  }
  ~Mpfr() { mpfr_clear(v_); }

  mpfr_ptr data() { return v_; }
  mpfr_srcptr data() const { return v_; }

#define ROTLEAK_MPFR_BINARY(op, fn)                             \
  friend Mpfr operator op(const Mpfr& a, const Mpfr& b) {       \
    Mpfr r;                                                     \
    fn(r.v_, a.v_, b.v_, MPFR_RNDN);                            \
    return r;                                                   \
  }                                                             \
  Mpfr& operator op##=(const Mpfr& b) { return *this = *this op b; }
  ROTLEAK_MPFR_BINARY(+, mpfr_add)
  ROTLEAK_MPFR_BINARY(-, mpfr_sub)
  ROTLEAK_MPFR_BINARY(*, mpfr_mul)
  ROTLEAK_MPFR_BINARY(/, mpfr_div)
#undef ROTLEAK_MPFR_BINARY
  friend Mpfr operator-(const Mpfr& a) {
    Mpfr r;
    mpfr_neg(r.v_, a.v_, MPFR_RNDN);
    return r;
  }
  friend bool operator<(const Mpfr& a, const Mpfr& b) { return mpfr_less_p(a.v_, b.v_); }
  friend bool operator<=(const Mpfr& a, const Mpfr& b) { return mpfr_lessequal_p(a.v_, b.v_); }
  friend bool operator>(const Mpfr& a, const Mpfr& b) { return mpfr_greater_p(a.v_, b.v_); }
  friend bool operator>=(const Mpfr& a, const Mpfr& b) { return mpfr_greaterequal_p(a.v_, b.v_); }
  friend bool operator==(const Mpfr& a, const Mpfr& b) { return mpfr_equal_p(a.v_, b.v_); }
  friend bool operator!=(const Mpfr& a, const Mpfr& b) { return !mpfr_equal_p(a.v_, b.v_); }

#define ROTLEAK_MPFR_UNARY(name, fn)  \
  friend Mpfr name(const Mpfr& a) {   \
    Mpfr r;                           \
    fn(r.v_, a.v_, MPFR_RNDN);        \
    return r;                         \
  }
  ROTLEAK_MPFR_UNARY(sqrt, mpfr_sqrt)
  ROTLEAK_MPFR_UNARY(sin, mpfr_sin)
  ROTLEAK_MPFR_UNARY(cos, mpfr_cos)
  ROTLEAK_MPFR_UNARY(abs, mpfr_abs)
#undef ROTLEAK_MPFR_UNARY
  friend Mpfr floor(const Mpfr& a) {
    Mpfr r;
    mpfr_floor(r.v_, a.v_);
    return r;
  }
  friend Mpfr atan2(const Mpfr& y, const Mpfr& x) {
    Mpfr r;
    mpfr_atan2(r.v_, y.v_, x.v_, MPFR_RNDN);
    return r;
  }
  friend Mpfr fma(const Mpfr& a, const Mpfr& b, const Mpfr& c) {
    Mpfr r;
    mpfr_fma(r.v_, a.v_, b.v_, c.v_, MPFR_RNDN);
    return r;
  }

 private:
  mpfr_t v_;
};

/// An interval comparison that the enclosures cannot decide.
class UncertainDecision : public std::runtime_error {
 public:
  UncertainDecision() : std::runtime_error("interval comparison undecided") {}
};

class Mpfi {
 public:
  Mpfi() { mpfi_init2(v_, MpfrPrecision::current()), mpfi_set_si(v_, 0); }
  Mpfi(double x) { mpfi_init2(v_, MpfrPrecision::current()), mpfi_set_d(v_, x); }  // NOLINT
  Mpfi(int x) { mpfi_init2(v_, MpfrPrecision::current()), mpfi_set_si(v_, x); }     // NOLINT
  Mpfi(long x) { mpfi_init2(v_, MpfrPrecision::current()), mpfi_set_si(v_, x); }    // NOLINT
  Mpfi(const Mpfi& o) { mpfi_init2(v_, mpfi_get_prec(o.v_)), mpfi_set(v_, o.v_); }
  Mpfi(Mpfi&& o) noexcept { mpfi_init2(v_, MPFR_PREC_MIN), mpfi_swap(v_, o.v_); }
  Mpfi& operator=(const Mpfi& o) {
    if (this != &o) {
      mpfi_set_prec(v_, mpfi_get_prec(o.v_));
      mpfi_set(v_, o.v_);
    }
    return *this;
  }
  Mpfi& operator=(Mpfi&& o) noexcept {
    mpfi_swap(v_, o.v_);
    return *this;
  }
  ~Mpfi() { mpfi_clear(v_); }

  mpfi_ptr data() { return v_; }
  mpfi_srcptr data() const { return v_; }
  /// Width of the enclosure, rounded up, as a double.
  double width() const {
    mpfr_t w;
    mpfr_init2(w, 53);
    mpfi_diam_abs(w, v_);
    const double d = mpfr_get_d(w, MPFR_RNDU);
    mpfr_clear(w);
    return d;
  }
  double lo() const { return mpfr_get_d(&v_->left, MPFR_RNDD); }
  double hi() const { return mpfr_get_d(&v_->right, MPFR_RNDU); }
  bool contains(mpfr_srcptr x) const { return mpfi_is_inside_fr(x, v_) > 0; }

#define ROTLEAK_MPFI_BINARY(op, fn)                       \
  friend Mpfi operator op(const Mpfi& a, const Mpfi& b) { \
    Mpfi r;                                               \
    fn(r.v_, a.v_, b.v_);                                 \
    return r;                                             \
  }                                                       \
  Mpfi& operator op##=(const Mpfi& b) { return *this = *this op b; }
  ROTLEAK_MPFI_BINARY(+, mpfi_add)
  ROTLEAK_MPFI_BINARY(-, mpfi_sub)
  ROTLEAK_MPFI_BINARY(*, mpfi_mul)
  ROTLEAK_MPFI_BINARY(/, mpfi_div)
#undef ROTLEAK_MPFI_BINARY
  friend Mpfi operator-(const Mpfi& a) {
    Mpfi r;
    mpfi_neg(r.v_, a.v_);
    return r;
  }
  // Certain answers only: a < b is true when every point of a is below every point of b, false when
  // no point is, and undecided otherwise.
  friend bool operator<(const Mpfi& a, const Mpfi& b) {
    if (mpfr_less_p(&a.v_->right, &b.v_->left)) return true;
    if (mpfr_greaterequal_p(&a.v_->left, &b.v_->right)) return false;
    throw UncertainDecision();
  }
  friend bool operator<=(const Mpfi& a, const Mpfi& b) {
    if (mpfr_lessequal_p(&a.v_->right, &b.v_->left)) return true;
    if (mpfr_greater_p(&a.v_->left, &b.v_->right)) return false;
    throw UncertainDecision();
  }
  friend bool operator>(const Mpfi& a, const Mpfi& b) { return b < a; }
  friend bool operator>=(const Mpfi& a, const Mpfi& b) { return b <= a; }
  friend bool operator==(const Mpfi& a, const Mpfi& b) {
    if (mpfr_equal_p(&a.v_->left, &a.v_->right) && mpfr_equal_p(&b.v_->left, &b.v_->right) &&
        mpfr_equal_p(&a.v_->left, &b.v_->left))
      return true;
    if (mpfr_less_p(&a.v_->right, &b.v_->left) || mpfr_less_p(&b.v_->right, &a.v_->left)) return false;
    throw UncertainDecision();
  }
  friend bool operator!=(const Mpfi& a, const Mpfi& b) { return !(a == b); }

#define ROTLEAK_MPFI_UNARY(name, fn) \
  friend Mpfi name(const Mpfi& a) {  \
    Mpfi r;                          \
    fn(r.v_, a.v_);                  \
    return r;                        \
  }
  ROTLEAK_MPFI_UNARY(sqrt, mpfi_sqrt)
  ROTLEAK_MPFI_UNARY(sin, mpfi_sin)
  ROTLEAK_MPFI_UNARY(cos, mpfi_cos)
  ROTLEAK_MPFI_UNARY(abs, mpfi_abs)
#undef ROTLEAK_MPFI_UNARY
  friend Mpfi atan2(const Mpfi& y, const Mpfi& x) {
    Mpfi r;
    mpfi_atan2(r.v_, y.v_, x.v_);
    return r;
  }
  friend Mpfi floor(const Mpfi& a) {
    mpfr_t lo, hi;
    mpfr_inits2(mpfi_get_prec(a.v_), lo, hi, static_cast<mpfr_ptr>(nullptr));
    mpfr_floor(lo, &a.v_->left);
    mpfr_floor(hi, &a.v_->right);
    const bool same = mpfr_equal_p(lo, hi);
    Mpfi r;
    if (same) mpfi_set_fr(r.v_, lo);
    mpfr_clears(lo, hi, static_cast<mpfr_ptr>(nullptr));
    if (!same) throw UncertainDecision();
    return r;
  }
  /// a*b + c: for intervals the enclosure of the exact value (used where point types need an exact FMA).
  friend Mpfi fma(const Mpfi& a, const Mpfi& b, const Mpfi& c) { return a * b + c; }

 private:
  mpfi_t v_;
};

}  // namespace rotleak
