// The vectorised kernel's lanes, written once for every table: the pack of N particles and its lifecycle (refill,
// retire), and the collision step (lane_step) that the stadium's part (StadiumStep, sim/kernel/simd_kernel.ipp) and
// any table's (TableStep, sim/kernel/simd_table.ipp) fill in. Included, inside the instruction set's namespace, by
// simd_engine.cpp and simd_avx512.cpp after sim/kernel/simd_pack.ipp (V, MV, select, for_lanes) and before the
// tables' parts; everything here has internal linkage.

namespace {

struct Lanes {
  alignas(sizeof(B)) double qx[N], qy[N], vx[N], vy[N], t[N], zero[N], w[N];
  std::uint64_t id[N];
  /// a lane's collisions are counted by the pack's steps (each step is one collision of every lane, but
  /// the flight past t_max that ends it): base = its start's collisions - the pack's steps when it came
  std::uint64_t base[N];
};

/// N particles in registers, with their bookkeeping in memory for the rare lane changes.
struct Pack {
  Lanes L{};
  V qx, qy, vx, vy, t;
  unsigned live_mask = 0;   ///< bit k: lane k holds a particle (parked lanes sit past t_max and must not retire)
  std::uint64_t steps = 0;  ///< steps taken (Lanes::base)
  bool zeros = false;       ///< some lane's count of zero-length flights in a row (Lanes::zero) is not 0
  bool hungry = false;      ///< a lane found no start, and more will come (Pause::starts)
};
static_assert(N <= kMaxPackLanes && sizeof(Pack) <= sizeof(KernelState::pack) && alignof(Pack) <= 64);

/// The pack a state holds: made on its first call (every lane idle), the same object on every later one.
Pack& pack_of(KernelState& state) {
  if (!state.started) {
    new (state.pack) Pack{};
    state.started = true;
  }
  return *std::launder(reinterpret_cast<Pack*>(state.pack));
}

void park(const KernelScene& S, Lanes& L, int k) {
  // an idle lane: parked far past t_max, never reported (its bit of live_mask is clear)
  L.qx[k] = 0, L.qy[k] = 0, L.vx[k] = 0, L.vy[k] = -1, L.t[k] = 2 * S.t_max + 1;
  L.w[k] = 0;
}

void reload(Pack& g) {
  g.qx = load(g.L.qx), g.qy = load(g.L.qy), g.vx = load(g.L.vx), g.vy = load(g.L.vy), g.t = load(g.L.t);
}

/// Lane k takes the next start, or is parked when there is none (its bit of live_mask follows; Pack::hungry when
/// more will come).
void take(const KernelScene& S, Pack& g, int k, Exchange& x) {
  Lanes& L = g.L;
  L.zero[k] = 0;
  if (x.taken == x.n_starts) {
    park(S, L, k);
    g.live_mask &= ~(1u << k);
    g.hungry = g.hungry || !x.last;
    return;
  }
  const Start& st = x.starts[x.taken++];
  L.id[k] = st.id;
  g.live_mask |= 1u << k;
  L.qx[k] = st.qx, L.qy[k] = st.qy, L.vx[k] = st.vx, L.vy[k] = st.vy, L.t[k] = st.t;
  L.base[k] = st.collisions - g.steps;
  L.w[k] = st.weight;
}

/// The lanes' registers into their memory (before lanes change).
[[gnu::always_inline]] inline void unload(Pack& g) {
  store(g.qx, g.L.qx), store(g.qy, g.L.qy), store(g.vx, g.L.vx), store(g.vy, g.L.vy), store(g.t, g.L.t);
}

/// A call's start: every idle lane takes a start (or stays parked).
[[gnu::always_inline]] inline void fill(const KernelScene& S, Pack& g, Exchange& x) {
  g.hungry = false;
  unload(g);
  for (int k = 0; k < N; ++k)
    if (!((g.live_mask >> k) & 1)) take(S, g, k, x);
  reload(g);
}


/// Reports the lanes in `done` (Exchange::ends) and refills them from its starts (or parks them), for every table:
/// each lane's piece and (an escaped lane's) leak index; `none`: the lanes whose flight made no collision in this
/// step (past t_max, or no piece met); `handoff`: the lanes handed back to the fast-forward.
void retire(const KernelScene& S, Pack& g, const V& piece, const V& leak, const MV& done, const MV& esc,
            const MV& stuck, const MV& over, const MV& none, const MV& handoff, Exchange& x) {
  Lanes& L = g.L;
  unload(g);
  alignas(sizeof(B)) double pieces[N], leaks[N];
  store(piece, pieces), store(leak, leaks);
  const unsigned em = bits(esc), sm = bits(stuck), om = bits(over), nm = bits(none), hm = bits(handoff);
  for_lanes(bits(done) & g.live_mask, [&](int i) {
    End& e = x.ends[x.n_ends++];
    e.fate = ((om >> i) & 1)   ? LaneEnd::survived
             : ((em >> i) & 1) ? LaneEnd::escaped
             : ((sm >> i) & 1) ? LaneEnd::stuck
             : ((hm >> i) & 1) ? LaneEnd::handed_back
                               : LaneEnd::survived;
    e.t = L.t[i];
    e.weight = L.w[i];
    e.qx = L.qx[i], e.qy = L.qy[i], e.vx = L.vx[i], e.vy = L.vy[i];
    e.piece = static_cast<int>(pieces[i]);
    e.leak = ((em >> i) & 1) ? static_cast<int>(leaks[i]) : 0;
    e.collisions = L.base[i] + g.steps - ((nm >> i) & 1);
    e.id = L.id[i];
    take(S, g, i, x);
  });
  reload(g);
}

/// Whether the pack may take another step in this call: a lane that wants a start, or buffers that might not hold
/// a step's ends and counted collisions, send it back to the caller (the Pause).
inline bool pause(const Pack& g, const Exchange& x, Pause& why) {
  if (g.hungry) return why = Pause::starts, true;
  if (x.n_ends + N > x.end_capacity) return why = Pause::ends, true;
  if (x.hits && x.n_hits + N > x.hit_capacity) return why = Pause::hits, true;
  return false;
}

/// Which leak took each lane's hit (Geo::leak): the escaped lanes and, on a table with a list, the leak's index.
struct Taken {
  MV esc;
  V leak;
};

/// One collision for the lanes of g, written once for every table, in the scalar core's order (sim/model/particle.hpp:
/// fly, the leak test, bounce): next hit, lost (no piece met: the lane stays where it is and is stuck), time check,
/// f_c, leak test, reflection, zero-flight count; lanes that end are reported and refilled (retire). The table's part
/// is Geo (StadiumStep below: the stadium's convex next hit, its filtered leak test and the fast-forward's hand-off;
/// TableStep, sim/kernel/simd_table.ipp: any table): hit, leak, reflect, observe (f_c), piece (a lane's piece index),
/// and for a table where a flight can meet nothing (Geo::can_lose) found; with Geo::hands_off, handoff.
/// KeepLast (KernelScene::keep_last, a split run's epochs): a lane past t_max reports the state of its last
/// collision before it. A separate instantiation (the branch cost time where no lane took it); flattened.
template <bool KeepLast, class Geo>
ROTLEAK_KERNEL_FLATTEN inline void lane_step(const KernelScene& S, const Geo& geo, Pack& g, Exchange& x) {
  const V TMAX(S.t_max), ZERO(0.0), ONE(1.0);
  const V vx = g.vx, vy = g.vy;
  const auto h = geo.hit(g.qx, g.qy, vx, vy);
  const V t = g.t + h.t;
  MV over = t > TMAX, lost(false), hit;
  if constexpr (Geo::can_lose) {
    const MV found = geo.found(h);
    lost = !found, over = over & found, hit = found & !over;
  } else {
    hit = !over;
  }
  ++g.steps;                    // a collision of every lane (a flight past t_max is not one: Lanes::base)
  if (S.density_windows > 0) {  // parked lanes sit past t_max: `hit` excludes them
    // within the windows' span [first from, last to]; a time in a gap between windows has a cell
    // that no window holds, so it is counted nowhere
    const MV count = (t >= V(S.win_span_from)) & (t <= V(S.win_span_to)) & hit;
    if (bits(count)) geo.observe(g, h, t, count, x);
  }
  const Taken taken = geo.leak(h, t, hit);
  geo.reflect(h, vx, vy, g);
  // zero-length flights in a row (a lane that makes too many is stuck): counted in memory, and only in
  // a step that has one or follows one (nearly never)
  const MV moved = h.t > ZERO;
  MV stuck = lost;
  if (g.zeros || bits(moved) != kAllLanes) {
    const V zero = select(moved, ZERO, load(g.L.zero) + ONE);
    store(zero, g.L.zero);
    const MV many = zero > V(static_cast<double>(kMaxZeroFlights));
    if constexpr (Geo::can_lose) stuck = stuck | many;
    else stuck = many;
    g.zeros = bits(zero != ZERO) != 0;
  }
  if constexpr (!KeepLast && !Geo::can_lose) g.qx = h.x, g.qy = h.y, g.t = t;
  MV done = over | taken.esc | stuck, handoff(false);
  if constexpr (Geo::hands_off) handoff = geo.handoff(h, g, over, taken.esc), done = done | handoff;
  const bool any = (bits(done) & g.live_mask) != 0;
  // where each lane now is: the hit, but a lost lane stays (the scalar core's stuck particle ends at its last t),
  // and with KeepLast a lane past t_max keeps its last collision's state (where a split run goes on)
  const auto place = [&](const MV& stay) {
    g.qx = select(stay, g.qx, h.x), g.qy = select(stay, g.qy, h.y), g.t = select(stay, g.t, t);
    if constexpr (KeepLast) g.vx = select(over, vx, g.vx), g.vy = select(over, vy, g.vy);
  };
  if constexpr (Geo::can_lose) {
    place(KeepLast ? over | lost : lost);
  } else if constexpr (KeepLast) {
    if (any) place(over);
    else g.qx = h.x, g.qy = h.y, g.t = t;
  }
  if (any) retire(S, g, geo.piece(h), taken.leak, done, taken.esc, stuck, over, over | lost, handoff, x);
}

/// The pack's calls of lane_step with the table's part Geo, until the lanes are done or the exchange must be served.
template <class Geo>
inline Pause run_lanes(const KernelScene& S, const Geo& geo, KernelState& state, Exchange& x) {
  Pack& g = pack_of(state);
  fill(S, g, x);
  Pause why = Pause::idle;
  if (S.keep_last) {
    while (g.live_mask && !pause(g, x, why)) lane_step<true>(S, geo, g, x);
  } else {
    while (g.live_mask && !pause(g, x, why)) lane_step<false>(S, geo, g, x);
  }
  if (!g.live_mask) return g.hungry ? Pause::starts : Pause::idle;
  return why;
}

}  // namespace
