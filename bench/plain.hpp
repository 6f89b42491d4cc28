// The plain scalar simulator: what one writes first, independent of the core (unit velocity
// renormalised after each arc reflection, a branch per piece, the leak decided from s, which on the
// arcs needs an atan2 at every collision, f_c binned from the same s). The baseline the engine's
// speed is measured against (bench_speed, bench_scale), and on a GPU, compiled for the device as it is
// (one thread a particle: bench_gpu), the GPU engine's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "numeric/device.hpp"

namespace rotleak::bench {

/// Stadium d = 2, r = 1, leak width `width` centred at frac(start + omega t). `density`: when not
/// null, collisions with t in window w counted in bins w * bins + floor(s bins).
struct PlainScene {
  static constexpr int kMaxWindows = 8;
  struct Window {
    double first, second;  ///< the window [first, second]
  };
  double omega = 0, start = 0, width = 0.01, t_max = 20000;
  std::uint64_t* density = nullptr;
  int bins = 0;
  Window windows[kMaxWindows] = {};
  int n_windows = 0;
  void add_window(double from, double to) { windows[n_windows++] = {from, to}; }
};

/// Collisions of one particle until it escapes or passes t_max.
ROTLEAK_HD inline std::uint64_t plain_particle(double qx, double qy, double vx, double vy, double t, const PlainScene& p) {
  const double hd = 1, r = 1, L = 4 + 2 * M_PI, half = p.width / 2;
  std::uint64_t n = 0;
  for (;;) {
    double th = 0, hx = 0, hy = 0, cx = 0;
    bool straight = false;
    if (vy != 0) {
      const double ey = vy > 0 ? r : -r;
      th = (ey - qy) / vy;
      hx = qx + vx * th;
      hy = ey;
      straight = std::abs(hx) <= hd;
      cx = hx > 0 ? hd : -hd;
    } else {
      cx = vx > 0 ? hd : -hd;
    }
    if (!straight) {
      const double dx = qx - cx, b = dx * vx + qy * vy, c = dx * dx + qy * qy - r * r;
      th = -b + std::sqrt(std::max(b * b - c, 0.0));
      hx = qx + th * vx;
      hy = qy + th * vy;
    }
    t += th;
    if (t > p.t_max) return n;
    ++n;
    double s;
    if (straight)
      s = hy > 0 ? (hx >= 0 ? hx / L : 1 + hx / L) : (hd + M_PI * r + (hd - hx)) / L;
    else if (cx > 0)
      s = (hd + r * std::atan2(hx - hd, hy)) / L;
    else
      s = (3 * hd + M_PI * r + r * std::atan2(-(hx + hd), -hy)) / L;
    if (p.density)
      for (int w = 0; w < p.n_windows; ++w)
        if (t >= p.windows[w].first && t <= p.windows[w].second) {
          std::uint64_t* count = p.density + static_cast<std::size_t>(w) * static_cast<std::size_t>(p.bins) +
                                 static_cast<std::size_t>(std::min(p.bins - 1, static_cast<int>(s * p.bins)));
#ifdef __CUDA_ARCH__
          atomicAdd(reinterpret_cast<unsigned long long*>(count), 1ULL);
#else
          ++*count;
#endif
        }
    double off = s - (p.start + p.omega * t);
    off -= std::floor(off + 0.5);
    if (std::abs(off) <= half) return n;
    if (straight) {
      vy = -vy;
    } else {
      const double nx = hx - cx, ny = hy, k = 2 * (vx * nx + vy * ny);
      vx -= k * nx;
      vy -= k * ny;
      const double len = std::sqrt(vx * vx + vy * vy);
      vx /= len;
      vy /= len;
    }
    qx = hx;
    qy = hy;
  }
}

}  // namespace rotleak::bench
