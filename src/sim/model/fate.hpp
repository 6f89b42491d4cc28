// The contract the two engines share: how a particle ends, and when a zero-length flight means
// stuck. The vectorised kernel (sim/kernel/simd_engine.cpp) reports the same codes, plus one of its own.
#pragma once

#include <cstdint>

namespace rotleak {

enum class Fate : std::uint8_t { escaped = 0, survived = 1, stuck = 2 };

/// Flights of zero length in a row before a particle is declared stuck (a corner or exact graze
/// that rounding cannot leave); counted and reported, never silently dropped.
inline constexpr int kMaxZeroFlights = 64;

/// How a lane of the vectorised kernel ends: a Fate, or handed back mid-flight to the scalar
/// fast-forward (the state travels with it).
enum class LaneEnd : int {
  escaped = static_cast<int>(Fate::escaped),
  survived = static_cast<int>(Fate::survived),
  stuck = static_cast<int>(Fate::stuck),
  handed_back = 3
};

}  // namespace rotleak
