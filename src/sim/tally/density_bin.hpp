// A collision's f_c bin, once for every engine that counts f_c: the CPU's observers (sim/tally/density.hpp) and
// the GPU engine's (sim/gpu/gpu_engine.cu). On the stadium the bin of its s; on any table the bin of the hit's
// share of the whole boundary (Table::boundary_share: the loops laid end to end), `bins` equal bins of [0, 1).
#pragma once

#include "geometry/stadium.hpp"
#include "geometry/table.hpp"
#include "numeric/device.hpp"
#include "numeric/num_traits.hpp"

namespace rotleak {

/// The bin of s in [0, 1) among `bins` (formula::density_bin, in double).
ROTLEAK_HD inline int density_bin_of(double s, int bins) {
  return static_cast<int>(formula::density_bin(s, static_cast<double>(bins)));
}

/// The bin of a hit at q on the stadium's piece p.
template <class R>
ROTLEAK_HD int density_bin_of(const Stadium<R>& st, Piece p, const Vec2<R>& q, int bins) {
  return density_bin_of(num_traits<R>::to_double(st.s_of(p, q)), bins);
}

/// The bin of a hit at q on the table's piece k.
template <class R>
ROTLEAK_HD int density_bin_of(const Table<R>& table, int k, const Vec2<R>& q, int bins) {
  const R share = table.boundary_share(table.piece(k).loop, table.s_of(k, q));
  return density_bin_of(num_traits<R>::to_double(share), bins);
}

}  // namespace rotleak
