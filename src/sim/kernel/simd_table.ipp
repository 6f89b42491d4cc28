// The vectorised kernel on any table (KernelScene::table: a TableModel<double> in plain numbers), included after
// sim/kernel/simd_kernel.ipp by each instruction set's translation unit: the table's part (TableStep) of the
// collision step that sim/kernel/simd_lanes.ipp writes once (lane_step: the pack, the lanes' lifecycle, the step's
// order), with the f_c time cells of simd_kernel.ipp. Everything here has internal linkage but run_table_kernel.
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
//   own function (the same bits), an ellipse's by the core's ellipse_point_s lane by lane, each lane's once a step;
// - the reflection: one formula about w, the arc's radius vector or the segment's rounded normal (Table::reflect).
// So a lane's trajectory, fate, time, collisions and leak are the scalar engine's bit for bit
// (tests/test_table_runs.cpp). What this path leaves out: the stadium's filtered fast paths (its convex next hit,
// the rough angle and phase) and the fast-forward hand-off. f_c is weighted by the lanes' weights where the run is
// (a split run's members: book_density's hits).

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
    if (p.kind == PieceKind::ellipse) {  // the core's own function on each lane's double (the same bits)
      alignas(sizeof(B)) double x[N], y[N], out[N] = {};
      store(h.x, x), store(h.y, y);
      for_lanes(bits(on), [&](int i) { out[i] = ellipse_point_s(p, x[i], y[i], T.inv_length[p.loop]); });
      s = select(on, load(out), s);
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

/// The table's part of the step (lane_step, sim/kernel/simd_lanes.ipp): Table::next_hit (a flight may meet no piece:
/// lost), LeakList::hit, Table::reflect (one formula about w, the arc's radius vector or the segment's rounded
/// normal), f_c by the boundary's share; no hand-off (the fast-forward is the stadium's).
struct TableStep {
  const KernelScene& S;
  const KernelTable& T;
  static constexpr bool can_lose = true, hands_off = false;
  TableLanes hit(const V& qx, const V& qy, const V& vx, const V& vy) const { return table_next_hit(T, qx, qy, vx, vy); }
  static MV found(const TableLanes& h) { return h.found; }
  Taken leak(const TableLanes& h, const V& t, const MV& look) const {
    const V leak = table_leak_of(T, h, t, look);
    return {look & (leak >= V(0.0)), leak};
  }
  static void reflect(const TableLanes& h, const V& vx, const V& vy, Pack& g) {
    const Vec2<V> v = reflect_about(Vec2<V>{h.wx, h.wy}, Vec2<V>{vx, vy});  // Table::reflect's
    g.vx = v.x, g.vy = v.y;
  }
  void observe(const Pack& g, const TableLanes& h, const V& t, const MV& count, Exchange& x) const {
    observe_table_density(S, T, g, h, t, count, x);
  }
  static V piece(const TableLanes& h) { return h.piece; }
};

}  // namespace

Pause run_table_kernel(const KernelScene& S, KernelState& state, Exchange& x) {
  return run_lanes(S, TableStep{S, *S.table}, state, x);
}
