#include "verify/certify_checkpoint.hpp"

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>

#include "io/bytes.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "verify/checkpoint_text.hpp"

namespace rotleak {

namespace {

constexpr const char* kMagic = "rotleak-certify-checkpoint 1";

std::uint64_t scene_hash(const Scene& scene) {
  const std::string text = scene_to_toml(scene);
  return fnv1a(text.data(), text.size());
}

}  // namespace

std::string certify_sample_inputs(const Scene& scene, const SampleOptions& opt) {
  std::ostringstream out;
  out << "scene=" << std::hex << scene_hash(scene) << std::dec << " sample=" << opt.sample
      << " t_cap=" << hex_exact(opt.t_cap > 0 ? opt.t_cap : scene.t_max) << " bits=" << opt.start_bits << '-'
      << opt.max_bits << " time_width=" << hex_exact(opt.time_width);
  return out.str();
}

std::string certify_checkpoint_text(const std::string& inputs, const std::vector<ParticleEscape>& particles,
                                    const std::vector<char>& done) {
  std::ostringstream out;
  out << kMagic << "\ninputs " << inputs << "\n";
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!done[i]) continue;
    const ParticleEscape& e = particles[i];
    out << "particle " << e.id << ' ' << status_name(e.status) << ' ' << hex_exact(e.t_lo) << ' ' << hex_exact(e.t_hi)
        << ' ' << e.collisions << ' ' << e.bits << ' ' << hex_exact(e.seconds) << '\n';
  }
  return out.str();
}

namespace {

/// One `particle ...` record.
ParticleEscape parse_particle(const std::vector<std::string>& w, const CheckpointReader& r) {
  if (w.size() != 8 || w[0] != "particle") r.fail("not a particle line");
  ParticleEscape e;
  e.id = r.count(w[1]);
  if (w[2] == "proven")
    e.status = EscapeStatus::proven;
  else if (w[2] == "survives")
    e.status = EscapeStatus::survives;
  else if (w[2] == "undecided")
    e.status = EscapeStatus::undecided;
  else
    r.fail("not a status: \"" + w[2] + "\"");
  e.t_lo = r.time(w[3]);
  e.t_hi = r.time(w[4]);
  if (e.t_lo > e.t_hi) r.fail("t_lo above t_hi");
  e.collisions = r.count(w[5]);
  const std::size_t bits = r.count(w[6]);
  if (bits > (std::size_t{1} << 22)) r.fail("more bits than certify allows");
  e.bits = static_cast<long>(bits);
  e.seconds = r.time(w[7]);
  return e;
}

}  // namespace

CertifyCheckpoint parse_certify_checkpoint(const std::string& text, const std::string& where) {
  CheckpointReader r(text, kMagic, where);
  CertifyCheckpoint c;
  c.inputs = r.inputs();
  std::set<std::uint64_t> seen;
  for (std::vector<std::string> w; r.next(w);) {
    c.particles.push_back(parse_particle(w, r));
    if (!seen.insert(c.particles.back().id).second) r.fail("particle " + w[1] + " twice");
  }
  return c;
}

}  // namespace rotleak
