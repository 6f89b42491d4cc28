// A certified sample's checkpoint (`rotleak certify --sample N --out DIR` keeps DIR.checkpoint while it
// runs): the inputs, then one line per particle whose certificate is done, its times exactly in hexadecimal.
// A certificate depends on its particle alone, so a resumed run that takes the stored ones and certifies the
// rest writes what one uninterrupted run writes. Text, one record a line (docs/output.md).
#pragma once

#include <string>
#include <vector>

#include "verify/certify_sample.hpp"

namespace rotleak {

struct CertifyCheckpoint {
  std::string inputs;  ///< certify_sample_inputs: a checkpoint of other inputs is refused
  std::vector<ParticleEscape> particles;
};

/// The inputs line of a sample: the scene (its TOML's FNV-1a hash), the sample, the cap, the bits, the width.
std::string certify_sample_inputs(const Scene& scene, const SampleOptions& opt);

/// The checkpoint of the particles marked done.
std::string certify_checkpoint_text(const std::string& inputs, const std::vector<ParticleEscape>& particles,
                                    const std::vector<char>& done);
/// std::runtime_error naming `where` and the line on anything malformed (an id twice included).
CertifyCheckpoint parse_certify_checkpoint(const std::string& text, const std::string& where);

}  // namespace rotleak
