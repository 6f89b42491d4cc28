#pragma once

#include "numeric/device.hpp"

namespace rotleak {

template <class R>
struct Vec2 {
  R x{0}, y{0};
};

template <class R>
ROTLEAK_HD inline Vec2<R> operator+(const Vec2<R>& a, const Vec2<R>& b) {
  return {a.x + b.x, a.y + b.y};
}
template <class R>
ROTLEAK_HD inline Vec2<R> operator-(const Vec2<R>& a, const Vec2<R>& b) {
  return {a.x - b.x, a.y - b.y};
}
template <class R>
ROTLEAK_HD inline Vec2<R> operator*(const R& k, const Vec2<R>& a) {
  return {k * a.x, k * a.y};
}
template <class R>
ROTLEAK_HD inline R dot(const Vec2<R>& a, const Vec2<R>& b) {
  return a.x * b.x + a.y * b.y;
}
/// z-component of a x b: positive when b lies counter-clockwise of a.
template <class R>
ROTLEAK_HD inline R cross(const Vec2<R>& a, const Vec2<R>& b) {
  return a.x * b.y - a.y * b.x;
}

}  // namespace rotleak
