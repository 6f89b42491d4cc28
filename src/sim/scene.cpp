#include "sim/scene.hpp"

#include <cmath>

namespace rotleak {

std::string to_string(InitKind k) { return k == InitKind::birkhoff ? "birkhoff" : "flow"; }

std::string to_string(SamplingKind k) { return k == SamplingKind::uniform ? "uniform" : "mupo"; }

std::size_t Scene::survival_bins() const { return static_cast<std::size_t>(std::ceil(t_max / survival_dt)); }

}  // namespace rotleak
