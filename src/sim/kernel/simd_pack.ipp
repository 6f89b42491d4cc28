// The kernel's pack (sim/kernel/simd_kernel.ipp): N = W G lanes in G registers, every operation the
// register's own applied to each of them side by side, the lane masks, the selection hook the shared
// formulas take (numeric/select.hpp), loads and stores. Included, before simd_lanes.ipp, inside the
// namespace of each instruction set's kernel (simd_engine.cpp: AVX2; simd_avx512.cpp: AVX-512), after its
// definitions of B, M, W, G and bits(M).

constexpr int N = W * G;  ///< lanes of a pack
static_assert(N <= 32, "lane masks are 32-bit");
constexpr unsigned kAllLanes = N == 32 ? ~0u : (1u << N) - 1;

namespace {

/// f(0), ..., f(G - 1), unrolled
template <class F>
inline void each(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) { (f(I), ...); }
  (std::make_integer_sequence<int, G>{});
}

// ---- the pack: G registers, every operation the register's own, applied to each ---------------

struct V {
  B b[G];
  V() = default;
  explicit V(double x) {
    each([&](int i) { b[i] = B(x); });
  }
};
struct MV {
  M m[G];
  MV() = default;
  explicit MV(bool x) {
    each([&](int i) { m[i] = M(x); });
  }
};

#define ROTLEAK_V_BINARY(op)                         \
  inline V operator op(const V& x, const V& y) {     \
    V r;                                             \
    each([&](int i) { r.b[i] = x.b[i] op y.b[i]; }); \
    return r;                                        \
  }
ROTLEAK_V_BINARY(+)
ROTLEAK_V_BINARY(-)
ROTLEAK_V_BINARY(*)
ROTLEAK_V_BINARY(/)
#undef ROTLEAK_V_BINARY
#define ROTLEAK_V_COMPARE(op)                        \
  inline MV operator op(const V& x, const V& y) {    \
    MV r;                                            \
    each([&](int i) { r.m[i] = x.b[i] op y.b[i]; }); \
    return r;                                        \
  }
ROTLEAK_V_COMPARE(<)
ROTLEAK_V_COMPARE(<=)
ROTLEAK_V_COMPARE(>)
ROTLEAK_V_COMPARE(>=)
ROTLEAK_V_COMPARE(==)
ROTLEAK_V_COMPARE(!=)
#undef ROTLEAK_V_COMPARE
// -x as IEEE negation, the sign bit flipped: xsimd's AVX-512 neg is 0 - x, which gives +0 for +0 where the core's
// -x gives -0 (the core's arc angle at x = -d/2 hangs on that zero's sign: tests/test_kernel_probe.cpp)
inline V operator-(const V& x) {
  V r;
  each([&](int i) { r.b[i] = xsimd::bitwise_xor(x.b[i], B(-0.0)); });
  return r;
}
inline MV operator&(const MV& x, const MV& y) {
  MV r;
  each([&](int i) { r.m[i] = x.m[i] & y.m[i]; });
  return r;
}
inline MV operator|(const MV& x, const MV& y) {
  MV r;
  each([&](int i) { r.m[i] = x.m[i] | y.m[i]; });
  return r;
}
inline MV operator!(const MV& x) {
  MV r;
  each([&](int i) { r.m[i] = !x.m[i]; });
  return r;
}
template <class F>
inline V map(const V& x, F f) {
  V r;
  each([&](int i) { r.b[i] = f(x.b[i]); });
  return r;
}
inline V sqrt(const V& x) {
  return map(x, [](B a) { return xsimd::sqrt(a); });
}
inline V abs(const V& x) {
  return map(x, [](B a) { return xsimd::abs(a); });
}
inline V floor(const V& x) {
  return map(x, [](B a) { return xsimd::floor(a); });
}
inline V nearbyint(const V& x) {
  return map(x, [](B a) { return xsimd::nearbyint(a); });
}
// the selection hook of the shared formulas (numeric/select.hpp), for packs: per lane
inline V select(const MV& m, const V& x, const V& y) {
  V r;
  each([&](int i) { r.b[i] = xsimd::select(m.m[i], x.b[i], y.b[i]); });
  return r;
}
inline MV select(const MV& m, const MV& x, const MV& y) { return (m & x) | ((!m) & y); }
inline Vec2<V> select(const MV& m, const Vec2<V>& x, const Vec2<V>& y) {
  return {select(m, x.x, y.x), select(m, x.y, y.y)};
}
// a * b + c as the core evaluates the spelling: a multiply, then an add (two roundings;
// -ffp-contract=off keeps the compiler from fusing them)
inline V fma(const V& x, const V& y, const V& z) {
  V r;
  each([&](int i) { r.b[i] = x.b[i] * y.b[i] + z.b[i]; });
  return r;
}
/// lane k of the pack is bit k
inline unsigned bits(const MV& m) {
  unsigned r = 0;
  each([&](int i) { r |= bits(m.m[i]) << (W * i); });
  return r;
}
/// both branches, and a lane select: no branch to mispredict (a lane's choice is data)
template <class F, class G2>
inline auto choose(const MV& m, const F& a, const G2& b) -> decltype(a()) {
  return select(m, a(), b());
}
template <class F>
inline MV both(const MV& m, const F& f) {
  return m & f();
}
inline bool none(const MV& m) { return bits(m) == 0; }
inline V load(const double* p) {
  V r;
  each([&](int i) { r.b[i] = B::load_aligned(p + W * i); });
  return r;
}
inline void store(const V& v, double* p) {
  each([&](int i) { v.b[i].store_aligned(p + W * i); });
}
/// lanes of `mask` in increasing order
template <class F>
inline void for_lanes(unsigned mask, F f) {
  while (mask) {
    f(__builtin_ctz(mask));
    mask &= mask - 1;
  }
}

}  // namespace
