#include "verify/certify_checkpoint.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>

#include "io/files.hpp"
#include "io/scene_file.hpp"

namespace rotleak {

namespace {

constexpr const char* kMagic = "rotleak-certify-checkpoint 1";

std::string hex(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

}  // namespace

std::string certify_sample_inputs(const Scene& scene, const SampleOptions& opt) {
  std::ostringstream out;
  out << "scene=" << std::hex << fnv1a(scene_to_toml(scene)) << std::dec << " sample=" << opt.sample
      << " t_cap=" << hex(opt.t_cap > 0 ? opt.t_cap : scene.t_max) << " bits=" << opt.start_bits << '-' << opt.max_bits
      << " time_width=" << hex(opt.time_width);
  return out.str();
}

std::string certify_checkpoint_text(const std::string& inputs, const std::vector<ParticleEscape>& particles,
                                    const std::vector<char>& done) {
  std::ostringstream out;
  out << kMagic << "\ninputs " << inputs << "\n";
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!done[i]) continue;
    const ParticleEscape& e = particles[i];
    out << "particle " << e.id << ' ' << status_name(e.status) << ' ' << hex(e.t_lo) << ' ' << hex(e.t_hi) << ' '
        << e.collisions << ' ' << e.bits << ' ' << hex(e.seconds) << '\n';
  }
  return out.str();
}

namespace {

/// One `particle ...` line's words; fail(why) throws with the line.
template <class Fail>
ParticleEscape parse_particle(const std::vector<std::string>& w, const Fail& fail) {
  const auto count = [&](const std::string& x) {
    std::size_t at = 0;
    unsigned long long v = 0;
    try {
      v = std::stoull(x, &at);
    } catch (const std::exception&) {
      at = 0;
    }
    if (x.empty() || x[0] == '-' || at != x.size()) fail("not a count: \"" + x + "\"");
    return v;
  };
  const auto number = [&](const std::string& x) {
    char* end = nullptr;
    const double v = std::strtod(x.c_str(), &end);
    if (x.empty() || end != x.c_str() + x.size() || !std::isfinite(v) || v < 0) fail("not a time: \"" + x + "\"");
    return v;
  };
  if (w.size() != 8 || w[0] != "particle") fail("not a particle line");
  ParticleEscape e;
  e.id = count(w[1]);
  if (w[2] == "proven")
    e.status = EscapeStatus::proven;
  else if (w[2] == "survives")
    e.status = EscapeStatus::survives;
  else if (w[2] == "undecided")
    e.status = EscapeStatus::undecided;
  else
    fail("not a status: \"" + w[2] + "\"");
  e.t_lo = number(w[3]);
  e.t_hi = number(w[4]);
  if (e.t_lo > e.t_hi) fail("t_lo above t_hi");
  e.collisions = count(w[5]);
  const unsigned long long bits = count(w[6]);
  if (bits > (1ULL << 22)) fail("more bits than certify allows");
  e.bits = static_cast<long>(bits);
  e.seconds = number(w[7]);
  return e;
}

}  // namespace

CertifyCheckpoint parse_certify_checkpoint(const std::string& text, const std::string& where) {
  CertifyCheckpoint c;
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0;
  const auto fail = [&](const std::string& why) {
    throw std::runtime_error(where + ":" + std::to_string(n) + ": " + why);
  };
  std::set<std::uint64_t> seen;
  while (std::getline(in, line)) {
    ++n;
    if (n == 1) {
      if (line != kMagic) fail("not a rotleak certify checkpoint");
      continue;
    }
    if (n == 2) {
      if (line.rfind("inputs ", 0) != 0) fail("no inputs line");
      c.inputs = line.substr(7);
      continue;
    }
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    c.particles.push_back(parse_particle(w, fail));
    if (!seen.insert(c.particles.back().id).second) fail("particle " + w[1] + " twice");
  }
  if (n < 2) fail("incomplete: no inputs line");
  return c;
}

}  // namespace rotleak
