// Initial conditions from (seed, id) alone: Philox4x64-10, counter = (id, draw, 0, 0), key = (seed, stream).
// The draws are binary doubles; every tier converts those same bits exactly, so a shadow run at any
// precision starts from the identical point.
#pragma once

#include <Random123/philox.h>

#include <cstdint>
#include <memory>

#include "geometry/stadium.hpp"
#include "geometry/table.hpp"
#include "numeric/device.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// The binary initial data of one particle.
struct InitialDraw {
  double s = 0, p = 0;         ///< Birkhoff start (init = birkhoff)
  double x = 0, y = 0, u = 0;  ///< flow start: position and direction angle 2*pi*u (init = flow)
  double tau = 0;              ///< creation time
  bool flow = false;
  /// Low parts of a double-double Birkhoff start (s + s_lo, p + p_lo, tau + tau_lo), for a tier wider than double
  /// (splitting over initial conditions moves starts below a double's ulp); 0 for every double start. Last, so that
  /// the draws written field by field stay as they were.
  double s_lo = 0, p_lo = 0, tau_lo = 0;
};

class InitialConditions {
 public:
  static constexpr std::uint64_t kStreamInitial = 0;

  InitialConditions(std::uint64_t seed, InitKind kind, double creation_window, double half_d, double r)
      : seed_(seed), kind_(kind), window_(creation_window), half_d_(half_d), r_(r) {}
  /// On any table: flow starts drawn in the outer loop's box and kept when inside the table (Table::contains).
  InitialConditions(std::uint64_t seed, InitKind kind, double creation_window,
                    std::shared_ptr<const Table<double>> table)
      : seed_(seed), kind_(kind), window_(creation_window), half_d_(0), r_(0), table_(std::move(table)) {}

  std::uint64_t seed() const { return seed_; }
  InitKind kind() const { return kind_; }
  double creation_window() const { return window_; }

  /// Uniform double in [0,1) from the top 53 bits.
  ROTLEAK_HD static double unit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1p-53; }
  /// Uniform in the open interval (-1, 1), symmetric and exact: (2m + 1 - 2^53) / 2^53.
  ROTLEAK_HD static double symmetric(std::uint64_t bits) {
    const std::int64_t m = static_cast<std::int64_t>(bits >> 11);
    return static_cast<double>(2 * m + 1 - (std::int64_t(1) << 53)) * 0x1p-53;
  }

  /// Particle id's Birkhoff start (init = birkhoff: one try, counter word 1 = 0) under seed and creation window:
  /// what draw() returns for it, and what the GPU engine draws on the device.
  ROTLEAK_HD static InitialDraw birkhoff_draw(std::uint64_t seed, double window, std::uint64_t id) {
    r123::Philox4x64 gen;
    const r123::Philox4x64::key_type key = {{seed, kStreamInitial}};
    const r123::Philox4x64::ctr_type ctr = {{id, 0, 0, 0}};
    const auto w = gen(ctr, key);
    InitialDraw out;
    out.tau = window * unit(w[3]);
    out.s = unit(w[0]);
    out.p = symmetric(w[1]);
    return out;
  }

  InitialDraw draw(std::uint64_t id) const {
    if (kind_ == InitKind::birkhoff) return birkhoff_draw(seed_, window_, id);
    r123::Philox4x64 gen;
    r123::Philox4x64::key_type key = {{seed_, kStreamInitial}};
    InitialDraw out;
    for (std::uint64_t k = 0;; ++k) {
      r123::Philox4x64::ctr_type ctr = {{id, k, 0, 0}};
      const auto w = gen(ctr, key);
      out.tau = window_ * unit(w[3]);
      // Flow: rejection from the bounding box; each try uses the next counter.
      out.flow = true;
      out.u = unit(w[2]);
      if (table_) {
        const Vec2<double> lo = table_->box_lo(), hi = table_->box_hi();
        out.x = lo.x + (hi.x - lo.x) * unit(w[0]);
        out.y = lo.y + (hi.y - lo.y) * unit(w[1]);
        if (table_->contains({out.x, out.y})) return out;
        continue;
      }
      out.x = (half_d_ + r_) * (2 * unit(w[0]) - 1);
      out.y = r_ * (2 * unit(w[1]) - 1);
      const double ax = out.x < 0 ? -out.x : out.x;
      if (ax <= half_d_ || (ax - half_d_) * (ax - half_d_) + out.y * out.y < r_ * r_) return out;
    }
  }

 private:
  std::uint64_t seed_;
  InitKind kind_;
  double window_, half_d_, r_;
  std::shared_ptr<const Table<double>> table_;  ///< any table's flow starts (null: the stadium's)
};

/// The scene's initial conditions (its seed, kind, creation window and stadium size, or its table).
inline InitialConditions initial_conditions(const Scene& scene) {
  if (scene.table)
    return InitialConditions(scene.seed, scene.init, scene.creation_window,
                             std::make_shared<const Table<double>>(table_spec(scene)));
  return InitialConditions(scene.seed, scene.init, scene.creation_window,
                           round_exact<double>(scene.d / ExactReal::parse("2")), round_exact<double>(scene.r));
}

/// Position, unit velocity and time of a particle at creation, in tier R.
template <class R>
struct ParticleState {
  Vec2<R> q, v;
  R t{0};
};

/// The same on any table: a Birkhoff start's s is a share of the whole boundary (Table::loop_s), its p taken about
/// that point's inward normal; a flow start's direction is the angle 2 pi u.
/// A start coordinate in tier R: hi, plus its low part where it has one (a double start's bits unchanged).
template <class R>
ROTLEAK_HD R start_coordinate(double hi, double lo) {
  R x = R(hi);
  if (lo != 0) x += R(lo);
  return x;
}

template <class R>
ROTLEAK_HD ParticleState<R> initial_state(const Table<R>& table, const InitialDraw& dr) {
  ParticleState<R> ps;
  ps.t = start_coordinate<R>(dr.tau, dr.tau_lo);
  if (!dr.flow) {
    const auto [loop, s] = table.loop_s(start_coordinate<R>(dr.s, dr.s_lo));
    const TableFrame<R> f = table.at(loop, s);
    ps.q = f.q;
    ps.v = table.velocity(f, start_coordinate<R>(dr.p, dr.p_lo));
  } else {
    const auto sc = formula::tier_sin_cos(formula::flow_angle(table.pi(), R(dr.u)));
    ps.q = {R(dr.x), R(dr.y)};
    ps.v = {sc.cos, sc.sin};
  }
  return ps;
}

template <class R>
ROTLEAK_HD ParticleState<R> initial_state(const Stadium<R>& st, const InitialDraw& dr) {
  ParticleState<R> ps;
  ps.t = start_coordinate<R>(dr.tau, dr.tau_lo);
  if (!dr.flow) {
    const BoundaryPoint<R> b = st.at(start_coordinate<R>(dr.s, dr.s_lo));
    ps.q = b.q;
    ps.v = st.velocity(b, start_coordinate<R>(dr.p, dr.p_lo));
  } else {
    const auto sc = Stadium<R>::sin_cos(formula::flow_angle(st.pi(), R(dr.u)));
    ps.q = {R(dr.x), R(dr.y)};
    ps.v = {sc.cos, sc.sin};
  }
  return ps;
}

}  // namespace rotleak
