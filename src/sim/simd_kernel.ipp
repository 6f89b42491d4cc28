// The vectorised kernel, written once for any register width. Included, inside a namespace of its own,
// by one translation unit per instruction set (simd_engine.cpp: AVX2, 4 lanes; simd_avx512.cpp:
// AVX-512, 8 lanes), each compiled for its set alone (src/CMakeLists.txt). The includer defines, in an
// anonymous namespace before the #include: B (the register: xsimd::batch<double, arch>), M (its mask),
// W (lanes per register), G (registers per pack), bits(M) (lane k is bit k), fused_fms(a, b, c) (a true
// fused a * b - c) and sleef_atan2(y, x) (SLEEF's u35 atan2 for that width). Keep it self-contained: no
// std algorithms or shared inline helpers whose vector copies the linker could hand to scalar code (it
// shares only constants and enums with the core, from sim/fate.hpp); everything here has internal
// linkage but run_kernel, rough_kernel and cell_kernel.
//
// What matches the scalar core, as the tests check it (tests/test_simd.cpp):
// - Stationary leak: bit-identical. Every expression is evaluated in the scalar core's order with
//   one rounding per operation (xsimd's fma/fms on the plain avx2 arch are a multiply then an add,
//   as the scalar build with -ffp-contract=off), and the escape test is the same window test, so
//   per-particle results, escape records and tallies equal the scalar engine's exactly.
// - Moving leak and f_c: the same bits too. The boundary coordinate of an arc hit needs an angle:
//   SLEEF's vector atan2 (Sleef_atan2d4_u35avx2 / Sleef_atan2d8_u35avx512f, documented error <= 3.5 ulp) where libm's (< 1 ulp)
//   runs in the core. The two angles differ by at most 4.5 ulp (< 2e-15 for angles in [0, pi]), s
//   by less than 1e-15 after scaling by r/L and its one rounding, and so the leak test |offset| <=
//   half_width or the f_c bin floor(s bins) can come out differently only within that distance of
//   the leak's ends or of a bin edge. Lanes within `margin` (1e-12, a thousandfold safety) of one
//   ask the core (simd::Exact), so every decision is the core's. The angle is computed only for
//   arc hits that can matter: when the leak is within reach of that arc (the core's own skip) or
//   when f_c counts the collision.
// The one deliberate FMA is the exact product error of the leak phase, which the scalar core also
// takes from a true fma.
//
// Speed: a collision is a long dependent chain (division, square root, division), so one register of
// particles leaves the core waiting. The kernel works on a pack of G registers (V: N = W G lanes),
// each operation written once and applied to the G registers side by side, so the G chains
// interleave instruction by instruction; branches (an ended lane, a lane near a moving leak) are
// taken once per pack.

constexpr int N = W * G;  ///< lanes of a pack
static_assert(N <= 32, "lane masks are 32-bit");
constexpr unsigned kAllLanes = N == 32 ? ~0u : (1u << N) - 1;
constexpr int kDensityBuffer = 1024;
/// rough_atan2's error bound in rad (1.15e-5 measured; tests/test_simd.cpp checks the bound), i.e.
/// kRoughAngleError r / L in s (< 3.2e-6: r / L < 0.16). The moving leak trusts the rough angle's
/// verdict beyond kRoughMargin of a leak end (a 30-fold safety or more), f_c its bin beyond twice the
/// bound in s of a bin edge (twofold; 3.5-fold on the measured error)
constexpr double kRoughAngleError = 2e-5;
constexpr double kRoughMargin = 1e-4;
constexpr double kRoughBinSafety = 2;

namespace {

/// f(0), ..., f(G - 1), unrolled
template <class F>
inline void each(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) { (f(I), ...); }(std::make_integer_sequence<int, G>{});
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

#define ROTLEAK_V_BINARY(op)                                  \
  inline V operator op(const V& x, const V& y) {              \
    V r;                                                      \
    each([&](int i) { r.b[i] = x.b[i] op y.b[i]; });          \
    return r;                                                 \
  }
ROTLEAK_V_BINARY(+)
ROTLEAK_V_BINARY(-)
ROTLEAK_V_BINARY(*)
ROTLEAK_V_BINARY(/)
#undef ROTLEAK_V_BINARY
#define ROTLEAK_V_COMPARE(op)                                 \
  inline MV operator op(const V& x, const V& y) {             \
    MV r;                                                     \
    each([&](int i) { r.m[i] = x.b[i] op y.b[i]; });          \
    return r;                                                 \
  }
ROTLEAK_V_COMPARE(<)
ROTLEAK_V_COMPARE(<=)
ROTLEAK_V_COMPARE(>)
ROTLEAK_V_COMPARE(>=)
ROTLEAK_V_COMPARE(==)
ROTLEAK_V_COMPARE(!=)
#undef ROTLEAK_V_COMPARE
inline V operator-(const V& x) {
  V r;
  each([&](int i) { r.b[i] = -x.b[i]; });
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
inline V max(const V& x, const V& y) {
  V r;
  each([&](int i) { r.b[i] = xsimd::max(x.b[i], y.b[i]); });
  return r;
}
inline V min(const V& x, const V& y) {
  V r;
  each([&](int i) { r.b[i] = xsimd::min(x.b[i], y.b[i]); });
  return r;
}
inline V select(const MV& m, const V& x, const V& y) {
  V r;
  each([&](int i) { r.b[i] = xsimd::select(m.m[i], x.b[i], y.b[i]); });
  return r;
}
// the core's fma/fms/fnma spellings, evaluated as it evaluates them: a multiply, then an add (two
// roundings; -ffp-contract=off keeps the compiler from fusing them)
inline V fma(const V& x, const V& y, const V& z) {
  V r;
  each([&](int i) { r.b[i] = x.b[i] * y.b[i] + z.b[i]; });
  return r;
}
inline V fms(const V& x, const V& y, const V& z) {
  V r;
  each([&](int i) { r.b[i] = x.b[i] * y.b[i] - z.b[i]; });
  return r;
}
inline V fnma(const V& x, const V& y, const V& z) {
  V r;
  each([&](int i) { r.b[i] = z.b[i] - x.b[i] * y.b[i]; });
  return r;
}
/// lane k of the pack is bit k
inline unsigned bits(const MV& m) {
  unsigned r = 0;
  each([&](int i) { r |= bits(m.m[i]) << (W * i); });
  return r;
}
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

// circular offset of s from c in [-1/2, 1/2)
inline V offset(const V& s, const V& c) {
  const V d = s - c;
  return d - floor(d + V(0.5));
}

struct Lanes {
  alignas(sizeof(B)) double qx[N], qy[N], vx[N], vy[N], t[N], coll[N], zero[N], w[N];
  std::uint64_t id[N];
};

/// N particles in registers, with their bookkeeping in memory for the rare lane changes.
struct Pack {
  Lanes L{};
  V qx, qy, vx, vy, t, coll, zero;
  unsigned live_mask = 0;  ///< bit k: lane k holds a particle (parked lanes sit past t_max and must not retire)
};

void park(const Scene& S, Lanes& L, int k) {
  // an idle lane: parked far past t_max, never reported (its bit of live_mask is clear)
  L.qx[k] = 0, L.qy[k] = 0, L.vx[k] = 0, L.vy[k] = -1, L.t[k] = 2 * S.t_max + 1;
  L.coll[k] = 0;
  L.w[k] = 0;
}

void reload(Pack& g) {
  g.qx = load(g.L.qx), g.qy = load(g.L.qy), g.vx = load(g.L.vx), g.vy = load(g.L.vy), g.t = load(g.L.t);
  g.coll = load(g.L.coll), g.zero = load(g.L.zero);
}

/// Lane k takes the next particle, or is parked when there is none (its bit of live_mask follows).
void take(const Scene& S, Pack& g, int k, void* ctx, NextParticle next) {
  Lanes& L = g.L;
  Start st;
  L.zero[k] = 0;
  if (!next(ctx, &st, &L.id[k])) {
    park(S, L, k);
    g.live_mask &= ~(1u << k);
    return;
  }
  g.live_mask |= 1u << k;
  L.qx[k] = st.qx, L.qy[k] = st.qy, L.vx[k] = st.vx, L.vy[k] = st.vy, L.t[k] = st.t;
  L.coll[k] = st.collisions;
  L.w[k] = st.weight;
}

void fill(const Scene& S, Pack& g, void* ctx, NextParticle next) {
  for (int k = 0; k < N; ++k) take(S, g, k, ctx, next);
  reload(g);
}

/// Where the lanes next meet the boundary, decided as Stadium::next_hit decides it.
struct HitLanes {
  V t;          ///< flight time
  V x, y;       ///< collision point
  V cx;         ///< centre x of the arc on the side the line leaves |x| <= d/2 (used for arc hits)
  MV straight;  ///< the hit is on a straight edge
  MV up;        ///< moving up (the top edge, for a straight hit)
  MV right;     ///< the right arc (for an arc hit)
};

/// The straight edges decide first: a line that crosses y = +-r inside |x| <= d/2 hits that edge;
/// otherwise it leaves through the arc on the side where it crosses (convexity), and one quadratic
/// t^2 + 2bt + c = 0 is solved for its larger root, in the form without cancellation.
inline HitLanes next_hit(const Scene& S, const V& qx, const V& qy, const V& vx, const V& vy) {
  const V R(S.r), HD(S.half_d), ZERO(0.0);
  HitLanes h;
  h.up = vy > ZERO;
  const V ey = select(h.up, R, -R);
  const V tl = (ey - qy) / vy;  // a horizontal flight divides by zero here; `flat` masks it out
  const V xl = fma(vx, tl, qx);
  const MV flat = vy == ZERO;
  h.straight = (abs(xl) <= HD) & !flat;
  h.right = (flat & (vx > ZERO)) | ((!flat) & (xl > ZERO));
  h.cx = select(h.right, HD, -HD);
  const V dx = qx - h.cx;
  const V b = fma(dx, vx, qy * vy);
  const V c = fma(dx - R, dx + R, qy * qy);
  // grazing: rounding may push a tangent ray just outside, so the discriminant is clamped at 0
  const V sq = sqrt(max(fms(b, b, c), ZERO));
  // b > 0 (a start outside the disc moving off its centre line) is rare: divide only where a register needs it
  V ta = sq - b;
  each([&](int i) {
    const M far = b.b[i] > B(0.0);
    if (bits(far)) ta.b[i] = xsimd::select(far, -c.b[i] / (b.b[i] + sq.b[i]), ta.b[i]);
  });
  h.t = select(h.straight, tl, ta);
  h.x = select(h.straight, xl, fma(h.t, vx, qx));
  h.y = select(h.straight, ey, fma(h.t, vy, qy));
  return h;
}

/// Stationary leak: the precomputed windows of Leak::in_windows, an x range on a straight edge and
/// two half-plane tests from the arc's centre on an arc (no transcendental function per hit).
inline MV in_stationary_leak(const Scene& S, const HitLanes& h) {
  const V ZERO(0.0);
  MV in(false);
  for (int w = 0; w < S.n_windows[0]; ++w)
    in = in | (h.straight & h.up & (h.x >= V(S.lo[0][w])) & (h.x <= V(S.hi[0][w])));
  for (int w = 0; w < S.n_windows[2]; ++w)
    in = in | (h.straight & !h.up & (h.x >= V(S.lo[2][w])) & (h.x <= V(S.hi[2][w])));
  const V rx = h.x - h.cx;
  for (int p = 1; p <= 3; p += 2) {
    const MV on = (!h.straight) & (p == 1 ? h.right : !h.right);
    for (int w = 0; w < S.n_windows[p]; ++w) {
      const V c1 = fms(V(S.from_x[p][w]), h.y, V(S.from_y[p][w]) * rx);  // cross(from, rel)
      const V c2 = fms(rx, V(S.to_y[p][w]), h.y * V(S.to_x[p][w]));      // cross(rel, to)
      in = in | (on & (c1 <= ZERO) & (c2 <= ZERO));
    }
  }
  return in;
}

/// The boundary coordinate s of the straight hits as Stadium::s_of computes it (arc lanes: junk).
inline V straight_s(const Scene& S, const HitLanes& h) {
  const V HD(S.half_d), ZERO(0.0), ONE(1.0);
  V s_top = h.x * V(S.inv_L);
  s_top = select(s_top < ZERO, s_top + ONE, s_top);
  s_top = select(s_top >= ONE, ZERO, s_top);
  const V s_bottom = fma(HD - h.x, V(S.inv_L), V(S.junction[1]));  // a multiply, then an add
  return select(h.up, s_top, s_bottom);
}

/// s of the arc hits as Stadium::s_of computes it, the angle from SLEEF's atan2, evaluated only for
/// the registers with a lane in `arcs`; their other lanes keep `s`.
inline V arc_s(const Scene& S, const HitLanes& h, const MV& arcs, V s) {
  each([&](int i) {
    if (!bits(arcs.m[i])) return;
    // right arc: atan2(x - d/2, y); left arc: atan2(-(x + d/2), -y); one call for both
    const M right = h.right.m[i];
    const B x = h.x.b[i], y = h.y.b[i], hd(S.half_d);
    const B ay = xsimd::select(right, x - hd, -(x + hd));
    const B ax = xsimd::select(right, y, -y);
    B ang = sleef_atan2(ay, ax);
    ang = xsimd::min(xsimd::max(ang, B(0.0)), B(S.pi));
    const B sa = ang * B(S.r_over_L) + xsimd::select(right, B(S.junction[0]), B(S.junction[2]));  // two roundings
    s.b[i] = xsimd::select(arcs.m[i], sa, s.b[i]);
  });
  return s;
}

/// s of every hit: straight_s, and arc_s for the arc lanes in `arcs` (other arc lanes get -1).
inline V s_of(const Scene& S, const HitLanes& h, const MV& arcs) {
  return arc_s(S, h, arcs, select(h.straight, straight_s(S, h), V(-1.0)));
}

/// A cheap angle atan2(ay, ax) in [-pi, pi] for the moving leak's first look: octant reduction and
/// Abramowitz & Stegun 4.4.49 (their bound 1e-5 rad on [0, 1]; with the reflections and the seven
/// published digits of the coefficients, 1.15e-5 measured): taken as |error| <= 2e-5 rad, which
/// tests/test_simd.cpp checks against libm on 4 * 10^6 angles.
inline V rough_atan2(const V& ay, const V& ax) {
  const V ZERO(0.0);
  const V a = abs(ay), b = abs(ax);
  const V hi = max(a, b), lo = min(a, b);
  const V z = lo / select(hi > ZERO, hi, V(1.0));
  const V z2 = z * z;
  V p = fma(z2, V(0.0208351), V(-0.0851330));
  p = fma(z2, p, V(0.1801410));
  p = fma(z2, p, V(-0.3302995));
  p = fma(z2, p, V(0.9998660));
  V t = z * p;
  t = select(a > b, V(1.5707963267948966) - t, t);
  t = select(ax < ZERO, V(3.141592653589793) - t, t);
  return select(ay < ZERO, -t, t);
}

/// s of the arc hits as arc_s computes it but from rough_atan2: within 2e-5 rad, 3.2e-6 in s (r / L
/// < 0.16), of the core's. Inlined by force: as a call it returns its pack through memory (omega =
/// 2/3 measured 4% slower).
[[gnu::always_inline]] inline V rough_arc_s(const Scene& S, const HitLanes& h) {
  const V HD(S.half_d);
  const V ang =
      min(max(rough_atan2(select(h.right, h.x - HD, -(h.x + HD)), select(h.right, h.y, -h.y)), V(0.0)), V(S.pi));
  return fma(ang, V(S.r_over_L), select(h.right, V(S.junction[0]), V(S.junction[2])));
}

/// Per-lane answers from the core for the lanes in `ask`, replacing `m` there.
template <class F>
inline MV ask_core(const MV& m, const MV& ask, F core) {
  alignas(sizeof(B)) double v[N];
  const unsigned am = bits(ask), mm = bits(m);
  for (int i = 0; i < N; ++i) v[i] = ((am >> i) & 1) ? (core(i) ? 1.0 : 0.0) : (((mm >> i) & 1) ? 1.0 : 0.0);
  return load(v) != V(0.0);
}

/// Moving leak: the phase frac(start + omega t) as LeakSchedule::phase computes it, then Leak::hit:
/// on an arc nothing unless the leak's centre is within reach of the arc's middle; else the
/// circular distance of s from the centre against the half width, lanes near a leak end decided
/// by the core.
inline MV in_moving_leak(const Scene& S, const HitLanes& h, const V& t, const MV& live, void* ctx,
                         const Exact& exact) {
  const V prod = V(S.omega_hi) * t;
  V err;  // the exact error of hi*t: a true fused multiply-subtract
  each([&](int i) { err.b[i] = fused_fms(B(S.omega_hi), t.b[i], prod.b[i]); });
  V ph = (prod - floor(prod)) + fma(V(S.omega_lo), t, err) + V(S.start);
  ph = ph - floor(ph);
  const V mid = select(h.right, V(S.arc_mid[1]), V(S.arc_mid[3]));
  const V reach = select(h.right, V(S.arc_reach[1]), V(S.arc_reach[3]));
  MV near_arc = (!h.straight) & (abs(offset(mid, ph)) <= reach) & live;
  if (bits(near_arc)) {
    // first look with the rough angle: a hit more than kRoughMargin (in s) outside the leak is out
    // for any angle within 2e-5 rad (3.2e-6 in s) of it; only the rest get the exact angle
    const V s_rough = rough_arc_s(S, h);
    near_arc = near_arc & (abs(offset(s_rough, ph)) <= V(S.half_width + kRoughMargin));
  }
  const V s = s_of(S, h, near_arc);
  const V off = abs(offset(s, ph));
  MV in = (h.straight | near_arc) & (off <= V(S.half_width));
  const MV unsure = near_arc & (abs(off - V(S.half_width)) <= V(S.margin));
  if (bits(unsure)) {
    alignas(sizeof(B)) double x[N], y[N], tt[N];
    store(h.x, x), store(h.y, y), store(t, tt);
    const unsigned rm = bits(h.right);
    in = ask_core(in, unsure, [&](int i) { return exact.escape(ctx, ((rm >> i) & 1) ? 1 : 3, x[i], y[i], tt[i]); });
  }
  return in;
}

/// The time cell of t: how many window edges it has passed (t >= from, t > to); the cell fixes the set
/// of windows that hold t, so one count per collision serves every window (the caller folds them).
inline V time_cell(const Scene& S, const V& t) {
  const V ONE(1.0), ZERO(0.0);
  V cell(0.0);
  for (int w = 0; w < S.density_windows; ++w)
    cell = cell + select(t >= V(S.win_from[w]), ONE, ZERO) + select(t > V(S.win_to[w]), ONE, ZERO);
  return cell;
}

/// f_c: the lanes in `count` (alive, t within the windows' span) add one collision to bin
/// floor(s bins) of their time cell (see simd::DensityHit; a cell in a gap has no window). An arc hit's bin comes from the rough angle when its s is more than
/// kRoughBinSafety times the rough angle's bound (in s) from a bin edge (for any angle within rough_atan2's bound the bin is the same);
/// the rest take SLEEF's angle, and those within `margin` of an edge take s from the core.
inline void observe_density(const Scene& S, const Pack& g, const HitLanes& h, const V& t, const MV& count, void* ctx,
                            const Exact& exact, DensityHit* buf, int& used) {
  const V bins(static_cast<double>(S.bins)), ZERO(0.0);
  const MV arcs = count & !h.straight;
  V s = straight_s(S, h);  // arc lanes: below
  MV fine = arcs;          // arc lanes that need more than the rough angle
  if (bits(arcs)) {
    const V s_rough = rough_arc_s(S, h);
    const V sb = s_rough * bins;
    fine = arcs & (abs(sb - nearbyint(sb)) <= V(kRoughBinSafety * kRoughAngleError * S.r_over_L * S.bins));
    s = select(arcs, s_rough, s);
  }
  if (bits(fine)) {
    s = arc_s(S, h, fine, s);
    const V sb = s * bins;
    if (const unsigned um = bits(fine & (abs(sb - nearbyint(sb)) <= V(S.margin * S.bins)))) {
      alignas(sizeof(B)) double sv[N], x[N], y[N];
      store(s, sv), store(h.x, x), store(h.y, y);
      const unsigned rm = bits(h.right);
      for_lanes(um, [&](int i) { sv[i] = exact.s_of(ctx, ((rm >> i) & 1) ? 1 : 3, x[i], y[i]); });
      s = load(sv);
    }
  }
  // as DensityObserver bins it, int(s bins) clamped to [0, bins): s bins > -1, so floor and the
  // clamp give the same as the truncation and the clamp
  const V bin = min(max(floor(s * bins), ZERO), V(S.bins - 1.0));
  alignas(sizeof(B)) double index[N];
  store(fma(time_cell(S, t), bins, bin), index);  // exact: small integers
  const unsigned in = bits(count);
  if (exact.counts) {
    if (in == kAllLanes) {  // the common case (a window covering most of the run): no mask walk
      for (int i = 0; i < N; ++i) ++exact.counts[static_cast<std::uint32_t>(index[i])];
    } else {
      for_lanes(in, [&](int i) { ++exact.counts[static_cast<std::uint32_t>(index[i])]; });
    }
    return;
  }
  for_lanes(in, [&](int i) {
    if (used == kDensityBuffer) {
      exact.density(ctx, buf, used);
      used = 0;
    }
    buf[used++] = {static_cast<std::uint32_t>(index[i]), g.L.w[i]};
  });
}

/// Reports the lanes in `done` to finish() and refills them from next() (or parks them).
void retire(const Scene& S, Pack& g, const HitLanes& h, const MV& done, const MV& esc, const MV& stuck,
            const MV& over, const MV& handoff, void* ctx, NextParticle next, Finish finish) {
  Lanes& L = g.L;
  store(g.qx, L.qx), store(g.qy, L.qy), store(g.vx, L.vx), store(g.vy, L.vy);
  store(g.t, L.t), store(g.coll, L.coll), store(g.zero, L.zero);
  const unsigned em = bits(esc), sm = bits(stuck), om = bits(over), hm = bits(handoff);
  const unsigned straight_m = bits(h.straight), up_m = bits(h.up), right_m = bits(h.right);
  for_lanes(bits(done) & g.live_mask, [&](int i) {
    End e;
    e.fate = ((om >> i) & 1)   ? LaneEnd::survived
             : ((em >> i) & 1) ? LaneEnd::escaped
             : ((sm >> i) & 1) ? LaneEnd::stuck
             : ((hm >> i) & 1) ? LaneEnd::handed_back
                               : LaneEnd::survived;
    e.t = L.t[i];
    e.weight = L.w[i];
    e.qx = L.qx[i];
    e.qy = L.qy[i];
    e.vx = L.vx[i];
    e.vy = L.vy[i];
    e.piece = ((straight_m >> i) & 1) ? (((up_m >> i) & 1) ? 0 : 2) : (((right_m >> i) & 1) ? 1 : 3);
    e.collisions = static_cast<std::uint64_t>(L.coll[i]);
    finish(ctx, L.id[i], e);
    take(S, g, i, ctx, next);
  });
  reload(g);
}

/// One collision for the lanes of g, in the scalar core's order (particle.hpp advance): next hit,
/// time check, escape test, reflection, zero-flight count; lanes that end are reported and refilled.
/// KeepLast (Scene::keep_last, a split run's epochs): a lane past t_max reports the state of its last
/// collision before it. A separate instantiation, so that ordinary runs keep their code as it was
/// (the branch measured 4-8% slower in bench_scale even where no lane took it).
template <bool KeepLast>
inline void step(const Scene& S, Pack& g, void* ctx, NextParticle next, Finish finish, const Exact& exact,
                 DensityHit* buf, int& used) {
  const V R(S.r), HD(S.half_d), TMAX(S.t_max), ZERO(0.0), ONE(1.0);
  const V vx = g.vx, vy = g.vy;
  const HitLanes h = next_hit(S, g.qx, g.qy, vx, vy);
  const V t = g.t + h.t;
  const MV over = t > TMAX;
  g.coll = g.coll + select(over, ZERO, ONE);  // a flight past t_max is not a collision
  if (S.density_windows > 0) {                // parked lanes sit past t_max: `over` excludes them
    // within the windows' span [first from, last to]; a time in a gap between windows has a cell
    // that no window holds, so it is counted nowhere
    const MV count = (t >= V(S.win_span_from)) & (t <= V(S.win_span_to)) & !over;
    if (bits(count)) observe_density(S, g, h, t, count, ctx, exact, buf, used);
  }
  const MV esc = (S.rotating ? in_moving_leak(S, h, t, !over, ctx, exact) : in_stationary_leak(S, h)) & !over;

  // reflect: about the radius vector as it is, not divided by r (see Stadium::reflect)
  const V wx = h.x - h.cx;
  const V k = V(2.0) * fma(wx, vx, h.y * vy) / fma(wx, wx, h.y * h.y);
  g.vx = select(h.straight, vx, fnma(k, wx, vx));
  g.vy = select(h.straight, -vy, fnma(k, h.y, vy));
  g.zero = select(h.t > ZERO, ZERO, g.zero + ONE);
  const MV stuck = g.zero > V(static_cast<double>(kMaxZeroFlights));
  if constexpr (!KeepLast) g.qx = h.x, g.qy = h.y, g.t = t;
  // a long run between the straight edges ahead: (room to the arc) |vy| >= n 2r |vx|, no division
  MV handoff(false);
  if (S.handoff_bounces > 0) {
    const V room = select(vx > ZERO, HD - h.x, HD + h.x);
    handoff = h.straight & !over & !esc & (room * abs(g.vy) >= V(2 * S.handoff_bounces) * R * abs(g.vx));
  }
  const MV done = over | esc | stuck | handoff;
  if constexpr (KeepLast) {
    if (bits(done) & g.live_mask) {
      // a lane past t_max keeps the state of its last collision before it (where a split run goes on)
      g.qx = select(over, g.qx, h.x), g.qy = select(over, g.qy, h.y), g.t = select(over, g.t, t);
      g.vx = select(over, vx, g.vx), g.vy = select(over, vy, g.vy);
      retire(S, g, h, done, esc, stuck, over, handoff, ctx, next, finish);
    } else {
      g.qx = h.x, g.qy = h.y, g.t = t;
    }
  } else {
    if (bits(done) & g.live_mask) retire(S, g, h, done, esc, stuck, over, handoff, ctx, next, finish);
  }
}

}  // namespace

void run_kernel(const Scene& S, void* ctx, NextParticle next, Finish finish, const Exact& exact) {
  Pack g;
  DensityHit buf[kDensityBuffer];
  int used = 0;
  fill(S, g, ctx, next);
  if (S.keep_last)
    while (g.live_mask) step<true>(S, g, ctx, next, finish, exact, buf, used);
  else
    while (g.live_mask) step<false>(S, g, ctx, next, finish, exact, buf, used);
  if (used) exact.density(ctx, buf, used);
}

void cell_kernel(const Scene& S, const double* t, double* out, std::size_t n) {
  alignas(sizeof(B)) double a[N], o[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) a[k] = k < m ? t[i + k] : 0;
    store(time_cell(S, load(a)), o);
    for (std::size_t k = 0; k < m; ++k) out[i + k] = o[k];
  }
}

void rough_kernel(const double* ay, const double* ax, double* out, std::size_t n) {
  alignas(sizeof(B)) double a[N], b[N], o[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) a[k] = k < m ? ay[i + k] : 0, b[k] = k < m ? ax[i + k] : 1;
    store(rough_atan2(load(a), load(b)), o);
    for (std::size_t k = 0; k < m; ++k) out[i + k] = o[k];
  }
}
