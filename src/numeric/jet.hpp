// A first-order jet: a value and its N partial derivatives, carried through the shared physics formulas
// (geometry/formulas.hpp) by forward-mode differentiation, after Ceres' Jet. Over an interval type V the
// jet of a box holds the function's values on the box and an enclosure of its Jacobian there, which is
// what a mean-value (Lohner) enclosure needs (verify/lohner.hpp). Comparisons compare values only, so a
// branch is the value type's: an interval type refuses an undecided one, and every point of the box
// takes the branch the jet took.
#pragma once

#include <array>
#include <cmath>
#include <type_traits>

#include "numeric/mpfi_ops.hpp"

namespace rotleak {

template <class V, int N>
struct Jet {
  V v{0};
  std::array<V, N> d{};

  Jet() {
    for (V& x : d) x = V(0);
  }
  Jet(int c) : v(c) {  // NOLINT: a constant of the formulas, T(0) or T(2)
    for (V& x : d) x = V(0);
  }
  explicit Jet(const V& value) : v(value) {
    for (V& x : d) x = V(0);
  }
  /// Variable i of N at `value`.
  static Jet variable(const V& value, int i) {
    Jet j(value);
    j.d[static_cast<std::size_t>(i)] = V(1);
    return j;
  }

  friend Jet operator+(const Jet& a, const Jet& b) {
    Jet r(a.v + b.v);
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
  }
  friend Jet operator-(const Jet& a, const Jet& b) {
    Jet r(a.v - b.v);
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
  }
  friend Jet operator-(const Jet& a) {
    Jet r(-a.v);
    for (std::size_t i = 0; i < N; ++i) r.d[i] = -a.d[i];
    return r;
  }
  friend Jet operator*(const Jet& a, const Jet& b) {
    Jet r(a.v * b.v);
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
  }
  /// (a / b)' = (a' - (a / b) b') / b
  friend Jet operator/(const Jet& a, const Jet& b) {
    Jet r(a.v / b.v);
    for (std::size_t i = 0; i < N; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) / b.v;
    return r;
  }
  friend Jet sqrt(const Jet& a) {
    using std::sqrt;
    Jet r(sqrt(a.v));
    const V twice = r.v + r.v;
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] / twice;
    return r;
  }
  /// |a|. Where an interval type cannot decide the sign (the box holds 0), the value is the interval's
  /// |a| and each derivative the hull of +-a' (|x| is Lipschitz with slopes in [-1, 1], which is what a
  /// mean-value enclosure needs); V then provides hull(x, y).
  friend Jet abs(const Jet& a) {
    if constexpr (std::is_floating_point_v<V>) {
      return a.v < V(0) ? -a : a;
    } else {
      try {
        return a.v < V(0) ? -a : a;
      } catch (const UncertainDecision&) {
        using std::abs;
        Jet r(abs(a.v));
        for (std::size_t i = 0; i < N; ++i) r.d[i] = hull(a.d[i], -a.d[i]);
        return r;
      }
    }
  }

  friend bool operator<(const Jet& a, const Jet& b) { return a.v < b.v; }
  friend bool operator<=(const Jet& a, const Jet& b) { return a.v <= b.v; }
  friend bool operator>(const Jet& a, const Jet& b) { return a.v > b.v; }
  friend bool operator>=(const Jet& a, const Jet& b) { return a.v >= b.v; }
  friend bool operator==(const Jet& a, const Jet& b) { return a.v == b.v; }
};

}  // namespace rotleak
