// The run directory's CSV files, as text (written atomically by the caller).
#pragma once

#include <string>
#include <vector>

#include "sim/engine.hpp"
#include "sim/scene.hpp"

namespace rotleak {

/// Grid times t_k = k dt for k = 0..bins, the last one clamped to t_max.
std::vector<double> survival_times(const Scene& scene);
/// survival.csv: header t,survivors,P.
std::string survival_csv(const Scene& scene, const Tally& tally);
/// fc.csv: s (bin centre), then per window the normalised density and the raw count.
std::string density_csv(const Scene& scene, const Tally& tally);
/// escapes.csv: id,fate,t,s,collisions.
std::string escapes_csv(std::uint64_t first_id, const std::vector<EscapeRecord>& records);

}  // namespace rotleak
