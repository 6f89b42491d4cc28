// The vectorised kernel on any table (KernelScene::table: a TableModel<double> in plain numbers), included after
// sim/kernel/simd_kernel.ipp by each instruction set's translation unit: it shares the pack, the lanes' lifecycle
// and the f_c time cells with the stadium's step. Everything here has internal linkage but run_table_kernel.
//
// The physics is not written here either: each lane performs Table<double>'s and LeakList<double>'s operations in
// their order, through the templates they call themselves (geometry/table_piece.hpp: a piece's crossing, the
// reflection, s; leak/leak_window.hpp: the leak test; leak/leak_formulas.hpp: the phase, may_touch, in_leak)
// instantiated on the pack, with the piece's numbers broadcast. The next hit is Table::nearest's own loop over the
// pieces (nearest_crossing, geometry/table_piece.hpp: every piece's outward crossing, the nearest kept per lane), a
// first look and a second with the spans widened by the table's slack for the lanes that found none, as
// Table::next_hit. The leak test is LeakList::hit's own loop over the leaks (first_leak, leak/leak_window.hpp: the
// first leak that takes the hit; a stationary one by its windows, a moving one by the exact phase, may_touch and
// the hit's s). What is here is the step's order and s:
// - s (a moving leak, f_c): a segment's by formula::segment_piece_s, an arc's from formula::atan2_of, the core's
//   own function (the same bits), each lane's once a step;
// - the reflection: one formula about w, the arc's radius vector or the segment's rounded normal (Table::reflect).
// So a lane's trajectory, fate, time, collisions and leak are the scalar engine's bit for bit
// (tests/test_table_runs.cpp). What this path leaves out: the stadium's filtered fast paths (its convex next hit,
// the rough angle and phase), the fast-forward hand-off, weighted f_c (tables run uniform draws).

namespace {

/// Where the lanes next meet the table (geometry/table_piece.hpp): flight time, point, the reflection's w, the piece
/// (its index as a double; -1: none, a flight through a gap the rounding opened) and whether one was found.
using TableLanes = NearestCrossing<V>;

/// Table::next_hit for every lane: the first look, then the second (spans widened by the slack) for the lanes
/// that found no piece.
inline TableLanes table_next_hit(const KernelTable& T, const V& qx, const V& qy, const V& vx, const V& vy) {
  const V ZERO(0.0);
  TableLanes h{ZERO, ZERO, ZERO, ZERO, ZERO, V(-1.0), MV(false)};
  nearest_crossing(T.piece, T.pieces, qx, qy, vx, vy, 0.0, MV(true), h);
  if (const MV lost = !h.found; bits(lost)) nearest_crossing(T.piece, T.pieces, qx, qy, vx, vy, T.slack, lost, h);
  return h;
}

/// The lanes of `m` on piece k.
inline MV on_piece(const TableLanes& h, int k, const MV& m) { return m & (h.piece == V(static_cast<double>(k))); }

/// Table::s_of of the hits of the lanes in `need` (the others: 0): a segment's by its template, an arc's from the
/// double tier's atan2 (formula::atan2_scalar, the core's own function) of its template's arguments, lane by lane.
inline V table_s(const KernelTable& T, const TableLanes& h, const MV& need) {
  V s(0.0), ay(0.0), ax(1.0);
  MV arcs(false);
  for (int k = 0; k < T.pieces; ++k) {
    const MV on = on_piece(h, k, need);
    if (!bits(on)) continue;
    const TablePiece<double>& p = T.piece[k];
    if (p.kind == PieceKind::segment) {
      s = select(on, segment_point_s(p, h.x, h.y, T.inv_length[p.loop]), s);
      continue;
    }
    const Vec2<V> a = arc_angle_args(p, h.x, h.y);
    ax = select(on, a.x, ax), ay = select(on, a.y, ay);
    arcs = arcs | on;
  }
  if (!bits(arcs)) return s;
  alignas(sizeof(B)) double y[N], x[N], angle[N] = {};
  store(ay, y), store(ax, x);
  for_lanes(bits(arcs), [&](int i) { angle[i] = formula::atan2_scalar(y[i], x[i]); });
  const V a = load(angle);
  for (int k = 0; k < T.pieces; ++k) {
    const MV on = on_piece(h, k, arcs);
    if (T.piece[k].kind == PieceKind::arc && bits(on)) s = select(on, arc_point_s(T.piece[k], a, T.two_pi), s);
  }
  return s;
}

/// LeakList::hit for the lanes of `look`: first_leak (leak/leak_window.hpp), the index of the first leak that takes
/// the hit at time t (-1: none). The hit's s comes from table_s for the lanes a moving leak asks, each lane's once;
/// the exact error of the phase's product from a true fused multiply-subtract.
inline V table_leak_of(const KernelTable& T, const TableLanes& h, const V& t, const MV& look) {
  V s(0.0);
  MV have(false);
  const auto s_of = [&](const MV& ask, const V&, const V&) -> const V& {
    if (const MV more = ask & !have; bits(more)) s = select(more, table_s(T, h, more), s), have = have | more;
    return s;
  };
  return first_leak(T.leak, T.leaks, T.piece, h.piece, h.x, h.y, t, look, s_of, fms_error);
}

/// f_c of the lanes in `count`: bin floor(share bins) of the boundary's share (Table::boundary_share) of the hit,
/// booked in its time cell.
inline void observe_table_density(const KernelScene& S, const KernelTable& T, const Pack& g, const TableLanes& h,
                                  const V& t, const MV& count, Exchange& x) {
  V share = table_s(T, h, count);
  if (T.loops > 1) {
    V out(0.0);
    for (int l = 0; l < T.loops; ++l) {
      const MV on = count & (h.piece >= V(static_cast<double>(T.loop_first[l]))) &
                    (h.piece < V(static_cast<double>(T.loop_first[l] + T.loop_count[l])));
      if (bits(on))
        out = select(on, (V(T.loop_offset[l]) + share * V(T.loop_length[l])) / V(T.perimeter), out);
    }
    share = out;
  }
  book_density(S, g, formula::density_bin(share, V(static_cast<double>(S.bins))), time_cell(S, t), count, x);
}

/// Reports the lanes in `done` (Exchange::ends: their piece and leak; a lane whose flight met nothing or passed
/// t_max made no collision in this step) and refills them from its starts (or parks them).
void table_retire(const KernelScene& S, Pack& g, const TableLanes& h, const V& leak, const MV& done, const MV& esc,
                  const MV& stuck, const MV& over, const MV& lost, Exchange& x) {
  Lanes& L = g.L;
  unload(g);
  alignas(sizeof(B)) double piece[N], leaks[N];
  store(h.piece, piece), store(leak, leaks);
  const unsigned em = bits(esc), sm = bits(stuck), om = bits(over), none = bits(over | lost);
  for_lanes(bits(done) & g.live_mask, [&](int i) {
    End& e = x.ends[x.n_ends++];
    e.fate = ((om >> i) & 1)   ? LaneEnd::survived
             : ((em >> i) & 1) ? LaneEnd::escaped
             : ((sm >> i) & 1) ? LaneEnd::stuck
                               : LaneEnd::survived;
    e.t = L.t[i];
    e.weight = L.w[i];
    e.qx = L.qx[i], e.qy = L.qy[i], e.vx = L.vx[i], e.vy = L.vy[i];
    e.piece = static_cast<int>(piece[i]);
    e.leak = ((em >> i) & 1) ? static_cast<int>(leaks[i]) : 0;
    e.collisions = L.base[i] + g.steps - ((none >> i) & 1);
    e.id = L.id[i];
    take(S, g, i, x);
  });
  reload(g);
}

/// One collision of the lanes of g on the table, in advance()'s order (sim/model/particle.hpp): next hit (a lane
/// that finds no piece is stuck where it is), time check, f_c, leak test, reflection, zero-flight count.
/// KeepLast as step's: a lane past t_max reports its last collision's state.
template <bool KeepLast>
ROTLEAK_KERNEL_FLATTEN inline void table_step(const KernelScene& S, Pack& g, Exchange& x) {
  const KernelTable& T = *S.table;
  const V TMAX(S.t_max), ZERO(0.0), ONE(1.0);
  const V vx = g.vx, vy = g.vy;
  const TableLanes h = table_next_hit(T, g.qx, g.qy, vx, vy);
  const MV lost = !h.found;
  const V t = g.t + h.t;
  const MV over = (t > TMAX) & h.found, hit = h.found & !over;
  ++g.steps;
  if (S.density_windows > 0) {
    const MV count = (t >= V(S.win_span_from)) & (t <= V(S.win_span_to)) & hit;
    if (bits(count)) observe_table_density(S, T, g, h, t, count, x);
  }
  const V leak = table_leak_of(T, h, t, hit);
  const MV esc = hit & (leak >= ZERO);
  const Vec2<V> v = reflect_about(Vec2<V>{h.wx, h.wy}, Vec2<V>{vx, vy});  // Table::reflect's
  g.vx = v.x, g.vy = v.y;
  const MV moved = h.t > ZERO;
  MV stuck = lost;
  if (g.zeros || bits(moved) != kAllLanes) {
    const V zero = select(moved, ZERO, load(g.L.zero) + ONE);
    store(zero, g.L.zero);
    stuck = stuck | (zero > V(static_cast<double>(kMaxZeroFlights)));
    g.zeros = bits(zero != ZERO) != 0;
  }
  const MV done = over | esc | stuck;
  // where each lane now is: the hit, but a lost lane stays (the scalar core's stuck particle ends at its last t),
  // and with KeepLast a lane past t_max keeps its last collision's state
  const MV stay = KeepLast ? over | lost : lost;
  g.qx = select(stay, g.qx, h.x), g.qy = select(stay, g.qy, h.y), g.t = select(stay, g.t, t);
  if constexpr (KeepLast) g.vx = select(over, vx, g.vx), g.vy = select(over, vy, g.vy);
  if (bits(done) & g.live_mask) table_retire(S, g, h, leak, done, esc, stuck, over, lost, x);
}

}  // namespace

Pause run_table_kernel(const KernelScene& S, KernelState& state, Exchange& x) {
  Pack& g = pack_of(state);
  fill(S, g, x);
  Pause why = Pause::idle;
  if (S.keep_last) {
    while (g.live_mask && !pause(g, x, why)) table_step<true>(S, g, x);
  } else {
    while (g.live_mask && !pause(g, x, why)) table_step<false>(S, g, x);
  }
  if (!g.live_mask) return g.hungry ? Pause::starts : Pause::idle;
  return why;
}
