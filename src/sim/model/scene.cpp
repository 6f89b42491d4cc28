#include "sim/model/scene.hpp"

#include <cmath>
#include <numbers>

#include "geometry/stadium.hpp"

namespace rotleak {

std::string to_string(InitKind k) { return k == InitKind::birkhoff ? "birkhoff" : "flow"; }

std::string to_string(SamplingKind k) { return k == SamplingKind::uniform ? "uniform" : "mupo"; }

std::size_t Scene::survival_bins() const { return static_cast<std::size_t>(std::ceil(t_max / survival_dt)); }

double small_hole_rate(const Scene& scene) {
  const Stadium<double> st(scene.d, scene.r);
  return scene.width.to_double() * st.perimeter() / (std::numbers::pi * st.area());
}

double default_split_every(const Scene& scene) { return std::numbers::ln2 / small_hole_rate(scene); }

}  // namespace rotleak
