// Compiled with -mavx2 -mfma (see src/CMakeLists.txt). Keep this file self-contained: no std
// algorithms or shared inline helpers whose AVX2 copies the linker could hand to scalar code.
//
// Bit-identical to the scalar core: every expression is evaluated in the scalar core's order with
// one rounding per operation (xsimd's fma/fms on the plain avx2 arch are a multiply then an add, as
// the scalar build with -ffp-contract=off), so per-particle results and tallies equal the scalar
// engine's exactly. The one deliberate FMA is the exact product error of the leak phase, which the
// scalar core also takes from a true fma.
#include "sim/simd_engine.hpp"

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

struct Lanes {
  alignas(32) double qx[W], qy[W], vx[W], vy[W], t[W], coll[W], zero[W];
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
      ++g.live;
    } else {
      park(S, g.L, k);
      g.L.coll[k] = 0;
    }
    g.L.zero[k] = 0;
  }
  reload(g);
}

/// One collision for the four lanes of g; lanes that end are reported and refilled.
inline void step(const Scene& S, Group& g, void* ctx, NextParticle next, Finish finish) {
  const B R(S.r), HD(S.half_d), TMAX(S.t_max), ZERO(0.0), ONE(1.0);
  B qx = g.qx, qy = g.qy, vx = g.vx, vy = g.vy, t = g.t;
  // next hit: the straight edge first, the arc on the side where the line leaves |x| <= d/2
  const M up = vy > ZERO;
  const B ey = xsimd::select(up, R, -R);
  const B tl = (ey - qy) / vy;
  const B xl = xsimd::fma(vx, tl, qx);
  const M flat = vy == ZERO;
  const M straight = (xsimd::abs(xl) <= HD) & !flat;
  const M right = (flat & (vx > ZERO)) | ((!flat) & (xl > ZERO));
  const B cx = xsimd::select(right, HD, -HD);
  const B dx = qx - cx;
  const B b = xsimd::fma(dx, vx, qy * vy);
  const B c = xsimd::fma(dx - R, dx + R, qy * qy);
  const B sq = xsimd::sqrt(xsimd::max(xsimd::fms(b, b, c), ZERO));
  // b > 0 (a start outside the disc moving off its centre line) is rare: divide only when a lane needs it
  const M far = b > ZERO;
  const B ta = xsimd::any(far) ? xsimd::select(far, -c / (b + sq), sq - b) : sq - b;
  const B th = xsimd::select(straight, tl, ta);
  const B hx = xsimd::select(straight, xl, xsimd::fma(th, vx, qx));
  const B hy = xsimd::select(straight, ey, xsimd::fma(th, vy, qy));
  t = t + th;
  const M over = t > TMAX;
  g.coll = g.coll + xsimd::select(over, ZERO, ONE);

  // escape test
  M in(false);
  if (!S.rotating) {
    for (int w = 0; w < S.n_windows[0]; ++w) in = in | (straight & up & (hx >= B(S.lo[0][w])) & (hx <= B(S.hi[0][w])));
    for (int w = 0; w < S.n_windows[2]; ++w) in = in | (straight & !up & (hx >= B(S.lo[2][w])) & (hx <= B(S.hi[2][w])));
    const B rx = hx - cx;
    for (int p = 1; p <= 3; p += 2) {
      const M on = (!straight) & (p == 1 ? right : !right);
      for (int w = 0; w < S.n_windows[p]; ++w) {
        const B c1 = xsimd::fms(B(S.from_x[p][w]), hy, B(S.from_y[p][w]) * rx);  // cross(from, rel)
        const B c2 = xsimd::fms(rx, B(S.to_y[p][w]), hy * B(S.to_x[p][w]));      // cross(rel, to)
        in = in | (on & (c1 <= ZERO) & (c2 <= ZERO));
      }
    }
  } else {
    const B prod = B(S.omega_hi) * t;
    // the exact error of hi*t needs a real FMA (xsimd's fms on plain avx2 rounds twice)
    const B err(_mm256_fmsub_pd(static_cast<__m256d>(B(S.omega_hi)), static_cast<__m256d>(t), static_cast<__m256d>(prod)));
    B ph = (prod - xsimd::floor(prod)) + xsimd::fma(B(S.omega_lo), t, err) + B(S.start);
    ph = ph - xsimd::floor(ph);
    B s_top = hx * B(S.inv_L);
    s_top = xsimd::select(s_top < ZERO, s_top + ONE, s_top);
    const B s_bottom = xsimd::fma(HD - hx, B(S.inv_L), B(S.junction[1]));
    const B PI(S.pi);
    B ang_r = xsimd::atan2(hx - HD, hy), ang_l = xsimd::atan2(-(hx + HD), -hy);
    ang_r = xsimd::min(xsimd::max(ang_r, ZERO), PI);
    ang_l = xsimd::min(xsimd::max(ang_l, ZERO), PI);
    const B s_right = xsimd::fma(ang_r, B(S.r_over_L), B(S.junction[0]));
    const B s_left = xsimd::fma(ang_l, B(S.r_over_L), B(S.junction[2]));
    const B s = xsimd::select(straight, xsimd::select(up, s_top, s_bottom), xsimd::select(right, s_right, s_left));
    in = xsimd::abs(offset(s, ph)) <= B(S.half_width);
  }
  const M esc = in & !over;

  // reflect: about the radius vector as it is (see Stadium::reflect)
  const B wx = hx - cx;
  const B k = B(2.0) * xsimd::fma(wx, vx, hy * vy) / xsimd::fma(wx, wx, hy * hy);
  g.vx = xsimd::select(straight, vx, xsimd::fnma(k, wx, vx));
  g.vy = xsimd::select(straight, -vy, xsimd::fnma(k, hy, vy));
  g.zero = xsimd::select(th > ZERO, ZERO, g.zero + ONE);
  const M stuck = g.zero > B(static_cast<double>(kMaxZeroFlights));
  g.qx = hx, g.qy = hy, g.t = t;
  // a long run between the straight edges ahead: (room to the arc) |vy| >= n 2r |vx|, no division
  M handoff(false);
  if (S.handoff_bounces > 0) {
    const B room = xsimd::select(vx > ZERO, HD - hx, HD + hx);
    handoff = straight & !over & !esc & (room * xsimd::abs(g.vy) >= B(2 * S.handoff_bounces) * R * xsimd::abs(g.vx));
  }

  const M done = over | esc | stuck | handoff;
  const unsigned dm = bits(done);
  if (!dm) return;
  Lanes& L = g.L;
  g.qx.store_aligned(L.qx), g.qy.store_aligned(L.qy), g.vx.store_aligned(L.vx), g.vy.store_aligned(L.vy);
  g.t.store_aligned(L.t), g.coll.store_aligned(L.coll), g.zero.store_aligned(L.zero);
  const unsigned em = bits(esc), sm = bits(stuck), om = bits(over), hm = bits(handoff);
  const unsigned straight_m = bits(straight), up_m = bits(up), right_m = bits(right);
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
    } else {
      park(S, L, i);
      --g.live;
      L.coll[i] = 0;
    }
    L.zero[i] = 0;
  }
  reload(g);
}

}  // namespace

void run(const Scene& S, void* ctx, NextParticle next, Finish finish) {
  // Independent groups side by side: each collision is a long dependent chain (division, square
  // root, division), and several chains at once keep the core busy.
  Group g[kGroups];
  for (Group& x : g) fill(S, x, ctx, next);
  for (;;) {
    int live = 0;
    for (Group& x : g) {
      step(S, x, ctx, next, finish);
      live += x.live;
    }
    if (live == 0) break;
  }
}

}  // namespace rotleak::simd
