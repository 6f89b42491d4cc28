#include "verify/certify_sample.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/files.hpp"
#include "io/json.hpp"
#include "io/progress.hpp"
#include "io/scene_file.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/model/sampling.hpp"
#include "verify/certify_checkpoint.hpp"
#include "verify/trace.hpp"
#include "version.hpp"

namespace rotleak {

const char* status_name(EscapeStatus s) {
  switch (s) {
    case EscapeStatus::proven:
      return "proven";
    case EscapeStatus::survives:
      return "survives";
    case EscapeStatus::undecided:
      return "undecided";
  }
  return "?";
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

ParticleEscape certify_particle(const Scene& capped, const InitialDraw& draw, std::uint64_t id,
                                const SampleOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Certificate> attempts =
      certify(capped, draw, opt.start_bits, opt.max_bits, std::numeric_limits<std::size_t>::max());
  // a proven escape whose time is still wide is proven again with more bits, until it is narrow
  while (attempts.back().escape_certified &&
         attempts.back().escape_time_hi - attempts.back().escape_time_lo > opt.time_width &&
         2 * attempts.back().bits <= opt.max_bits) {
    Certificate again = certify_at(capped, draw, 2 * attempts.back().bits, std::numeric_limits<std::size_t>::max());
    if (!again.escape_certified) break;  // cannot happen for a proven escape; keep the proof we have
    attempts.push_back(again);
  }
  const Certificate& c = attempts.back();
  ParticleEscape e;
  e.id = id;
  e.bits = c.bits;
  e.collisions = c.escape_certified ? c.escape_collision : c.certified_collisions;
  if (c.escape_certified) {
    e.status = EscapeStatus::proven;
    e.t_lo = c.escape_time_lo, e.t_hi = c.escape_time_hi;
  } else if (c.survived) {
    e.status = EscapeStatus::survives;
    e.t_lo = e.t_hi = capped.t_max;
  } else {
    e.status = EscapeStatus::undecided;
    e.t_lo = c.certified_collisions ? c.last_time_lo : draw.tau;
    e.t_hi = capped.t_max;
  }
  e.seconds = seconds_since(t0);
  return e;
}

/// A tier's escape time and collision for one particle (the scalar core, every bounce stepped).
template <class M>
std::pair<double, std::size_t> tier_escape(const M& model, const InitialDraw& draw) {
  using R = typename M::real_type;
  double t = std::numeric_limits<double>::infinity();
  std::size_t k = 0;
  trace(model, draw, std::numeric_limits<std::size_t>::max(), [&](const auto& s) {
    if (!s.in_leak) return true;
    t = num_traits<R>::to_double(s.t);
    k = s.k;
    return false;
  });
  return {t, k};
}

TierEscapes run_tier(const std::string& tier, const Scene& capped, const std::vector<InitialDraw>& draws,
                     std::vector<std::size_t>& collisions, int threads) {
  TierEscapes out;
  out.tier = tier;
  out.t.resize(draws.size());
  collisions.resize(draws.size());
  const auto t0 = std::chrono::steady_clock::now();
  with_tier(tier, [&](auto type) {
    using R = typename decltype(type)::type;
    with_model<R>(capped, [&](const auto& model) {
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
      for (std::size_t i = 0; i < draws.size(); ++i) std::tie(out.t[i], collisions[i]) = tier_escape(model, draws[i]);
    });
  });
  out.seconds = seconds_since(t0);
  return out;
}

/// The particles a checkpoint holds, marked done (none without one); a checkpoint of other inputs, or of ids
/// outside the sample, is refused.
std::vector<char> resume(const Scene& scene, const SampleOptions& opt, std::vector<ParticleEscape>& particles) {
  std::vector<char> done(opt.sample, 0);
  if (opt.checkpoint.empty() || !std::filesystem::exists(opt.checkpoint)) return done;
  const std::string where = opt.checkpoint.string();
  const CertifyCheckpoint c = parse_certify_checkpoint(read_file(opt.checkpoint), where);
  if (c.inputs != certify_sample_inputs(scene, opt))
    throw std::runtime_error(where + ": a checkpoint of other inputs (" + c.inputs + "); remove it to start again");
  for (const ParticleEscape& e : c.particles) {
    if (e.id >= opt.sample)
      throw std::runtime_error(where + ": particle " + std::to_string(e.id) + " is not in the sample");
    particles[e.id] = e;
    done[e.id] = 1;
  }
  return done;
}

/// Kolmogorov's limiting distribution, P(D sqrt(n_e) > lambda) (the series converges fast for lambda >= 0.2).
double kolmogorov_q(double lambda) {
  if (lambda < 0.2) return 1;
  double sum = 0;
  for (int j = 1; j <= 100; ++j) sum += (j % 2 ? 2 : -2) * std::exp(-2.0 * j * j * lambda * lambda);
  return std::clamp(sum, 0.0, 1.0);
}

Scene capped_scene(const Scene& scene, const SampleOptions& opt) {
  Scene capped = scene;
  capped.t_max = opt.t_cap > 0 ? opt.t_cap : scene.t_max;
  return capped;
}

std::vector<InitialDraw> draws_of(const Scene& capped, std::uint64_t n) {
  const auto sampler = make_sampler(capped);
  std::vector<InitialDraw> draws(n);
  for (std::uint64_t i = 0; i < n; ++i) draws[i] = sampler->draw(i);
  return draws;
}

}  // namespace

SampleParticles certify_particles(const Scene& scene, const SampleOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene capped = capped_scene(scene, opt);
  const std::vector<InitialDraw> draws = draws_of(capped, opt.sample);
  SampleParticles out;
  out.particles.resize(opt.sample);
  out.done = resume(scene, opt, out.particles);
  out.threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const int threads = out.threads;
  const auto mine = [&](std::uint64_t i) { return i % opt.ranks == opt.rank; };
  std::uint64_t owned = 0;
  std::atomic<std::uint64_t> finished{0}, collisions{0};
  for (std::uint64_t i = 0; i < opt.sample; ++i) {
    owned += mine(i);
    if (mine(i) && out.done[i]) ++finished, collisions += out.particles[i].collisions;
  }
  ProgressLine progress(opt.progress, "[certify]");
  auto saved = std::chrono::steady_clock::now();
  constexpr std::uint64_t kChunk = 256;  // particles between chances to write the checkpoint
  for (std::uint64_t from = 0; from < opt.sample; from += kChunk) {
    const std::uint64_t to = std::min(opt.sample, from + kChunk);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::uint64_t i = from; i < to; ++i) {
      if (out.done[i] || !mine(i)) continue;
      out.particles[i] = certify_particle(capped, draws[i], i, opt);
      out.done[i] = 1;
      collisions += out.particles[i].collisions;
      const std::uint64_t n = ++finished;
      if (omp_get_thread_num() == 0) progress.update(n, owned, collisions, false);
    }
    if (!opt.checkpoint.empty() && to < opt.sample && seconds_since(saved) >= opt.checkpoint_seconds) {
      write_file_atomic(opt.checkpoint,
                        certify_checkpoint_text(certify_sample_inputs(scene, opt), out.particles, out.done));
      saved = std::chrono::steady_clock::now();
    }
  }
  progress.update(owned, owned, collisions, true);
  out.seconds = seconds_since(t0);
  return out;
}

SampleCertificate complete_sample(const Scene& scene, const SampleOptions& opt, SampleParticles p) {
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < opt.sample; ++i)
    if (!p.done.at(i)) throw std::logic_error("complete_sample: particle " + std::to_string(i) + " not certified");
  const Scene capped = capped_scene(scene, opt);
  const std::vector<InitialDraw> draws = draws_of(capped, opt.sample);
  SampleCertificate out;
  out.particles = std::move(p.particles);
  out.t_cap = capped.t_max;
  out.threads = p.threads;
  for (const std::string& tier : opt.tiers) {
    std::vector<std::size_t> k;
    out.tiers.push_back(run_tier(tier, capped, draws, k, p.threads));
    out.tier_collisions.insert(out.tier_collisions.end(), k.begin(), k.end());
  }
  out.seconds = p.seconds + seconds_since(t0);
  return out;
}

SampleCertificate certify_sample(const Scene& scene, const SampleOptions& opt) {
  return complete_sample(scene, opt, certify_particles(scene, opt));
}

SampleBracket bracket_of(const SampleCertificate& c, double dt) {
  SampleBracket b;
  const double n = static_cast<double>(c.particles.size());
  const std::size_t points = static_cast<std::size_t>(std::floor(c.t_cap / dt + 1e-9)) + 1;
  b.tier_p.assign(c.tiers.size(), {});
  for (std::size_t j = 0; j < points; ++j) {
    const double t = std::min(c.t_cap, static_cast<double>(j) * dt);
    std::size_t alive = 0, maybe = 0;
    for (const ParticleEscape& e : c.particles) {
      if (e.t_lo > t)
        ++alive;  // proven alive at t: the escape (or the doubt) comes later
      else if (e.t_hi > t || e.status == EscapeStatus::undecided)
        ++maybe;  // its escape time's enclosure holds t, or it is undecided from t_lo on (the cap included:
                  // it may live past it)
      else if (e.status == EscapeStatus::survives)
        ++alive;
    }
    b.t.push_back(t);
    b.lower.push_back(static_cast<double>(alive) / n);
    b.upper.push_back(static_cast<double>(alive + maybe) / n);
    for (std::size_t k = 0; k < c.tiers.size(); ++k) {
      const auto& ts = c.tiers[k].t;
      b.tier_p[k].push_back(static_cast<double>(std::count_if(ts.begin(), ts.end(), [&](double x) { return x > t; })) /
                            n);
    }
  }
  return b;
}

SampleTotals totals_of(const SampleCertificate& c, const SampleBracket& b) {
  SampleTotals t;
  for (const ParticleEscape& e : c.particles) {
    t.proven += e.status == EscapeStatus::proven;
    t.survives += e.status == EscapeStatus::survives;
    t.undecided += e.status == EscapeStatus::undecided;
    t.cpu_seconds += e.seconds;
    t.bits_max = std::max(t.bits_max, e.bits);
    if (e.status == EscapeStatus::proven) t.escape_width_max = std::max(t.escape_width_max, e.t_hi - e.t_lo);
  }
  for (std::size_t i = 0; i < b.t.size(); ++i)
    if (b.upper[i] - b.lower[i] > t.bracket_width_max)
      t.bracket_width_max = b.upper[i] - b.lower[i], t.bracket_widest_at = b.t[i];
  return t;
}

std::vector<TierJudgement> judge_tiers(const SampleCertificate& c, const SampleBracket& b) {
  std::vector<TierJudgement> out;
  const std::size_t n = c.particles.size();
  const double nd = static_cast<double>(n);
  for (std::size_t k = 0; k < c.tiers.size(); ++k) {
    TierJudgement j;
    j.tier = c.tiers[k].tier;
    j.grid_points = b.t.size();
    for (std::size_t i = 0; i < b.t.size(); ++i) {
      const double p = b.tier_p[k][i], mid = 0.5 * (b.lower[i] + b.upper[i]);
      // beyond the shadowing horizon a tier's escape and the truth's are two draws from one law: the
      // difference of two proportions of n has standard error sqrt(2 P (1 - P) / n)
      const double se = std::sqrt(2 * std::max(mid * (1 - mid), 1 / nd) / nd);
      const bool outside = p < b.lower[i] || p > b.upper[i];
      const double gap = std::max(b.lower[i] - p, p - b.upper[i]);
      const bool tight = b.upper[i] - b.lower[i] < se;
      j.outside += outside;
      j.outside_beyond_3s += outside && gap > 3 * se;
      j.tight += tight;
      j.outside_where_tight += outside && tight;
    }
    // Kolmogorov-Smirnov on the escape times up to the cap, the certified ones taken at their enclosures'
    // midpoints (undecided particles left out of both samples)
    std::vector<double> a, t;
    for (std::size_t i = 0; i < n; ++i) {
      const ParticleEscape& e = c.particles[i];
      if (e.status == EscapeStatus::undecided) continue;
      a.push_back(e.status == EscapeStatus::proven ? 0.5 * (e.t_lo + e.t_hi) : std::numeric_limits<double>::infinity());
      t.push_back(c.tiers[k].t[i]);
      if (e.status == EscapeStatus::proven && c.tier_collisions[k * n + i] == e.collisions) ++j.same_escape_collision;
    }
    std::sort(a.begin(), a.end());
    std::sort(t.begin(), t.end());
    std::size_t ia = 0, it = 0;
    double d = 0;
    while (ia < a.size() && it < t.size() && std::isfinite(std::min(a[ia], t[it]))) {
      const double x = std::min(a[ia], t[it]);
      while (ia < a.size() && a[ia] <= x) ++ia;
      while (it < t.size() && t[it] <= x) ++it;
      d = std::max(d, std::abs(static_cast<double>(ia) - static_cast<double>(it)) / static_cast<double>(a.size()));
    }
    const double ne = static_cast<double>(a.size()) / 2;
    j.ks_d = d;
    j.ks_p = a.empty() ? 1 : kolmogorov_q((std::sqrt(ne) + 0.12 + 0.11 / std::sqrt(ne)) * d);
    out.push_back(j);
  }
  return out;
}

namespace {

std::string escapes_csv(const SampleCertificate& c) {
  std::ostringstream esc;
  esc << "id,status,t_lo,t_hi,collisions,bits";
  for (const TierEscapes& t : c.tiers) esc << ",t_" << t.tier;
  esc << "\n";
  for (std::size_t i = 0; i < c.particles.size(); ++i) {
    const ParticleEscape& e = c.particles[i];
    esc << e.id << ',' << status_name(e.status) << ',' << shortest(e.t_lo) << ',' << shortest(e.t_hi) << ','
        << e.collisions << ',' << e.bits;
    for (const TierEscapes& t : c.tiers) esc << ',' << (std::isfinite(t.t[i]) ? shortest(t.t[i]) : "inf");
    esc << "\n";
  }
  return esc.str();
}

std::string bracket_csv(const SampleCertificate& c, const SampleBracket& b) {
  std::ostringstream br;
  br << "t,lower,upper";
  for (const TierEscapes& t : c.tiers) br << ",p_" << t.tier;
  br << "\n";
  for (std::size_t i = 0; i < b.t.size(); ++i) {
    br << shortest(b.t[i]) << ',' << shortest(b.lower[i]) << ',' << shortest(b.upper[i]);
    for (const auto& p : b.tier_p) br << ',' << shortest(p[i]);
    br << "\n";
  }
  return br.str();
}

json tiers_json(const SampleCertificate& c, const std::vector<TierJudgement>& judged) {
  json tiers = json::array();
  for (std::size_t k = 0; k < judged.size(); ++k) {
    const TierJudgement& j = judged[k];
    tiers.push_back({{"tier", j.tier},
                     {"seconds", c.tiers[k].seconds},
                     {"grid_points", j.grid_points},
                     {"outside", j.outside},
                     {"outside_beyond_3_errors", j.outside_beyond_3s},
                     {"tight", j.tight},
                     {"outside_where_tight", j.outside_where_tight},
                     {"ks_d", j.ks_d},
                     {"ks_p", j.ks_p},
                     {"same_escape_collision", j.same_escape_collision}});
  }
  return tiers;
}

json summary_json(const Scene& scene, const SampleOptions& opt, const SampleCertificate& c, const SampleBracket& b,
                  double dt) {
  const SampleTotals tot = totals_of(c, b);
  const double n = static_cast<double>(c.particles.size());
  return {{"command", "certify"},
          {"schema", 1},
          {"version", kVersion},
          {"scene", scene_to_toml(scene)},
          {"sample", c.particles.size()},
          {"t_cap", c.t_cap},
          {"dt", dt},
          {"proven", tot.proven},
          {"survives", tot.survives},
          {"undecided", tot.undecided},
          {"proven_fraction", static_cast<double>(tot.proven + tot.survives) / n},
          {"bits", {{"start", opt.start_bits}, {"cap", opt.max_bits}, {"largest_used", tot.bits_max}}},
          {"time_width", opt.time_width},
          {"escape_time_width_max", tot.escape_width_max},
          {"bracket_width_max", tot.bracket_width_max},
          {"threads", c.threads},
          {"seconds", c.seconds},
          {"seconds_per_particle", tot.cpu_seconds / n},
          {"tiers", tiers_json(c, judge_tiers(c, b))}};
}

}  // namespace

void write_sample_certificate(const std::filesystem::path& dir, const Scene& scene, const SampleOptions& opt,
                              const SampleCertificate& c) {
  std::filesystem::create_directories(dir);
  const double dt = opt.dt > 0 ? opt.dt : c.t_cap / 400;
  const SampleBracket b = bracket_of(c, dt);
  write_file_atomic(dir / "escapes.csv", escapes_csv(c));
  write_file_atomic(dir / "bracket.csv", bracket_csv(c, b));
  write_file_atomic(dir / "summary.json", summary_json(scene, opt, c, b, dt).dump(2) + "\n");
}

}  // namespace rotleak
