// Compiled with -mavx2 -mfma (see src/CMakeLists.txt). Keep this file self-contained: no std
// algorithms or shared inline helpers whose AVX2 copies the linker could hand to scalar code (it
// shares only constants and enums with the core, from sim/fate.hpp).
//
// What matches the scalar core, as the tests check it (tests/test_simd.cpp):
// - Stationary leak: bit-identical. Every expression is evaluated in the scalar core's order with
//   one rounding per operation (xsimd's fma/fms on the plain avx2 arch are a multiply then an add,
//   as the scalar build with -ffp-contract=off), and the escape test is the same window test, so
//   per-particle results, escape records and tallies equal the scalar engine's exactly.
// - Moving leak and f_c: the same bits too. The boundary coordinate of an arc hit needs an angle:
//   SLEEF's vector atan2 (Sleef_atan2d4_u35avx2, documented error <= 3.5 ulp) where libm's (< 1 ulp)
//   runs in the core. The two angles differ by at most 4.5 ulp (< 2e-15 for angles in [0, pi]), s
//   by less than 1e-15 after scaling by r/L and its one rounding, and so the leak test |offset| <=
//   half_width or the f_c bin floor(s bins) can come out differently only within that distance of
//   the leak's ends or of a bin edge. Lanes within `margin` (1e-12, a thousandfold safety) of one
//   ask the core (simd::Exact), so every decision is the core's. The angle is computed only for
//   arc hits that can matter: when the leak is within reach of that arc (the core's own skip) or
//   when f_c counts the collision.
// The one deliberate FMA is the exact product error of the leak phase, which the scalar core also
// takes from a true fma.
#include "sim/simd_engine.hpp"

#include <sleef.h>

#include <xsimd/xsimd.hpp>

#ifndef ROTLEAK_SIMD_GROUPS
#define ROTLEAK_SIMD_GROUPS 4
#endif

namespace rotleak::simd {

namespace {

using B = xsimd::batch<double, xsimd::avx2>;
using M = B::batch_bool_type;
constexpr int W = 4;
constexpr int kGroups = ROTLEAK_SIMD_GROUPS;
constexpr int kDensityBuffer = 1024;
/// rough_atan2's error, <= 2e-5 rad, is below 4e-6 in s (r / L < 0.16): a 25-fold safety
constexpr double kRoughMargin = 1e-4;

struct Lanes {
  alignas(32) double qx[W], qy[W], vx[W], vy[W], t[W], coll[W], zero[W], w[W];
  std::uint64_t id[W];
  bool live[W];
};

inline B load(const double* p) { return B::load_aligned(p); }
inline unsigned bits(const M& m) { return static_cast<unsigned>(_mm256_movemask_pd(static_cast<__m256d>(m))); }

// circular offset of s from c in [-1/2, 1/2)
inline B offset(B s, B c) {
  B d = s - c;
  return d - xsimd::floor(d + B(0.5));
}

}  // namespace

bool available() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

namespace {

/// Four particles in registers, with their bookkeeping in memory for the rare lane changes.
struct Group {
  Lanes L{};
  B qx, qy, vx, vy, t, coll, zero;
  int live = 0;
};

void park(const Scene& S, Lanes& L, int k) {
  L.live[k] = false;  // an idle lane: parked far past t_max, never reported
  L.qx[k] = 0, L.qy[k] = 0, L.vx[k] = 0, L.vy[k] = -1, L.t[k] = 2 * S.t_max + 1;
}

void reload(Group& g) {
  g.qx = load(g.L.qx), g.qy = load(g.L.qy), g.vx = load(g.L.vx), g.vy = load(g.L.vy), g.t = load(g.L.t);
  g.coll = load(g.L.coll), g.zero = load(g.L.zero);
}

void fill(const Scene& S, Group& g, void* ctx, NextParticle next) {
  for (int k = 0; k < W; ++k) {
    Start st;
    if (next(ctx, &st, &g.L.id[k])) {
      g.L.live[k] = true;
      g.L.qx[k] = st.qx, g.L.qy[k] = st.qy, g.L.vx[k] = st.vx, g.L.vy[k] = st.vy, g.L.t[k] = st.t;
      g.L.coll[k] = st.collisions;
      g.L.w[k] = st.weight;
      ++g.live;
    } else {
      park(S, g.L, k);
      g.L.coll[k] = 0;
      g.L.w[k] = 0;
    }
    g.L.zero[k] = 0;
  }
  reload(g);
}

/// Where four lanes next meet the boundary, decided as Stadium::next_hit decides it.
struct HitLanes {
  B t;         ///< flight time
  B x, y;      ///< collision point
  B cx;        ///< centre x of the arc on the side the line leaves |x| <= d/2 (used for arc hits)
  M straight;  ///< the hit is on a straight edge
  M up;        ///< moving up (the top edge, for a straight hit)
  M right;     ///< the right arc (for an arc hit)
};

/// The straight edges decide first: a line that crosses y = +-r inside |x| <= d/2 hits that edge;
/// otherwise it leaves through the arc on the side where it crosses (convexity), and one quadratic
/// t^2 + 2bt + c = 0 is solved for its larger root, in the form without cancellation.
inline HitLanes next_hit(const Scene& S, B qx, B qy, B vx, B vy) {
  const B R(S.r), HD(S.half_d), ZERO(0.0);
  HitLanes h;
  h.up = vy > ZERO;
  const B ey = xsimd::select(h.up, R, -R);
  const B tl = (ey - qy) / vy;  // a horizontal flight divides by zero here; `flat` masks it out
  const B xl = xsimd::fma(vx, tl, qx);
  const M flat = vy == ZERO;
  h.straight = (xsimd::abs(xl) <= HD) & !flat;
  h.right = (flat & (vx > ZERO)) | ((!flat) & (xl > ZERO));
  h.cx = xsimd::select(h.right, HD, -HD);
  const B dx = qx - h.cx;
  const B b = xsimd::fma(dx, vx, qy * vy);
  const B c = xsimd::fma(dx - R, dx + R, qy * qy);
  // grazing: rounding may push a tangent ray just outside, so the discriminant is clamped at 0
  const B sq = xsimd::sqrt(xsimd::max(xsimd::fms(b, b, c), ZERO));
  // b > 0 (a start outside the disc moving off its centre line) is rare: divide only when a lane needs it
  const M far = b > ZERO;
  const B ta = xsimd::any(far) ? xsimd::select(far, -c / (b + sq), sq - b) : sq - b;
  h.t = xsimd::select(h.straight, tl, ta);
  h.x = xsimd::select(h.straight, xl, xsimd::fma(h.t, vx, qx));
  h.y = xsimd::select(h.straight, ey, xsimd::fma(h.t, vy, qy));
  return h;
}

/// Stationary leak: the precomputed windows of Leak::in_windows, an x range on a straight edge and
/// two half-plane tests from the arc's centre on an arc (no transcendental function per hit).
inline M in_stationary_leak(const Scene& S, const HitLanes& h) {
  const B ZERO(0.0);
  M in(false);
  for (int w = 0; w < S.n_windows[0]; ++w)
    in = in | (h.straight & h.up & (h.x >= B(S.lo[0][w])) & (h.x <= B(S.hi[0][w])));
  for (int w = 0; w < S.n_windows[2]; ++w)
    in = in | (h.straight & !h.up & (h.x >= B(S.lo[2][w])) & (h.x <= B(S.hi[2][w])));
  const B rx = h.x - h.cx;
  for (int p = 1; p <= 3; p += 2) {
    const M on = (!h.straight) & (p == 1 ? h.right : !h.right);
    for (int w = 0; w < S.n_windows[p]; ++w) {
      const B c1 = xsimd::fms(B(S.from_x[p][w]), h.y, B(S.from_y[p][w]) * rx);  // cross(from, rel)
      const B c2 = xsimd::fms(rx, B(S.to_y[p][w]), h.y * B(S.to_x[p][w]));      // cross(rel, to)
      in = in | (on & (c1 <= ZERO) & (c2 <= ZERO));
    }
  }
  return in;
}

/// The boundary coordinate s of the four hits as Stadium::s_of computes it, the arcs' angle from
/// SLEEF's atan2 (evaluated only when a lane in `arcs` needs it; other arc lanes get s = -1).
inline B s_of(const Scene& S, const HitLanes& h, M arcs) {
  const B HD(S.half_d), ZERO(0.0), ONE(1.0);
  B s_top = h.x * B(S.inv_L);
  s_top = xsimd::select(s_top < ZERO, s_top + ONE, s_top);
  s_top = xsimd::select(s_top >= ONE, ZERO, s_top);
  const B s_bottom = xsimd::fma(HD - h.x, B(S.inv_L), B(S.junction[1]));  // a multiply, then an add
  B s_arc(-1.0);
  if (bits(arcs)) {
    // right arc: atan2(x - d/2, y); left arc: atan2(-(x + d/2), -y); one call for both
    const B ay = xsimd::select(h.right, h.x - HD, -(h.x + HD));
    const B ax = xsimd::select(h.right, h.y, -h.y);
    B ang(Sleef_atan2d4_u35avx2(static_cast<__m256d>(ay), static_cast<__m256d>(ax)));
    ang = xsimd::min(xsimd::max(ang, ZERO), B(S.pi));
    s_arc = xsimd::fma(ang, B(S.r_over_L), xsimd::select(h.right, B(S.junction[0]), B(S.junction[2])));
  }
  return xsimd::select(h.straight, xsimd::select(h.up, s_top, s_bottom), s_arc);
}

/// A cheap angle atan2(ay, ax) in [-pi, pi] for the moving leak's first look: octant reduction and
/// Abramowitz & Stegun 4.4.49 (their bound 1e-5 rad on [0, 1]; with the reflections and the seven
/// published digits of the coefficients, 1.15e-5 measured): taken as |error| <= 2e-5 rad, which
/// tests/test_simd.cpp checks against libm on 4 * 10^6 angles.
inline B rough_atan2(B ay, B ax) {
  const B a = xsimd::abs(ay), b = xsimd::abs(ax);
  const B hi = xsimd::max(a, b), lo = xsimd::min(a, b);
  const B z = lo / xsimd::select(hi > B(0.0), hi, B(1.0));
  const B z2 = z * z;
  B p = xsimd::fma(z2, B(0.0208351), B(-0.0851330));
  p = xsimd::fma(z2, p, B(0.1801410));
  p = xsimd::fma(z2, p, B(-0.3302995));
  p = xsimd::fma(z2, p, B(0.9998660));
  B t = z * p;
  t = xsimd::select(a > b, B(1.5707963267948966) - t, t);
  t = xsimd::select(ax < B(0.0), B(3.141592653589793) - t, t);
  return xsimd::select(ay < B(0.0), -t, t);
}

/// Per-lane answers from the core for the lanes in `ask`, replacing `m` there.
template <class F>
inline M ask_core(M m, M ask, F core) {
  alignas(32) double v[W];
  const unsigned am = bits(ask), mm = bits(m);
  for (int i = 0; i < W; ++i) v[i] = ((am >> i) & 1) ? (core(i) ? 1.0 : 0.0) : (((mm >> i) & 1) ? 1.0 : 0.0);
  return load(v) != B(0.0);
}

/// Moving leak: the phase frac(start + omega t) as LeakSchedule::phase computes it, then Leak::hit:
/// on an arc nothing unless the leak's centre is within reach of the arc's middle; else the
/// circular distance of s from the centre against the half width, lanes near a leak end decided
/// by the core.
inline M in_moving_leak(const Scene& S, const HitLanes& h, B t, M live, void* ctx, const Exact& exact) {
  const B ZERO(0.0);
  const B prod = B(S.omega_hi) * t;
  // the exact error of hi*t needs a real FMA (xsimd's fms on plain avx2 rounds twice)
  const B err(
      _mm256_fmsub_pd(static_cast<__m256d>(B(S.omega_hi)), static_cast<__m256d>(t), static_cast<__m256d>(prod)));
  B ph = (prod - xsimd::floor(prod)) + xsimd::fma(B(S.omega_lo), t, err) + B(S.start);
  ph = ph - xsimd::floor(ph);
  const B mid = xsimd::select(h.right, B(S.arc_mid[1]), B(S.arc_mid[3]));
  const B reach = xsimd::select(h.right, B(S.arc_reach[1]), B(S.arc_reach[3]));
  M near_arc = (!h.straight) & (xsimd::abs(offset(mid, ph)) <= reach) & live;
  if (bits(near_arc)) {
    // first look with the rough angle: a hit more than kRoughMargin (in s) outside the leak is out
    // for any angle within 2e-5 rad (4e-6 in s) of it; only the rest get the exact angle
    const B HD(S.half_d);
    const B ang = xsimd::min(
        xsimd::max(rough_atan2(xsimd::select(h.right, h.x - HD, -(h.x + HD)), xsimd::select(h.right, h.y, -h.y)), ZERO),
        B(S.pi));
    const B s_rough = xsimd::fma(ang, B(S.r_over_L), xsimd::select(h.right, B(S.junction[0]), B(S.junction[2])));
    near_arc = near_arc & (xsimd::abs(offset(s_rough, ph)) <= B(S.half_width + kRoughMargin));
  }
  const B s = s_of(S, h, near_arc);
  const B off = xsimd::abs(offset(s, ph));
  M in = (h.straight | near_arc) & (off <= B(S.half_width));
  const M unsure = near_arc & (xsimd::abs(off - B(S.half_width)) <= B(S.margin));
  if (bits(unsure)) {
    alignas(32) double x[W], y[W], tt[W];
    h.x.store_aligned(x), h.y.store_aligned(y), t.store_aligned(tt);
    const unsigned rm = bits(h.right);
    in = ask_core(in, unsure, [&](int i) { return exact.escape(ctx, ((rm >> i) & 1) ? 1 : 3, x[i], y[i], tt[i]); });
  }
  return in;
}

/// f_c: the lanes in `count` (alive, t inside a window) add one collision to bin floor(s bins) of
/// each window that holds t; arc lanes near a bin edge take s from the core.
inline void observe_density(const Scene& S, const Group& g, const HitLanes& h, B t, M count, void* ctx,
                            const Exact& exact, DensityHit* buf, int& used) {
  const B s = s_of(S, h, count & !h.straight);
  const B sb = s * B(static_cast<double>(S.bins));
  const M unsure = count & !h.straight & (xsimd::abs(sb - xsimd::nearbyint(sb)) <= B(S.margin * S.bins));
  alignas(32) double sv[W], tv[W], x[W], y[W];
  s.store_aligned(sv), t.store_aligned(tv);
  const unsigned cm = bits(count), um = bits(unsure), rm = bits(h.right);
  if (um) h.x.store_aligned(x), h.y.store_aligned(y);
  for (int i = 0; i < W; ++i) {
    if (!((cm >> i) & 1)) continue;
    const double si = ((um >> i) & 1) ? exact.s_of(ctx, ((rm >> i) & 1) ? 1 : 3, x[i], y[i]) : sv[i];
    int b = static_cast<int>(si * S.bins);  // as DensityObserver bins it
    if (b >= S.bins) b = S.bins - 1;
    if (b < 0) b = 0;
    for (int w = 0; w < S.density_windows; ++w)
      if (tv[i] >= S.win_from[w] && tv[i] <= S.win_to[w]) {
        if (used == kDensityBuffer) {
          exact.density(ctx, buf, used);
          used = 0;
        }
        buf[used++] = {static_cast<std::uint32_t>(w * S.bins + b), g.L.w[i]};
      }
  }
}

/// Reports the lanes in `done` to finish() and refills them from next() (or parks them).
void retire(const Scene& S, Group& g, const HitLanes& h, M done, M esc, M stuck, M over, M handoff, void* ctx,
            NextParticle next, Finish finish) {
  Lanes& L = g.L;
  g.qx.store_aligned(L.qx), g.qy.store_aligned(L.qy), g.vx.store_aligned(L.vx), g.vy.store_aligned(L.vy);
  g.t.store_aligned(L.t), g.coll.store_aligned(L.coll), g.zero.store_aligned(L.zero);
  const unsigned dm = bits(done), em = bits(esc), sm = bits(stuck), om = bits(over), hm = bits(handoff);
  const unsigned straight_m = bits(h.straight), up_m = bits(h.up), right_m = bits(h.right);
  for (int i = 0; i < W; ++i) {
    if (!((dm >> i) & 1) || !L.live[i]) continue;
    End e;
    e.fate = ((om >> i) & 1)   ? LaneEnd::survived
             : ((em >> i) & 1) ? LaneEnd::escaped
             : ((sm >> i) & 1) ? LaneEnd::stuck
             : ((hm >> i) & 1) ? LaneEnd::handed_back
                               : LaneEnd::survived;
    e.t = e.fate == LaneEnd::survived ? S.t_max : L.t[i];
    e.qx = L.qx[i];
    e.qy = L.qy[i];
    e.vx = L.vx[i];
    e.vy = L.vy[i];
    e.piece = ((straight_m >> i) & 1) ? (((up_m >> i) & 1) ? 0 : 2) : (((right_m >> i) & 1) ? 1 : 3);
    e.collisions = static_cast<std::uint64_t>(L.coll[i]);
    finish(ctx, L.id[i], e);
    Start st;
    if (next(ctx, &st, &L.id[i])) {
      L.qx[i] = st.qx, L.qy[i] = st.qy, L.vx[i] = st.vx, L.vy[i] = st.vy, L.t[i] = st.t;
      L.coll[i] = st.collisions;
      L.w[i] = st.weight;
    } else {
      park(S, L, i);
      --g.live;
      L.coll[i] = 0;
      L.w[i] = 0;
    }
    L.zero[i] = 0;
  }
  reload(g);
}

/// One collision for the four lanes of g, in the scalar core's order (particle.hpp advance):
/// next hit, time check, escape test, reflection, zero-flight count; lanes that end are reported
/// and refilled.
inline void step(const Scene& S, Group& g, void* ctx, NextParticle next, Finish finish, const Exact& exact,
                 DensityHit* buf, int& used) {
  const B R(S.r), HD(S.half_d), TMAX(S.t_max), ZERO(0.0), ONE(1.0);
  const B vx = g.vx, vy = g.vy;
  const HitLanes h = next_hit(S, g.qx, g.qy, vx, vy);
  const B t = g.t + h.t;
  const M over = t > TMAX;
  g.coll = g.coll + xsimd::select(over, ZERO, ONE);  // a flight past t_max is not a collision
  if (S.density_windows > 0) {                       // parked lanes sit past t_max: `over` excludes them
    M in_window(false);
    for (int w = 0; w < S.density_windows; ++w)
      in_window = in_window | ((t >= B(S.win_from[w])) & (t <= B(S.win_to[w])));
    const M count = in_window & !over;
    if (bits(count)) observe_density(S, g, h, t, count, ctx, exact, buf, used);
  }
  const M esc = (S.rotating ? in_moving_leak(S, h, t, !over, ctx, exact) : in_stationary_leak(S, h)) & !over;

  // reflect: about the radius vector as it is, not divided by r (see Stadium::reflect)
  const B wx = h.x - h.cx;
  const B k = B(2.0) * xsimd::fma(wx, vx, h.y * vy) / xsimd::fma(wx, wx, h.y * h.y);
  g.vx = xsimd::select(h.straight, vx, xsimd::fnma(k, wx, vx));
  g.vy = xsimd::select(h.straight, -vy, xsimd::fnma(k, h.y, vy));
  g.zero = xsimd::select(h.t > ZERO, ZERO, g.zero + ONE);
  const M stuck = g.zero > B(static_cast<double>(kMaxZeroFlights));
  g.qx = h.x, g.qy = h.y, g.t = t;
  // a long run between the straight edges ahead: (room to the arc) |vy| >= n 2r |vx|, no division
  M handoff(false);
  if (S.handoff_bounces > 0) {
    const B room = xsimd::select(vx > ZERO, HD - h.x, HD + h.x);
    handoff = h.straight & !over & !esc & (room * xsimd::abs(g.vy) >= B(2 * S.handoff_bounces) * R * xsimd::abs(g.vx));
  }
  const M done = over | esc | stuck | handoff;
  if (bits(done)) retire(S, g, h, done, esc, stuck, over, handoff, ctx, next, finish);
}

}  // namespace

void run(const Scene& S, void* ctx, NextParticle next, Finish finish, const Exact& exact) {
  // Independent groups side by side: each collision is a long dependent chain (division, square
  // root, division), and several chains at once keep the core busy.
  Group g[kGroups];
  DensityHit buf[kDensityBuffer];
  int used = 0;
  for (Group& x : g) fill(S, x, ctx, next);
  for (;;) {
    int live = 0;
    for (Group& x : g) {
      step(S, x, ctx, next, finish, exact, buf, used);
      live += x.live;
    }
    if (live == 0) break;
  }
  if (used) exact.density(ctx, buf, used);
}

void rough_angles(const double* ay, const double* ax, double* out, std::size_t n) {
  for (std::size_t i = 0; i + W <= n; i += W)
    rough_atan2(B::load_unaligned(ay + i), B::load_unaligned(ax + i)).store_unaligned(out + i);
}

}  // namespace rotleak::simd
