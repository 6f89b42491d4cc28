// MPFR and MPFI numbers whose working precision is per thread (a scoped guard sets it), not a
// process-wide default: Boost 1.74's variable-precision mpfr_float keeps one static default for all
// threads, which an OpenMP audit cannot share. Each new value takes the calling thread's precision.
// Significands up to 512 bits are stored inline (no allocation per temporary; see detail::kInlineLimbs).
//
// Interval comparisons are predicates in CGAL's sense: they answer when the enclosures decide, and
// throw UncertainDecision when they overlap, so a generic branch either runs certified or stops.
#pragma once

#include <mpfi.h>
#include <mpfr.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
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

namespace detail {

/// Significands of up to this many limbs (512 bits on 64-bit limbs) live inside the number itself
/// (MPFR's custom interface), so the temporaries of the geometry core cost no allocation; wider
/// ones (the truth's doubling search) fall back to mpfr_init2's heap.
inline constexpr int kInlineLimbs = 8;

inline bool fits_inline(mpfr_prec_t bits) { return mpfr_custom_get_size(bits) <= sizeof(mp_limb_t) * kInlineLimbs; }

/// Initialises x to +0 at `bits`, in `buf` when it fits.
inline void init_limbs(mpfr_ptr x, mp_limb_t* buf, mpfr_prec_t bits) {
  if (fits_inline(bits)) {
    mpfr_custom_init(buf, bits);
    mpfr_custom_init_set(x, MPFR_ZERO_KIND, 0, bits, buf);
  } else {
    mpfr_init2(x, bits);
    mpfr_set_zero(x, 1);
  }
}
inline bool on_heap(mpfr_srcptr x, const mp_limb_t* buf) { return mpfr_custom_get_significand(x) != buf; }
inline void release_limbs(mpfr_ptr x, const mp_limb_t* buf) {
  if (on_heap(x, buf)) mpfr_clear(x);
}
/// dst = src for two inline numbers of the same precision: the limbs and the exponent copied
/// through the custom interface, without mpfr_set's general path (the result is the same value).
inline void copy_limbs(mpfr_ptr dst, mp_limb_t* dst_buf, mpfr_srcptr src, const mp_limb_t* src_buf) {
  if (on_heap(dst, dst_buf) || on_heap(src, src_buf)) {
    mpfr_set(dst, src, MPFR_RNDN);
    return;
  }
  const int kind = mpfr_custom_get_kind(src);
  const mpfr_prec_t bits = mpfr_get_prec(src);
  if (kind == MPFR_REGULAR_KIND || kind == -MPFR_REGULAR_KIND) {
    // the whole inline buffer, a constant size the compiler copies in a few moves (a call to
    // memcpy for the used limbs alone costs more than the copy)
    __builtin_memcpy(dst_buf, src_buf, sizeof(mp_limb_t) * kInlineLimbs);
    mpfr_custom_init_set(dst, kind, mpfr_custom_get_exp(src), bits, dst_buf);
  } else {
    mpfr_custom_init_set(dst, kind, 0, bits, dst_buf);
  }
}
/// dst = src; dst takes src's precision. A heap significand is handed over (src is left a valid 0).
inline void move_limbs(mpfr_ptr dst, mp_limb_t* dst_buf, mpfr_ptr src, mp_limb_t* src_buf) {
  if (on_heap(src, src_buf)) {
    release_limbs(dst, dst_buf);
    *dst = *src;
    init_limbs(src, src_buf, MPFR_PREC_MIN);
    return;
  }
  if (mpfr_get_prec(dst) != mpfr_get_prec(src)) {
    release_limbs(dst, dst_buf);
    init_limbs(dst, dst_buf, mpfr_get_prec(src));
  }
  copy_limbs(dst, dst_buf, src, src_buf);
}

}  // namespace detail

class Mpfr {
 public:
  Mpfr() { init(); }
  // init() leaves +0, so the core's many zeros cost no MPFR call
  Mpfr(double x) {  // NOLINT: implicit like a built-in
    init();
    if (x != 0 || std::signbit(x)) mpfr_set_d(v_, x, MPFR_RNDN);
  }
  Mpfr(int x) {  // NOLINT
    init();
    if (x != 0) mpfr_set_si(v_, x, MPFR_RNDN);
  }
  Mpfr(long x) {  // NOLINT
    init();
    if (x != 0) mpfr_set_si(v_, x, MPFR_RNDN);
  }
  Mpfr(const Mpfr& o) {
    detail::init_limbs(v_, buf_, mpfr_get_prec(o.v_));
    detail::copy_limbs(v_, buf_, o.v_, o.buf_);
  }
  Mpfr(Mpfr&& o) noexcept {
    detail::init_limbs(v_, buf_, MPFR_PREC_MIN);
    detail::move_limbs(v_, buf_, o.v_, o.buf_);
  }
  Mpfr& operator=(const Mpfr& o) {
    if (this != &o) {
      if (mpfr_get_prec(v_) != mpfr_get_prec(o.v_)) {
        detail::release_limbs(v_, buf_);
        detail::init_limbs(v_, buf_, mpfr_get_prec(o.v_));
      }
      detail::copy_limbs(v_, buf_, o.v_, o.buf_);
    }
    return *this;
  }
  Mpfr& operator=(Mpfr&& o) noexcept {
    if (this != &o) detail::move_limbs(v_, buf_, o.v_, o.buf_);
    return *this;
  }
  ~Mpfr() { detail::release_limbs(v_, buf_); }

  mpfr_ptr data() { return v_; }
  mpfr_srcptr data() const { return v_; }

  // a op= b keeps the semantics of a = a op b: the result has the thread's working precision.
#define ROTLEAK_MPFR_BINARY(op, fn)                                               \
  friend Mpfr operator op(const Mpfr& a, const Mpfr& b) {                         \
    Mpfr r;                                                                       \
    fn(r.v_, a.v_, b.v_, MPFR_RNDN);                                              \
    return r;                                                                     \
  }                                                                               \
  Mpfr& operator op##=(const Mpfr& b) {                                           \
    if (mpfr_get_prec(v_) != MpfrPrecision::current()) return *this = *this op b; \
    fn(v_, v_, b.v_, MPFR_RNDN);                                                  \
    return *this;                                                                 \
  }
  ROTLEAK_MPFR_BINARY(+, mpfr_add)
  ROTLEAK_MPFR_BINARY(-, mpfr_sub)
  ROTLEAK_MPFR_BINARY(*, mpfr_mul)
  ROTLEAK_MPFR_BINARY(/, mpfr_div)
#undef ROTLEAK_MPFR_BINARY
  friend Mpfr operator-(const Mpfr& a) {
    Mpfr r;
    if (mpfr_get_prec(a.v_) == mpfr_get_prec(r.v_) && !mpfr_nan_p(a.v_)) {
      // exact at equal precision: the limbs copied and the sign flipped, without mpfr_neg's general path
      detail::copy_limbs(r.v_, r.buf_, a.v_, a.buf_);
      mpfr_setsign(r.v_, r.v_, !mpfr_signbit(a.v_), MPFR_RNDN);
    } else {
      mpfr_neg(r.v_, a.v_, MPFR_RNDN);
    }
    return r;
  }
  friend bool operator<(const Mpfr& a, const Mpfr& b) { return mpfr_less_p(a.v_, b.v_); }
  friend bool operator<=(const Mpfr& a, const Mpfr& b) { return mpfr_lessequal_p(a.v_, b.v_); }
  friend bool operator>(const Mpfr& a, const Mpfr& b) { return mpfr_greater_p(a.v_, b.v_); }
  friend bool operator>=(const Mpfr& a, const Mpfr& b) { return mpfr_greaterequal_p(a.v_, b.v_); }
  friend bool operator==(const Mpfr& a, const Mpfr& b) { return mpfr_equal_p(a.v_, b.v_); }
  friend bool operator!=(const Mpfr& a, const Mpfr& b) { return !mpfr_equal_p(a.v_, b.v_); }

  // Small integer operands (the core's 0, 1, 2) go straight to MPFR's _si functions: no temporary,
  // and the same result (the integer is exact, the operation rounded once either way).
  template <class I>
  static constexpr bool small_int() {
    return std::is_integral_v<I> && std::is_signed_v<I> && sizeof(I) <= sizeof(long);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator+(const Mpfr& a, I b) {
    return with(mpfr_add_si, a, b);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator+(I a, const Mpfr& b) {
    return with(mpfr_add_si, b, a);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator-(const Mpfr& a, I b) {
    return with(mpfr_sub_si, a, b);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator-(I a, const Mpfr& b) {
    Mpfr r;
    mpfr_si_sub(r.v_, static_cast<long>(a), b.v_, MPFR_RNDN);
    return r;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator*(const Mpfr& a, I b) {
    return with(mpfr_mul_si, a, b);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator*(I a, const Mpfr& b) {
    return with(mpfr_mul_si, b, a);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend Mpfr operator/(const Mpfr& a, I b) {
    return with(mpfr_div_si, a, b);
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator<(const Mpfr& a, I b) {
    return !mpfr_nan_p(a.v_) && cmp(a, b) < 0;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator<=(const Mpfr& a, I b) {
    return !mpfr_nan_p(a.v_) && cmp(a, b) <= 0;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator>(const Mpfr& a, I b) {
    return !mpfr_nan_p(a.v_) && cmp(a, b) > 0;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator>=(const Mpfr& a, I b) {
    return !mpfr_nan_p(a.v_) && cmp(a, b) >= 0;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator==(const Mpfr& a, I b) {
    return !mpfr_nan_p(a.v_) && cmp(a, b) == 0;
  }
  template <class I, class = std::enable_if_t<small_int<I>()>>
  friend bool operator!=(const Mpfr& a, I b) {
    return mpfr_nan_p(a.v_) || cmp(a, b) != 0;
  }

#define ROTLEAK_MPFR_UNARY(name, fn) \
  friend Mpfr name(const Mpfr& a) {  \
    Mpfr r;                          \
    fn(r.v_, a.v_, MPFR_RNDN);       \
    return r;                        \
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
  void init() { detail::init_limbs(v_, buf_, MpfrPrecision::current()); }
  template <class I>
  static Mpfr with(int (*fn)(mpfr_ptr, mpfr_srcptr, long, mpfr_rnd_t), const Mpfr& a, I b) {
    Mpfr r;
    fn(r.v_, a.v_, static_cast<long>(b), MPFR_RNDN);
    return r;
  }
  /// Three-way comparison with an integer (callers rule out NaN first: it is unordered).
  template <class I>
  static int cmp(const Mpfr& a, I b) {
    return mpfr_cmp_si(a.v_, static_cast<long>(b));
  }

  mpfr_t v_;
  mp_limb_t buf_[detail::kInlineLimbs];
};

/// An interval comparison that the enclosures cannot decide.
class UncertainDecision : public std::runtime_error {
 public:
  UncertainDecision() : std::runtime_error("interval comparison undecided") {}
};

class Mpfi {
 public:
  Mpfi() { init(MpfrPrecision::current()); }
  Mpfi(double x) { init(MpfrPrecision::current()), mpfi_set_d(v_, x); }  // NOLINT
  Mpfi(int x) { init(MpfrPrecision::current()), mpfi_set_si(v_, x); }    // NOLINT
  Mpfi(long x) { init(MpfrPrecision::current()), mpfi_set_si(v_, x); }   // NOLINT
  Mpfi(const Mpfi& o) { init(mpfi_get_prec(o.v_)), mpfi_set(v_, o.v_); }
  Mpfi(Mpfi&& o) noexcept {
    init(MPFR_PREC_MIN);
    take(o);
  }
  Mpfi& operator=(const Mpfi& o) {
    if (this != &o) {
      if (mpfi_get_prec(v_) != mpfi_get_prec(o.v_)) {
        release();
        init(mpfi_get_prec(o.v_));
      }
      mpfi_set(v_, o.v_);
    }
    return *this;
  }
  Mpfi& operator=(Mpfi&& o) noexcept {
    if (this != &o) take(o);
    return *this;
  }
  ~Mpfi() { release(); }

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

#define ROTLEAK_MPFI_BINARY(op, fn)                                               \
  friend Mpfi operator op(const Mpfi& a, const Mpfi& b) {                         \
    Mpfi r;                                                                       \
    fn(r.v_, a.v_, b.v_);                                                         \
    return r;                                                                     \
  }                                                                               \
  Mpfi& operator op##=(const Mpfi& b) {                                           \
    if (mpfi_get_prec(v_) != MpfrPrecision::current()) return *this = *this op b; \
    fn(v_, v_, b.v_);                                                             \
    return *this;                                                                 \
  }
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
  ROTLEAK_MPFI_UNARY(sqr, mpfi_sqr)  ///< x^2 >= 0 (x * x of an interval holding 0 reaches below 0)
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
  // both end points in the number itself when they fit (see detail::kInlineLimbs)
  void init(mpfr_prec_t bits) {
    detail::init_limbs(&v_->left, lbuf_, bits);
    detail::init_limbs(&v_->right, rbuf_, bits);
  }
  void release() {
    detail::release_limbs(&v_->left, lbuf_);
    detail::release_limbs(&v_->right, rbuf_);
  }
  void take(Mpfi& o) {
    detail::move_limbs(&v_->left, lbuf_, &o.v_->left, o.lbuf_);
    detail::move_limbs(&v_->right, rbuf_, &o.v_->right, o.rbuf_);
  }

  mpfi_t v_;
  mp_limb_t lbuf_[detail::kInlineLimbs], rbuf_[detail::kInlineLimbs];
};

}  // namespace rotleak
