#include "sim/model/scene.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "geometry/stadium.hpp"

namespace rotleak {

std::string to_string(InitKind k) { return k == InitKind::birkhoff ? "birkhoff" : "flow"; }

std::string to_string(SamplingKind k) { return k == SamplingKind::uniform ? "uniform" : "mupo"; }

std::size_t Scene::survival_bins() const { return static_cast<std::size_t>(std::ceil(t_max / survival_dt)); }

TableSpec table_spec(const Scene& scene) {
  if (!scene.table) return stadium_table(scene.d, scene.r);
  const TableInput& t = *scene.table;
  if (t.kind == "polygon") {
    std::vector<std::pair<ExactReal, ExactReal>> v;
    for (const auto& [x, y] : t.vertices) v.emplace_back(x.value, y.value);
    return polygon_table(v);
  }
  const TableKind* kind = find_table_kind(t.kind);
  if (!kind || !kind->build || kind->params.size() != t.params.size())
    throw std::logic_error("table_spec: a table input of kind \"" + t.kind + "\" that the scene reader let through");
  std::vector<ExactReal> values;
  for (const ExactInput& p : t.params) values.push_back(p.value);
  return kind->build(values);
}

std::vector<LeakSpec> leak_specs(const Scene& scene) {
  if (scene.leaks.empty()) return {LeakSpec{0, scene.width, scene.start, scene.omega}};
  std::vector<LeakSpec> out;
  for (const LeakInput& l : scene.leaks) out.push_back({l.loop, l.width.value, l.start.value, l.omega.value});
  return out;
}

bool any_leak_moves(const Scene& scene) {
  for (const LeakSpec& l : leak_specs(scene))
    if (l.omega.sign() != 0) return true;
  return false;
}

double small_hole_rate(const Scene& scene) {
  if (scene.on_table()) {
    const TableSpec t = table_spec(scene);
    double length = 0;  // the leaks' lengths, in the order listed
    for (const LeakSpec& l : leak_specs(scene))
      length += l.width.to_double() * t.loops[static_cast<std::size_t>(l.loop)].length.to_double();
    return length / (std::numbers::pi * t.area.to_double());
  }
  const Stadium<double> st(scene.d, scene.r);
  return scene.width.to_double() * st.perimeter() / (std::numbers::pi * st.area());
}

double default_split_every(const Scene& scene) { return std::numbers::ln2 / small_hole_rate(scene); }

}  // namespace rotleak
