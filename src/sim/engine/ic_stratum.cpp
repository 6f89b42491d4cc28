// The starts splitting over initial conditions draws and moves (sim/engine/ic_splitting.hpp): the stratum, its
// packed coordinates in double and in double-double, the symmetric proposal, and the scenes' escape clocks in
// double, dd and float128.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "geometry/stadium.hpp"
#include "numeric/tiers.hpp"
#include "sim/engine/ic_splitting.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

namespace {

double total(const std::vector<std::pair<double, double>>& v) {
  double sum = 0;
  for (const auto& [lo, hi] : v) sum += hi - lo;
  return sum;
}

/// A point's place in a union of intervals laid end to end, and back.
double packed(const std::vector<std::pair<double, double>>& v, double x) {
  double before = 0;
  for (const auto& [lo, hi] : v) {
    if (x < hi) return before + (x - lo);
    before += hi - lo;
  }
  return before;
}
double unpacked(const std::vector<std::pair<double, double>>& v, double a) {
  for (const auto& [lo, hi] : v) {
    if (a < hi - lo) return lo + a;
    a -= hi - lo;
  }
  return v.back().second;  // past the end (rounding): outside, refused
}

bool inside(const std::vector<std::pair<double, double>>& v, double x) {
  for (const auto& [lo, hi] : v)
    if (x >= lo && x < hi) return true;
  return false;
}

// The same for a double-double hi + lo, in dd arithmetic: the lengths hi - lo of two doubles are exact in dd, so
// packing and unpacking are translations to 2^-106, and a step below a double's ulp moves the start.
dd_real dd_of(double hi, double lo) { return dd_real(hi) + lo; }
bool inside(const std::vector<std::pair<double, double>>& v, double hi, double lo) {
  if (lo == 0) return inside(v, hi);
  const dd_real x = dd_of(hi, lo);
  for (const auto& [a, b] : v)
    if (x >= dd_real(a) && x < dd_real(b)) return true;
  return false;
}
dd_real total_dd(const std::vector<std::pair<double, double>>& v) {
  dd_real sum = 0.0;
  for (const auto& [lo, hi] : v) sum += dd_real(hi) - lo;
  return sum;
}
dd_real packed_dd(const std::vector<std::pair<double, double>>& v, double hi, double lo) {
  dd_real before = 0.0;
  const dd_real x = dd_of(hi, lo);
  for (const auto& [a, b] : v) {
    if (x < dd_real(b)) return before + (x - a);
    before += dd_real(b) - a;
  }
  return before;
}
/// Back from packed coordinates into hi, lo; false past the end (rounding: outside, refused).
bool unpacked_dd(const std::vector<std::pair<double, double>>& v, dd_real a, double& hi, double& lo) {
  for (const auto& [x, y] : v) {
    const dd_real len = dd_real(y) - x;
    if (a < len) {
      const dd_real u = a + x;
      hi = u.x[0], lo = u.x[1];
      return true;
    }
    a -= len;
  }
  return false;
}

}  // namespace

double IcStratum::s_length() const { return total(s); }
double IcStratum::p_length() const { return total(p); }
double IcStratum::s_packed(double x) const { return packed(s, x); }
double IcStratum::p_packed(double x) const { return packed(p, x); }

bool IcStratum::contains(const IcPoint& x) const {
  if (!inside(s, x.s, x.s_lo) || !inside(p, x.p, x.p_lo)) return false;
  if (tau_lo == tau_hi) return x.tau == tau_lo && x.tau_lo == 0;
  return inside({{tau_lo, tau_hi}}, x.tau, x.tau_lo);
}

double IcStratum::share() const { return total(s) * total(p) / 2; }

IcPoint IcStratum::at(double us, double up, double ut) const {
  return {unpacked(s, us * total(s)), unpacked(p, up * total(p)), tau_lo + (tau_hi - tau_lo) * ut};
}

IcStratum ic_stratum(const Scene& scene, double p_lo, double p_hi, bool edges) {
  if (!(p_lo >= 0 && p_lo < p_hi && p_hi <= 1)) throw std::invalid_argument("ic_stratum: needs 0 <= p_lo < p_hi <= 1");
  IcStratum st;
  if (edges) {
    if (scene.on_table()) throw std::invalid_argument("ic_stratum: the straight edges are the stadium's");
    const Stadium<double> sd(scene.d, scene.r);
    st.s = {{0.0, sd.junction(0)}, {sd.junction(1), sd.junction(2)}, {sd.junction(3), 1.0}};
  } else {
    st.s = {{0.0, 1.0}};
  }
  if (p_lo == 0)
    st.p = {{-p_hi, p_hi}};
  else
    st.p = {{-p_hi, -p_lo}, {p_lo, p_hi}};
  st.tau_lo = 0, st.tau_hi = scene.creation_window;
  // moves along the leak only where a rotation and a delay are a symmetry (the circle): on the stadium at 100/101
  // they spent two proposals in three for nothing, doubling the errors past t = 5000 (docs/model.md)
  const bool circle = scene.table && scene.table->kind == "circle" && leak_count(scene) == 1;
  if (circle) st.drift = (scene.leaks.empty() ? scene.omega : scene.leaks.front().omega.value).to_double();
  return st;
}

namespace {

/// The clock of one model (the stadium's Model or any table's TableModel), shared by every thread that calls it.
template <class M>
EscapeClock model_clock(std::shared_ptr<const M> m) {
  return [m](const IcPoint& x) {
    InitialDraw d;
    d.s = x.s, d.p = x.p, d.tau = x.tau;
    // a double clock runs the double start hi; a wider one the whole of hi + lo
    if constexpr (!std::is_same_v<typename M::real_type, double>) d.s_lo = x.s_lo, d.p_lo = x.p_lo, d.tau_lo = x.tau_lo;
    NoCollisionObserver<typename M::real_type> none;
    const ParticleEnd e = run_particle(*m, initial_state(*m, d), none);
    IcEnd out;
    out.collisions = e.collisions;
    if (e.fate != Fate::survived) out.t = e.t, out.stuck = e.fate == Fate::stuck;
    return out;
  };
}

}  // namespace

namespace {

template <class R>
EscapeClock tier_clock(const Scene& scene) {
  if (scene.on_table())
    return model_clock(std::make_shared<const TableModel<R>>(table_spec(scene), leak_specs(scene), scene.t_max));
  return model_clock(std::make_shared<const Model<R>>(Model<R>::from(scene)));
}

}  // namespace

EscapeClock scene_clock(const Scene& scene, TierKind tier) {
  switch (tier) {
    case TierKind::double_:
      return tier_clock<double>(scene);
    case TierKind::dd:
      return tier_clock<dd_real>(scene);
    case TierKind::float128:
      return tier_clock<float128>(scene);
    default:
      throw std::invalid_argument("scene_clock: a double, dd or float128 clock");
  }
}

int ic_tier_bits(TierKind tier) {
  switch (tier) {
    case TierKind::dd:
      return 106;
    case TierKind::float128:
      return 113;
    default:
      return 53;
  }
}

IcPoint symmetric_proposal(const IcStratum& stratum, const IcScales& scales, const IcPoint& x, const double* u) {
  // One halving j for the three coordinates, the step uniform in [-extent 2^-j, extent 2^-j), taken in the
  // coordinates that lay the stratum's intervals end to end (a translation on each: the uniform law's density
  // stays 1, so a symmetric step there is symmetric for it); s wraps round, p and tau do not. In dd: the steps reach
  // below a double's ulp.
  // Along the leak (kind 1, 2): s steps by its own step in s - drift tau plus or minus drift times tau's step, a
  // translation of (s, tau) by a symmetric vector, so still symmetric.
  const IcMove m = ic_move(stratum, scales, u[0]);
  const int j = m.halving;
  const auto step = [j](double extent, double v) { return std::ldexp(extent, -j) * (2 * v - 1); };
  const bool spread = stratum.tau_hi > stratum.tau_lo;
  const double dtau = spread ? step(scales.tau, u[3]) : 0;
  const dd_real ls = total_dd(stratum.s);
  dd_real a = packed_dd(stratum.s, x.s, x.s_lo);
  if (m.kind == 0)
    a += step(scales.s, u[1]);
  else
    a += dd_real(step(scales.u, u[1])) + dd_real(stratum.drift) * dtau * (m.kind == 1 ? 1.0 : -1.0);
  a -= ls * floor(a / ls);
  const dd_real b = packed_dd(stratum.p, x.p, x.p_lo) + step(scales.p, u[2]);
  IcPoint y = x;
  if (!unpacked_dd(stratum.s, a, y.s, y.s_lo)) y.s = stratum.s.front().first, y.s_lo = 0;
  if (b < 0.0 || !unpacked_dd(stratum.p, b, y.p, y.p_lo)) y.p = 2.0, y.p_lo = 0;  // 2: outside every stratum, refused
  if (spread) {
    const dd_real t = dd_of(x.tau, x.tau_lo) + dtau;
    y.tau = t.x[0], y.tau_lo = t.x[1];
  }
  return y;
}

namespace {

/// Whether the stratum's proposals move along the leak: it turns, and tau spreads.
bool moves_along(const IcStratum& st) { return st.drift != 0 && st.tau_hi > st.tau_lo; }

}  // namespace

IcMove ic_move(const IcStratum& stratum, const IcScales& scales, double u0) {
  if (!moves_along(stratum)) return {0, scales.halving(u0)};
  const int kind = std::min(2, static_cast<int>(3 * u0));
  return {kind, scales.halving(3 * u0 - kind)};
}

int IcScales::halving(double u0) const {
  return lo + std::min(halvings - lo, static_cast<int>(u0 * (halvings - lo + 1)));
}

double IcScales::step(double extent) const { return std::ldexp(extent, -(lo + halvings) / 2); }

bool IcScales::holds(const IcStratum& st, int bits, int margin) const {
  // 2^margin ulps, in a tier of `bits`, of the largest magnitude in each coordinate
  const auto ulps = [&](double extent, double big) {
    return extent == 0 || big == 0 || extent >= std::ldexp(1.0, std::ilogb(big) - bits + 1 + margin);
  };
  const double s_big = st.s.back().second, p_big = std::max(std::abs(st.p.front().first), std::abs(st.p.back().second));
  return ulps(step(s), s_big) && ulps(step(p), p_big) && ulps(st.tau_hi > st.tau_lo ? step(tau) : 0, st.tau_hi) &&
         (!moves_along(st) || ulps(step(u), s_big));
}

}  // namespace rotleak
