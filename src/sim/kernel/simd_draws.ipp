// The vectorised draws' initial states (birkhoff_kernel, flow_kernel), included after sim/kernel/simd_kernel.ipp
// by each kernel translation unit, inside its namespace (its pack V, masks MV, load, store, select). Each
// particle's frame and velocity are Stadium<double>::at's and velocity's formulas (geometry/formulas.hpp),
// an arc's sine and cosine formula::sin_cos (numeric/sin_cos.hpp), the lanes' pieces chosen as at() chooses
// them: the scalar core's bits (tests/test_sin_cos.cpp).

namespace {
/// The product of a register of 64-bit words and a constant m, as (low, high) words (Random123's mulhilo64), from
/// four 32 x 32 -> 64-bit products.
inline void mulhilo(const U& a, std::uint64_t m, U& lo, U& hi) {
  const U low32(0xffffffffULL), mL(m & 0xffffffffULL), mH(m >> 32);
  const U aH = a >> 32;
  const U ll = mul_wide(a, mL), lh = mul_wide(a, mH), hl = mul_wide(aH, mL), hh = mul_wide(aH, mH);
  const U mid = (ll >> 32) + (lh & low32) + (hl & low32);
  lo = (mid << 32) | (ll & low32);
  hi = hh + (lh >> 32) + (hl >> 32) + (mid >> 32);
}

/// Philox4x64-10 of counters (id, 0, 0, 0) with key (seed, 0), per lane of the G registers ids[], as Random123
/// computes it (its round and key schedule; tests/test_sin_cos.cpp checks the words).
inline void philox(const U* ids, std::uint64_t seed, U (*w)[4]) {
  U k0[G], k1[G];
  for (int g = 0; g < G; ++g) {
    w[g][0] = ids[g], w[g][1] = w[g][2] = w[g][3] = U(std::uint64_t{0});
    k0[g] = U(seed), k1[g] = U(std::uint64_t{0});
  }
  for (int round = 0; round < 10; ++round) {
    for (int g = 0; g < G; ++g) {
      if (round > 0) k0[g] = k0[g] + U(0x9E3779B97F4A7C15ULL), k1[g] = k1[g] + U(0xBB67AE8584CAA73BULL);
      U lo0, hi0, lo1, hi1;
      mulhilo(w[g][0], 0xD2E7470EE14C6C93ULL, lo0, hi0);
      mulhilo(w[g][2], 0xCA5A826395121157ULL, lo1, hi1);
      const U c1 = w[g][1], c3 = w[g][3];
      w[g][0] = hi1 ^ c1 ^ k0[g], w[g][1] = lo1, w[g][2] = hi0 ^ c3 ^ k1[g], w[g][3] = lo0;
    }
  }
}

/// The integer bits >> 11 (< 2^53) of each lane as a double, exactly: its low 52 bits and its bit 52, each
/// through the exponent of 2^52 (as_double(2^52's exponent | k) - 2^52 = k), then their exact sum.
inline B top53(const U& bits) {
  const U m = bits >> 11, exponent(0x4330000000000000ULL);
  const B low = xsimd::bitwise_cast<B>((m & U(0xFFFFFFFFFFFFFULL)) | exponent) - B(0x1p52);
  const B bit52 = xsimd::bitwise_cast<B>((m >> 52) | exponent) - B(0x1p52);
  return low + bit52 * B(0x1p52);
}

/// A frame of lanes: `a` where m holds, else `b`.
inline formula::Frame<V> pick(const MV& m, const formula::Frame<V>& a, const formula::Frame<V>& b) {
  return {{select(m, a.q.x, b.q.x), select(m, a.q.y, b.q.y)},
          {select(m, a.tangent.x, b.tangent.x), select(m, a.tangent.y, b.tangent.y)},
          {select(m, a.normal.x, b.normal.x), select(m, a.normal.y, b.normal.y)}};
}
}  // namespace

/// Stadium<double>::at(s) and velocity(p) for a pack of lanes: each piece's frame by its formula, the lane's
/// piece chosen as at() chooses it, the arcs' sine and cosine by formula::sin_cos (only when a lane is on one).
ROTLEAK_KERNEL_FLATTEN void birkhoff_kernel(const KernelScene& S, const double* s, const double* p, Start* out,
                                            std::size_t n) {
  alignas(sizeof(B)) double a[N], b[N], qx[N], qy[N], vx[N], vy[N];
  const V L(S.L), r(S.r), half_d(S.half_d);
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) a[k] = k < m ? s[i + k] : 0, b[k] = k < m ? p[i + k] : 0;
    const V sv = load(a), pv = load(b);
    const MV right_half = sv < V(S.junction[0]), top = right_half | (sv >= V(S.junction[3]));
    const MV right = (!top) & (sv < V(S.junction[1]));
    const MV bottom = (!top) & (!right) & (sv < V(S.junction[2]));
    formula::Frame<V> f =
        pick(top, formula::top_frame(right_half, sv, L, r), formula::bottom_frame(sv, L, half_d, r, V(S.junction[1])));
    if (bits(!(top | bottom))) {
      const V th = formula::arc_angle_of(sv, select(right, V(S.junction[0]), V(S.junction[2])), V(S.L_over_r));
      const formula::SinCos<V> sc = formula::sin_cos(th);
      f = pick(top | bottom, f, formula::arc_frame(right, half_d, r, sc.sin, sc.cos));
    }
    const Vec2<V> v = formula::birkhoff_velocity(f, pv);
    store(f.q.x, qx), store(f.q.y, qy), store(v.x, vx), store(v.y, vy);
    for (std::size_t k = 0; k < m; ++k) {
      out[i + k].qx = qx[k], out[i + k].qy = qy[k];
      out[i + k].vx = vx[k], out[i + k].vy = vy[k];
    }
  }
}

/// A flow start's direction (cos, sin) of 2 pi u, by formula::sin_cos, for a pack of lanes.
ROTLEAK_KERNEL_FLATTEN void flow_kernel(const KernelScene& S, const double* u, double* vx, double* vy, std::size_t n) {
  alignas(sizeof(B)) double a[N], c[N], sn[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) a[k] = k < m ? u[i + k] : 0;
    const formula::SinCos<V> sc = formula::sin_cos(formula::flow_angle(V(S.pi), load(a)));
    store(sc.cos, c), store(sc.sin, sn);
    for (std::size_t k = 0; k < m; ++k) vx[i + k] = c[k], vy[i + k] = sn[k];
  }
}

/// Uniform Birkhoff starts of particles first .. first + n - 1 (InitialConditions::draw with init = birkhoff, then
/// birkhoff_kernel's states): the Philox words per lane, s = unit(w0), p = symmetric(w1), t = window unit(w3)
/// (InitialConditions::unit and symmetric, exactly).
ROTLEAK_KERNEL_FLATTEN void uniform_kernel(const KernelScene& S, std::uint64_t seed, double window, std::uint64_t first,
                                           std::size_t n, Start* out) {
  alignas(64) std::uint64_t id[N];
  alignas(64) double s[N], p[N], t[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) id[k] = first + i + k;
    U ids[G], w[G][4];
    for (int g = 0; g < G; ++g) ids[g] = U::load_aligned(id + g * W);
    philox(ids, seed, w);
    for (int g = 0; g < G; ++g) {
      const B unit = B(0x1p-53);
      (top53(w[g][0]) * unit).store_aligned(s + g * W);
      (((top53(w[g][1]) - B(0x1p52)) * B(2.0) + B(1.0)) * unit).store_aligned(p + g * W);
      (B(window) * (top53(w[g][3]) * unit)).store_aligned(t + g * W);
    }
    birkhoff_kernel(S, s, p, out + i, m);
    for (std::size_t k = 0; k < m; ++k) out[i + k].t = t[k], out[i + k].collisions = 0, out[i + k].weight = 1;
  }
}
