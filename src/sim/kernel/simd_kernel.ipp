// The vectorised kernel, written once for any register width. Included, inside a namespace of its own,
// by one translation unit per instruction set (simd_engine.cpp: AVX2, 4 lanes; simd_avx512.cpp:
// AVX-512, 8 lanes), each compiled for its set alone (src/CMakeLists.txt). The includer includes the
// formulas (geometry/, leak/, numeric/sin_cos.hpp) and sim/kernel/flatten.hpp at file scope and defines, in
// an anonymous namespace before the #include: B (the register: xsimd::batch<double, arch>), M (its mask), W (lanes per
// register), G (registers per pack), bits(M) (lane k is bit k), fused_fms(a, b, c) (a true fused
// a * b - c), sleef_atan2(y, x) (SLEEF's u35 atan2), U and mul_wide (64-bit lanes, their low halves' product).
//
// The physics is not written here: every expression of a flight, a collision, a boundary coordinate and
// the leak is a call into the shared formulas (geometry/formulas.hpp, leak/leak_formulas.hpp), the
// ones Stadium<R> and Leak<R> call, instantiated on this file's pack V with its lane masks MV and the
// selection hook below (select, choose, both). What is here: the stadium's part of the collision step (StadiumStep: the
// convex next hit, the leak test, the reflection, the fast-forward's hand-off), the two approximate angles and the
// cascade that decides which one a lane may trust (arc_s_for), and f_c's binning. The pack's lanes and the step's
// order, written once for every table, are sim/kernel/simd_lanes.ipp (lane_step). Keep it self-contained otherwise: the
// formulas are templates instantiated on V alone (internal linkage); no std algorithm or shared inline function whose
// vector copy the linker could hand to scalar code (ctest Layers.KernelObjectsShareNoInlineCode checks the objects);
// everything here has internal linkage but run_kernel, rough_kernel, cell_kernel, probe_kernel, flights_kernel,
// pack_size, birkhoff_kernel and flow_kernel.
//
// What matches the scalar core, as the tests check it (tests/test_simd.cpp, tests/test_stadiums.cpp):
// - Stationary leak: bit-identical. The formulas are evaluated in the scalar core's order with one
//   rounding per operation (the build has -ffp-contract=off), and the escape test is the core's own
//   (leak_takes, leak/leak_window.hpp, on the windows the kernel copies from Leak<double>), so per-particle
//   results, escape records and tallies equal the scalar engine's exactly.
// - Moving leak and f_c: the same bits too. The boundary coordinate of an arc hit needs an angle, and
//   the kernel has two cheaper ones than the core's (formula::atan2_of): a rough polynomial (rough_arc_s, within
//   1e-5 rad) and SLEEF's vector atan2 (Sleef_atan2d4_u35avx2 / Sleef_atan2d8_u35avx512f, within 3.5 ulp; the
//   core's is within 2 ulp, so the two differ by < 3e-15 in [0, pi] and s by < 1e-15). A decision on s (inside
//   the leak or not; which f_c bin) can differ from the core's only within that error of an edge, so
//   arc_s_for takes the rough s where it is far from every edge, SLEEF's where it is not, and the
//   core's own s (formula::atan2_of, lane by lane) within `margin` (1e-12) of one: every decision is the core's.
// The deliberate FMAs: the exact product error of the leak phase, as in the scalar core, and the rough s
// (rough_arc_s), whose bits decide nothing (only its error bound does).
//
// Speed: a collision is a long dependent chain (division, square root, division), so one register of
// particles leaves the core waiting. The kernel works on a pack of G registers (V: N = W G lanes), each
// operation applied to the G registers side by side, so the G chains interleave instruction by
// instruction; branches (an ended lane, a lane near a moving leak) are taken once per pack. The pack
// (V, MV, their operations and the selection hook) is sim/kernel/simd_pack.ipp, included before this file.

/// How far the kernel trusts its angles, in one place (arc_s_for, in_moving_leak): rough_arc_s's error
/// bound in rad (3.4e-6 in theory and measured; Simd.RoughArcAngleWithinItsBound checks the bound), i.e.
/// kRoughAngleError r / L in s (< 1.6e-6: r / L < 0.16); a rough s decides only beyond kRoughAngleSafety times
/// that bound from an edge (twofold; sixfold on the measured error). SLEEF's s decides beyond
/// KernelScene::margin of one.
constexpr double kRoughAngleError = 1e-5;
constexpr double kRoughAngleSafety = 2;

namespace {
/// Where the lanes next meet the boundary: formula::next_exit, as Stadium::next_hit.
using HitLanes = formula::Exit<V>;

/// formula::next_exit's pieces in its order, every lane computing both the straight and the arc hit;
/// the arc's rare far root (b > 0) divides only in the registers that have such a lane.
inline HitLanes next_hit(const KernelScene& S, const V& qx, const V& qy, const V& vx, const V& vy) {
  const V R(S.r), HD(S.half_d), ZERO(0.0);
  HitLanes h;
  const MV flat = vy == ZERO;
  h.up = vy > ZERO;
  const V ey = select(h.up, R, -R);
  const V tl = formula::line_flight(ey, qy, vy);
  const V xl = formula::along(qx, vx, tl);
  h.straight = formula::hits_straight_edge(flat, xl, HD);
  h.right = formula::leaves_right(h.straight, flat, vx, xl);
  h.cx = select(h.right, HD, -HD);
  const V dx = formula::from_centre(qx, h.cx);
  const V b = formula::arc_b(dx, qy, vx, vy), c = formula::arc_c(dx, qy, R), sq = formula::arc_sq(b, c);
  V ta = formula::larger_root_near(b, sq);
  each([&](int i) {
    // only arc lanes look at ta: a straight lane's b (from a junk centre) is often > 0, and would make
    // this rare branch a frequent, unpredictable one
    const M far = (b.b[i] > B(0.0)) & !h.straight.m[i];
    if (bits(far)) ta.b[i] = xsimd::select(far, formula::larger_root_far(b.b[i], c.b[i], sq.b[i]), ta.b[i]);
  });
  h.t = select(h.straight, tl, ta);
  h.x = select(h.straight, xl, formula::along(qx, vx, h.t));
  h.y = select(h.straight, ey, formula::along(qy, vy, h.t));
  return h;
}

/// The exact error of a b = p, lane by lane: a true fused multiply-subtract (the leak phase's product error, as
/// num_traits<double>::product_error gives the scalar core).
constexpr auto fms_error = [](const V& a, const V& b, const V& p) {
  V err;
  each([&](int i) { err.b[i] = fused_fms(a.b[i], b.b[i], p.b[i]); });
  return err;
};

/// The leak test of the lanes of `look`, Leak::hit's own: leak_takes (leak/leak_window.hpp) on the stadium's leak
/// and its four pieces (0 top, 1 right arc, 2 bottom, 3 left arc: the lanes on each from next_hit's masks), with
/// `s_of(lanes, c, hw)` the hit's s for the lanes a moving leak asks.
template <class SOf>
[[gnu::always_inline]] inline MV stadium_leak(const KernelScene& S, const HitLanes& h, const V& t, const MV& look,
                                              SOf& s_of) {
  const auto on_piece = [&](int k) {
    return k == 0 ? h.straight & h.up : k == 2 ? h.straight & !h.up : k == 1 ? h.right & !h.straight : !(h.right | h.straight);
  };
  return leak_takes(S.leak, S.leak_piece, on_piece, h.x, h.y, t, look, s_of, fms_error);
}

/// Stationary leak: its windows (an x range on a straight edge, two half-plane tests from the arc's centre on an
/// arc: no transcendental function per hit); no lane asks for s.
inline MV in_stationary_leak(const KernelScene& S, const HitLanes& h, const MV& look) {
  const auto no_s = [](const MV&, const V&, const V&) { return V(0.0); };
  return stadium_leak(S, h, V(0.0), look, no_s);
}

/// The boundary coordinate s of the straight hits (formula::straight_s; arc lanes: junk).
inline V straight_s(const KernelScene& S, const HitLanes& h) {
  return formula::straight_s(h.up, h.x, V(S.half_d), V(S.inv_L), V(S.junction[1]));
}

/// s of an arc hit from its angle (formula::arc_s, from the arc's start in s).
[[gnu::always_inline]] inline V arc_s_from(const KernelScene& S, const HitLanes& h, const V& angle) {
  return formula::arc_s(angle, select(h.right, V(S.junction[0]), V(S.junction[2])), V(S.r_over_L), V(S.pi));
}

/// s of the arc hits in `arcs` from SLEEF's atan2 (evaluated only for the registers with a lane in
/// `arcs`); the other lanes keep `s`.
inline V sleef_arc_s(const KernelScene& S, const HitLanes& h, const MV& arcs, const V& s) {
  const V ay = formula::arc_angle_y(h.right, h.x, V(S.half_d)), ax = formula::arc_angle_x(h.right, h.y);
  V angle(0.0);
  each([&](int i) {
    if (bits(arcs.m[i])) angle.b[i] = sleef_atan2(ay.b[i], ax.b[i]);
  });
  return select(arcs, arc_s_from(S, h, angle), s);
}

/// A cheap s of an arc point for the first look, within kRoughAngleError r / L of formula::arc_s(atan2(ay, ax))
/// (the angle clamped to [0, pi]), for a point at distance r from its arc's centre (ay, ax as formula::arc_angle_y,
/// arc_angle_x give them: ay >= 0 on the arc). By the half angle the angle is pi/2 - 2 atan(z), z = ax / (r + ay)
/// in [-1, 1], with atan(z) = z p(z^2), p a polynomial of degree 5 in z^2 (Lawson's minimax fit on [0, 1], 1.67e-6
/// rad at most), so within 3.4e-6 rad of the exact angle plus a few ulps for the point's own distance from the
/// centre (rounded: r (1 + 1e-15)). Its bits decide nothing (only its bound, through the cascade), so it is
/// evaluated in the fewest operations, with true fused multiply-adds: the coefficients `k` are p's scaled by
/// -2 r / L (RoughArc), so s = mid + z k(z^2), mid = the arc's start + (pi / 2) r / L. An ay with its sign bit
/// set (a point a rounding off the arc's end, or -0) has a negative angle, which arc_s clamps to 0: s = the
/// arc's start, as here. The upper clamp is not taken: beyond pi the polynomial's s lies within its bound of
/// arc_s's. tests/test_simd.cpp (Simd.RoughArcAngleWithinItsBound) checks it against libm within the bound.
constexpr double kRoughAtan[6] = {-0.011719012263455883, 0.05264705591686962, -0.11642623523528958,
                                  0.19354029313772714,   -0.3326228188511722, 0.9999772190936193};

/// rough_arc_s's constants for boundary coordinates scaled by r / L (the scene's, or 1 for the bare angle)
struct RoughArc {
  double k[6];
  explicit RoughArc(double r_over_L) {
    for (int i = 0; i < 6; ++i) k[i] = -2 * kRoughAtan[i] * r_over_L;
  }
};

[[gnu::always_inline]] inline B rough_arc_s(const B& ay, const B& ax, const B& r, const B& mid, const B& start,
                                            const RoughArc& c) {
  // Estrin's scheme: p = (k5 + k4 w) + w^2 (k3 + k2 w) + w^4 (k1 + k0 w), three steps deep after w = z^2
  // instead of Horner's five (the escape test's result is the branch that retires lanes: its latency counts)
  const B z = ax / (r + ay);
  const B w = z * z, w2 = w * w, w4 = w2 * w2;
  const B e0 = xsimd::fma(w, B(c.k[4]), B(c.k[5])), e1 = xsimd::fma(w, B(c.k[2]), B(c.k[3]));
  const B e2 = xsimd::fma(w, B(c.k[0]), B(c.k[1]));
  const B p = xsimd::fma(w4, e2, xsimd::fma(w2, e1, e0));
  return xsimd::select(xsimd::copysign(B(1.0), ay) < B(0.0), start, xsimd::fma(z, p, mid));
}

/// s of the arc hits from rough_arc_s: within kRoughAngleError r / L (r / L < 0.16) of the core's. ay as
/// formula::arc_angle_y spells it: at x = -d/2 its -0 (not |x| - d/2's +0) is what makes the core's angle 0
/// there. Inlined by force: as a call it returns its pack through memory (docs/performance.md, "Why the kernel
/// is written as it is").
[[gnu::always_inline]] inline V rough_arc_s(const KernelScene& S, const HitLanes& h) {
  const V ay = formula::arc_angle_y(h.right, h.x, V(S.half_d)), ax = formula::arc_angle_x(h.right, h.y);
  const V start = select(h.right, V(S.junction[0]), V(S.junction[2]));
  const V mid = start + V(S.pi / 2 * S.r_over_L);
  const RoughArc c(S.r_over_L);
  V s;
  each([&](int i) { s.b[i] = rough_arc_s(ay.b[i], ax.b[i], B(S.r), mid.b[i], start.b[i], c); });
  return s;
}

/// The cascade's second half: the lanes of `fine` take SLEEF's s, which they keep beyond KernelScene::margin of
/// every edge of near(s, tol), else the core's own s (Stadium::s_of: the double tier's atan2, formula::atan2_scalar, of
/// the same arguments, lane by lane, then formula::arc_s); the other lanes keep `s`.
template <class Near>
inline V fine_arc_s(const KernelScene& S, const HitLanes& h, const MV& fine, V s, const Near& near) {
  s = sleef_arc_s(S, h, fine, s);
  const MV ask = fine & near(s, S.margin);
  if (const unsigned m = bits(ask)) {
    alignas(sizeof(B)) double y[N], x[N], angle[N] = {};
    store(formula::arc_angle_y(h.right, h.x, V(S.half_d)), y), store(formula::arc_angle_x(h.right, h.y), x);
    for_lanes(m, [&](int i) { angle[i] = formula::atan2_scalar(y[i], x[i]); });
    s = select(ask, arc_s_from(S, h, load(angle)), s);
  }
  return s;
}

/// The cascade "cheap angle, then a precise one, then ask the core" (a filtered predicate, as CGAL's):
/// s of the arc lanes in `arcs` (the other lanes keep `s`), exact enough that every decision that
/// near(s, tol) guards comes out as the core's; near(s, tol) gives the lanes whose s lies within tol
/// (in s) of one of that decision's edges. A lane keeps the rough s beyond kRoughAngleSafety times its bound
/// from every edge, else takes fine_arc_s.
template <class Near>
inline V arc_s_for(const KernelScene& S, const HitLanes& h, const MV& arcs, V s, const Near& near) {
  if (!bits(arcs)) return s;
  s = select(arcs, rough_arc_s(S, h), s);
  const MV fine = arcs & near(s, kRoughAngleSafety * kRoughAngleError * S.r_over_L);
  if (!bits(fine)) return s;
  return fine_arc_s(S, h, fine, s, near);
}

/// The s of the hits of the lanes in `asks` for a moving leak's decision against centre c and half width hw: a
/// straight hit's formula::straight_s, an arc hit's from the cascade with the leak's two ends as its edges; the
/// other lanes keep `s`.
[[gnu::always_inline]] inline V moving_leak_s(const KernelScene& S, const HitLanes& h, const MV& asks, const V& s,
                                              const V& c, const V& hw) {
  const auto near_end = [&](const V& x, double tol) { return formula::distance_to_leak_end(x, c, hw) <= V(tol); };
  return select(asks & h.straight, straight_s(S, h), arc_s_for(S, h, asks & !h.straight, s, near_end));
}

/// Moving leak, Leak::hit's decision at every lane of `live`: the exact phase, may_touch on an arc, s from
/// moving_leak_s.
inline MV in_moving_leak_exact(const KernelScene& S, const HitLanes& h, const V& t, const MV& live) {
  const auto s_of = [&](const MV& asks, const V& c, const V& hw) { return moving_leak_s(S, h, asks, V(0.0), c, hw); };
  return stadium_leak(S, h, t, live, s_of);
}

/// A cheap s of the straight hits for the first look: x / L on the top edge, unwrapped (the leak test takes s
/// modulo 1), junction1 + (d/2 - x) / L on the bottom one; within a few ulps of formula::straight_s modulo 1.
[[gnu::always_inline]] inline V rough_straight_s(const KernelScene& S, const HitLanes& h) {
  const V base = select(h.up, V(0.0), V(S.junction[1] + S.half_d * S.inv_L));
  const V slope = select(h.up, V(S.inv_L), V(-S.inv_L));
  V s;
  each([&](int i) { s.b[i] = xsimd::fma(h.x.b[i], slope.b[i], base.b[i]); });
  return s;
}

/// Moving leak, the same decisions as a filtered predicate. The cheap centre c (formula::rough_leak_phase) is
/// within b = KernelScene::phase_bound of the exact one, the rough s (rough_arc_s, rough_straight_s) within
/// kRoughAngleError r / L of the core's; a lane whose distance from the leak's ends (gap) exceeds those errors
/// is decided by it, the rare others (`unsure`) by Leak::hit's own decision: the exact phase, may_touch, and s
/// from fine_arc_s. Leak::hit asks first whether the leak can touch the arc (may_touch: its centre within
/// reach = half the arc + the half width of the arc's middle); a hit inside the leak by more than those errors
/// lies on an arc the leak touches by as much (the triangle inequality), so only `unsure` lanes ask it.
inline MV in_moving_leak(const KernelScene& S, const HitLanes& h, const V& t, const MV& live) {
  if (S.phase_bound == 0) return in_moving_leak_exact(S, h, t, live);
  const double b = S.phase_bound;
  const V c = formula::rough_leak_phase(V(S.leak.omega_hi), V(S.leak.start), t);
  const MV arc = (!h.straight) & live;
  V s = rough_straight_s(S, h);
  if (S.arcs_reachable && bits(arc)) s = select(arc, rough_arc_s(S, h), s);
  // s - c less its nearest integer (formula::circular_offset takes floor(x + 1/2): the two differ only at offsets
  // near 1/2, far from a leak of half width <= 1/4), one rounding instruction shorter
  const V delta = s - c;
  const V gap = abs(delta - nearbyint(delta)) - V(S.leak.half_width);  // <= 0: inside
  const MV looked = S.arcs_reachable ? live : h.straight & live;
  const V tol(kRoughAngleSafety * kRoughAngleError * S.r_over_L + b);
  MV in = looked & (gap <= V(0.0));
  const MV unsure = looked & (abs(gap) <= tol);
  if (bits(unsure)) {
    // Leak::hit's own decision, the arc lanes' s refined from the rough one
    const auto s_of = [&](const MV& asks, const V& ph, const V& hw) {
      const MV fine = asks & arc;
      return select(asks & h.straight, straight_s(S, h),
                    bits(fine) ? fine_arc_s(S, h, fine, s,
                                            [&](const V& x, double e) {
                                              return formula::distance_to_leak_end(x, ph, hw) <= V(e);
                                            })
                               : s);
    };
    in = select(unsure, stadium_leak(S, h, t, unsure, s_of), in);
  }
  return in;
}

/// The time cell of t (formula::time_cell): one count per collision serves every window (the caller
/// folds the cells into them).
inline V time_cell(const KernelScene& S, const V& t) {
  // formula::time_cell over the edges the span leaves open (KernelScene::cell_base): t is a counted one's
  const V one(1.0), zero(0.0);
  V cell(S.cell_base);
  for (int k = 0; k < S.n_cell_from; ++k) cell = cell + select(t >= V(S.cell_from[k]), one, zero);
  for (int k = 0; k < S.n_cell_to; ++k) cell = cell + select(t > V(S.cell_to[k]), one, zero);
  return cell;
}

/// f_c: the lanes in `count` (alive, t within the windows' span) add one collision to bin
/// floor(s bins) of their time cell (see simd::DensityHit; a cell in a gap has no window); the arc
/// lanes' s from the cascade with the bin edges as its edges.
/// f_c's bin floor(s bins) of the lanes in `count`: the straight lanes' s by formula::straight_s, the arc
/// lanes' from the cascade with the bin edges as its edges.
inline V density_bin_of(const KernelScene& S, const HitLanes& h, const MV& count) {
  const V bins(static_cast<double>(S.bins));
  const auto near_edge = [&](const V& s, double tol) {
    const V sb = s * bins;
    return abs(sb - nearbyint(sb)) <= V(tol * S.bins);
  };
  const V s = arc_s_for(S, h, count & !h.straight, straight_s(S, h), near_edge);
  return formula::density_bin(s, bins);
}

/// Books the lanes in `count` in f_c's bin `bin` of time cell `cell`: the thread's counts (Exchange::counts), or
/// the hits the caller adds up (a weighted run).
inline void book_density(const KernelScene& S, const Pack& g, const V& bin, const V& cell, const MV& count,
                         Exchange& x) {
  const V bins(static_cast<double>(S.bins));
  const unsigned in = bits(count);
  if (x.counts) {
    alignas(sizeof(B)) double index[N];
    store(fma(cell, bins, bin), index);  // exact: small integers
    if (in == kAllLanes) {               // the common case (a window covering most of the run): no mask walk
      for (int i = 0; i < N; ++i) ++x.counts[static_cast<std::uint32_t>(index[i])];
    } else {
      for_lanes(in, [&](int i) { ++x.counts[static_cast<std::uint32_t>(index[i])]; });
    }
    return;
  }
  alignas(sizeof(B)) double cells[N], bin_of[N];
  store(cell, cells), store(bin, bin_of);
  for_lanes(in, [&](int i) {
    x.hits[x.n_hits++] = {static_cast<std::uint32_t>(cells[i]), static_cast<std::uint32_t>(bin_of[i]), g.L.w[i]};
  });
}

inline void observe_density(const KernelScene& S, const Pack& g, const HitLanes& h, const V& t, const MV& count,
                            Exchange& x) {
  book_density(S, g, density_bin_of(S, h, count), time_cell(S, t), count, x);
}

/// The stadium's part of the step (lane_step): formula::next_exit's convex next hit, the filtered leak test
/// (in_stationary_leak, in_moving_leak), formula::reflect's pieces and the fast-forward's hand-off.
struct StadiumStep {
  const KernelScene& S;
  static constexpr bool can_lose = false, hands_off = true;
  HitLanes hit(const V& qx, const V& qy, const V& vx, const V& vy) const { return next_hit(S, qx, qy, vx, vy); }
  Taken leak(const HitLanes& h, const V& t, const MV& look) const {
    return {S.leak.by_s ? in_moving_leak(S, h, t, look) : in_stationary_leak(S, h, look), V(0.0)};
  }
  /// formula::reflect's pieces, every lane computing the arc's reflection
  void reflect(const HitLanes& h, const V& vx, const V& vy, Pack& g) const {
    const V wx = formula::from_centre(h.x, h.cx);
    const V k = formula::reflect_factor(wx, h.y, vx, vy);
    g.vx = select(h.straight, vx, formula::reflected(vx, k, wx));
    g.vy = select(h.straight, -vy, formula::reflected(vy, k, h.y));
  }
  void observe(const Pack& g, const HitLanes& h, const V& t, const MV& count, Exchange& x) const {
    observe_density(S, g, h, t, count, x);
  }
  /// a long run between the straight edges ahead: handed back to the fast-forward
  MV handoff(const HitLanes& h, const Pack& g, const MV& over, const MV& esc) const {
    if (S.handoff_bounces <= 0) return MV(false);
    return h.straight & !over & !esc &
           formula::straight_run_at_least(h.x, g.vx, g.vy, V(S.half_d), V(S.r), V(S.handoff_bounces));
  }
  /// Piece's numbering: 0 the top edge, 1 the right arc, 2 the bottom edge, 3 the left arc
  static V piece(const HitLanes& h) {
    return select(h.straight, select(h.up, V(0.0), V(2.0)), select(h.right, V(1.0), V(3.0)));
  }
};

}  // namespace

Pause run_kernel(const KernelScene& S, KernelState& state, Exchange& x) {
  return run_lanes(S, StadiumStep{S}, state, x);
}

ROTLEAK_KERNEL_FLATTEN double flights_kernel(const KernelScene& S, const Start* starts, std::uint64_t steps) {
  Lanes L{};
  for (int k = 0; k < N; ++k)
    L.qx[k] = starts[k].qx, L.qy[k] = starts[k].qy, L.vx[k] = starts[k].vx, L.vy[k] = starts[k].vy;
  V qx = load(L.qx), qy = load(L.qy), vx = load(L.vx), vy = load(L.vy), sum(0.0);
  for (std::uint64_t n = 0; n < steps; ++n) {
    const HitLanes h = next_hit(S, qx, qy, vx, vy);
    // step's reflection, the same four lines: formula::reflect (its choose of two lambdas) and a shared
    // helper each made GCC 12's code slower (docs/performance.md, "Why the kernel is written as it is")
    const V wx = formula::from_centre(h.x, h.cx);
    const V k = formula::reflect_factor(wx, h.y, vx, vy);
    vx = select(h.straight, vx, formula::reflected(vx, k, wx));
    vy = select(h.straight, -vy, formula::reflected(vy, k, h.y));
    qx = h.x, qy = h.y, sum = sum + h.t;
  }
  alignas(sizeof(B)) double out[N];
  store(sum, out);
  double total = 0;
  for (double x : out) total += x;
  return total;
}

int pack_size() { return N; }

void cell_kernel(const KernelScene& S, const double* t, double* out, std::size_t n) {
  alignas(sizeof(B)) double a[N], o[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) a[k] = k < m ? t[i + k] : 0;
    store(time_cell(S, load(a)), o);
    for (std::size_t k = 0; k < m; ++k) out[i + k] = o[k];
  }
}

void probe_kernel(const KernelScene& S, const Probe* points, ProbeResult* out, std::size_t n) {
  alignas(sizeof(B)) double piece[N], x[N], y[N], t[N], bin[N], leak[N];
  for (std::size_t i = 0; i < n; i += N) {
    const std::size_t m = n - i < N ? n - i : N;
    for (std::size_t k = 0; k < N; ++k) {
      const Probe p = k < m ? points[i + k] : Probe{0, 0, S.r, 0};
      piece[k] = p.piece, x[k] = p.x, y[k] = p.y, t[k] = p.t;
    }
    const V pc = load(piece);
    HitLanes h;
    h.straight = (pc == V(0.0)) | (pc == V(2.0));
    h.up = pc == V(0.0);
    h.right = pc == V(1.0);
    h.x = load(x), h.y = load(y), h.t = V(0.0), h.cx = select(h.right, V(S.half_d), V(-S.half_d));
    const MV all(true);
    store(density_bin_of(S, h, all), bin);
    const MV in = S.leak.by_s ? in_moving_leak(S, h, load(t), all) : in_stationary_leak(S, h, all);
    store(select(in, V(1.0), V(0.0)), leak);
    for (std::size_t k = 0; k < m; ++k) out[i + k] = {bin[k], leak[k] != 0};
  }
}

void rough_kernel(double r, double r_over_L, const double* ay, const double* ax, double* out, std::size_t n) {
  alignas(sizeof(B)) double a[W], b[W], o[W];
  const RoughArc c(r_over_L);
  for (std::size_t i = 0; i < n; i += W) {
    const std::size_t m = n - i < W ? n - i : W;
    for (std::size_t k = 0; k < W; ++k) a[k] = k < m ? ay[i + k] : 0, b[k] = k < m ? ax[i + k] : r;
    rough_arc_s(B::load_aligned(a), B::load_aligned(b), B(r), B(M_PI / 2 * r_over_L), B(0.0), c).store_aligned(o);
    for (std::size_t k = 0; k < m; ++k) out[i + k] = o[k];
  }
}
