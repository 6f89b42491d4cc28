#include "analysis/output/table_output.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/table.hpp"

namespace rotleak {

namespace {

/// The points of loop `loop` at the shares s (each in [0, 1)) as "x", "y" arrays.
json points(const Table<double>& table, int loop, const std::vector<double>& s) {
  json x = json::array(), y = json::array();
  for (const double u : s) {
    const TableFrame<double> f = table.at(loop, u);
    x.push_back(f.q.x);
    y.push_back(f.q.y);
  }
  return {{"x", x}, {"y", y}};
}

/// s in [0, 1) of u (any real).
double unit(double u) {
  const double f = u - std::floor(u);
  return f < 1 ? f : 0.0;
}

}  // namespace

json table_drawing(const Scene& scene, int samples) {
  const TableSpec spec = table_spec(scene);
  const Table<double> table(spec);
  json loops = json::array();
  for (int l = 0; l < table.loops(); ++l) {
    std::vector<double> s;
    for (int k = 0; k < samples; ++k) s.push_back(static_cast<double>(k) / samples);
    for (int k = table.loop_first(l); k < table.loop_first(l) + table.loop_count(l); ++k)
      s.push_back(unit(table.piece(k).s0));  // every corner
    std::sort(s.begin(), s.end());
    s.push_back(s.front());  // closed
    json drawn = points(table, l, s);
    const TableFrame<double> o = table.at(l, 0.0);
    drawn["origin"] = {o.q.x, o.q.y};
    drawn["direction"] = {o.tangent.x, o.tangent.y};
    loops.push_back(drawn);
  }
  json leaks = json::array();
  for (const LeakSpec& leak : leak_specs(scene)) {
    const double c = unit(leak.start.to_double()), w = leak.width.to_double();
    std::vector<double> s;
    const int n = std::max(8, static_cast<int>(w * samples));
    for (int k = 0; k <= n; ++k) s.push_back(unit(c - w / 2 + w * k / n));
    json drawn = points(table, leak.loop, s);
    drawn["loop"] = leak.loop;
    drawn["moving"] = leak.omega.sign() != 0;
    leaks.push_back(drawn);
  }
  return {{"kind", spec.name},
          {"area", spec.area.to_double()},
          {"perimeter", spec.perimeter.to_double()},
          {"loops", loops},
          {"leaks", leaks}};
}

}  // namespace rotleak
