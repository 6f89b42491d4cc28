#include "run/certify_shared.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "verify/certify_checkpoint.hpp"

namespace rotleak {

SampleCertificate certify_shared(const Scene& scene, SampleOptions opt, const Team& team) {
  if (team.size() == 1) return certify_sample(scene, opt);
  opt.rank = static_cast<std::uint64_t>(team.rank());
  opt.ranks = static_cast<std::uint64_t>(team.size());
  opt.checkpoint.clear();  // ranks keep no checkpoint (a killed shared run starts again)
  opt.progress = opt.progress && team.rank() == 0;
  SampleParticles mine = certify_particles(scene, opt);
  const std::string inputs = certify_sample_inputs(scene, opt);
  const std::vector<std::string> parts = team.gather(certify_checkpoint_text(inputs, mine.particles, mine.done));
  if (team.rank() != 0) return {};
  SampleParticles all;
  all.particles.resize(opt.sample);
  all.done.assign(opt.sample, 0);
  all.threads = mine.threads;
  all.seconds = mine.seconds;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    const CertifyCheckpoint c = parse_certify_checkpoint(parts[r], "rank " + std::to_string(r));
    if (c.inputs != inputs) throw std::logic_error("rank " + std::to_string(r) + " certified other inputs");
    for (const ParticleEscape& e : c.particles) {
      if (e.id >= opt.sample || e.id % opt.ranks != r || all.done[e.id])
        throw std::logic_error("rank " + std::to_string(r) + " sent particle " + std::to_string(e.id));
      all.particles[e.id] = e;
      all.done[e.id] = 1;
    }
  }
  return complete_sample(scene, opt, std::move(all));  // refuses a sample with a particle missing
}

}  // namespace rotleak
