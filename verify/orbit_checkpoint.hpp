// The orbit search's checkpoint (`rotleak orbits --out DIR` keeps DIR.checkpoint while it runs): the inputs,
// then each completed period's tally and orbits (code, weight, the refined bounce parameters the proof
// started from, exactly, in hexadecimal). A resumed search re-proves every stored orbit from its parameters (the proof
// is the record, not the file) and goes on with the next period. Text, one record a line (docs/output.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "verify/orbits.hpp"

namespace rotleak {

struct OrbitCheckpoint {
  std::string inputs;  ///< "d=2 r=1 bits=160 starts=48 seed=1": a checkpoint of other inputs is refused
  std::vector<PeriodTally> periods;
  struct Orbit {
    OrbitCode code;
    int weight = 1;
    std::vector<std::string> u;  ///< the refined point the proof started from, exact hexadecimal (%Ra)
  };
  std::vector<Orbit> orbits;
};

/// The inputs line of a search.
std::string orbit_search_inputs(const ExactReal& d, const ExactReal& r, const OrbitOptions& opt);

std::string orbit_checkpoint_text(const std::string& inputs, const OrbitSearch& s);
/// std::runtime_error naming `where` and the line on anything malformed.
OrbitCheckpoint parse_orbit_checkpoint(const std::string& text, const std::string& where);

/// The search of a checkpoint, its orbits proven again at opt.bits (std::runtime_error if one fails).
OrbitSearch resume_orbit_search(const ExactReal& d, const ExactReal& r, const OrbitCheckpoint& c,
                                const OrbitOptions& opt);

}  // namespace rotleak
