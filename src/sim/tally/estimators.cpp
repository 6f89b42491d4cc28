#include "sim/tally/estimators.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace rotleak {

void WeightedEstimator::resize(std::size_t bins) {
  escaped_w.assign(bins, FixedSum{});
  escaped_w2.assign(bins, FixedSum{});
}

void WeightedEstimator::add_end(Fate fate, std::size_t bin, double w) {
  total_w.add(w);
  total_w2.add(w * w);
  if (fate == Fate::escaped) {
    escaped_w[bin].add(w);
    escaped_w2[bin].add(w * w);
  }
}

void WeightedEstimator::merge(const WeightedEstimator& o) {
  for (std::size_t i = 0; i < escaped_w.size(); ++i) {
    escaped_w[i].merge(o.escaped_w[i]);
    escaped_w2[i].merge(o.escaped_w2[i]);
  }
  total_w.merge(o.total_w);
  total_w2.merge(o.total_w2);
}

void LinesEstimator::resize(std::size_t bins) {
  const std::size_t points = bins + 1;
  for (auto* v : {&line_in, &line_out, &line2_in, &line2_out, &linex_in, &linex_out}) v->assign(points, FixedSum{});
  lines_ended.assign(points, 0);
  born_per_bin.assign(bins, 0);
  culled_per_bin.assign(bins, 0);
}

void LinesEstimator::add_end(Fate fate, std::size_t /*bin*/, double w) {
  (fate == Fate::escaped ? w_escaped : w_alive_end).add(w);
}

void LinesEstimator::merge(const LinesEstimator& o) {
  for (std::size_t i = 0; i < line_in.size(); ++i) {
    line_in[i].merge(o.line_in[i]);
    line_out[i].merge(o.line_out[i]);
    line2_in[i].merge(o.line2_in[i]);
    line2_out[i].merge(o.line2_out[i]);
    linex_in[i].merge(o.linex_in[i]);
    linex_out[i].merge(o.linex_out[i]);
    lines_ended[i] += o.lines_ended[i];
  }
  for (std::size_t i = 0; i < born_per_bin.size(); ++i) {
    born_per_bin[i] += o.born_per_bin[i];
    culled_per_bin[i] += o.culled_per_bin[i];
  }
  splits += o.splits;
  culls += o.culls;
  for (auto [a, b] : {std::pair{&w_start, &o.w_start},
                      {&w_gained, &o.w_gained},
                      {&w_escaped, &o.w_escaped},
                      {&w_removed, &o.w_removed},
                      {&w_alive_end, &o.w_alive_end}})
    a->merge(*b);
  for (std::size_t c = 0; c < unsplit_start.size(); ++c) unsplit_start[c].merge(o.unsplit_start[c]);
  for (const auto& [key, cell] : o.unsplit_left) unsplit_left[key].merge(cell);
  levels = std::max(levels, o.levels);
  max_population = std::max(max_population, o.max_population);
  max_line = std::max(max_line, o.max_line);
}

void LinesEstimator::start_line(double w0) {
  w_start.add(w0);
  unsplit_start[static_cast<std::size_t>(unsplit_class(w0))].add(w0);
}

void LinesEstimator::leave_unsplit(std::size_t g, double w0) {
  unsplit_left[g * kUnsplitClasses + static_cast<std::uint64_t>(unsplit_class(w0))].add(w0);
}

void LinesEstimator::stretch(std::size_t from, std::size_t to, double y, double w0) {
  const std::size_t points = line_in.size();
  if (!(y > 0) || from >= points || to <= from) return;
  const double yw = y * w0;  // rounded once, then summed exactly: the same bits in any order (a variance's term)
  line_in[from].add(y);
  line2_in[from].add_square(y);
  linex_in[from].add(yw);
  if (to < points) {
    line_out[to].add(y);
    line2_out[to].add_square(y);
    linex_out[to].add(yw);
  }
}

void LinesEstimator::split(std::size_t bin) {
  ++splits;
  ++born_per_bin[bin];
}

void LinesEstimator::roulette(bool kept, double weight, std::size_t bin) {
  if (kept) {
    w_gained.add(weight);
    return;
  }
  w_removed.add(weight);
  ++culls;
  ++culled_per_bin[bin];
}

void LinesEstimator::check_conservation() const {
  FixedSum in = w_start, out = w_escaped;
  in.merge(w_gained);
  out.merge(w_removed);
  out.merge(w_alive_end);
  if (!(in == out)) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "split run: weight not conserved (start + roulette gains %.17g, escaped + removed + alive %.17g)",
                  in.value(), out.value());
    throw std::logic_error(why);
  }
}

}  // namespace rotleak
