// rotleak certify SCENE --particle ID [--bits B] [--max-bits M] [--method lohner|interval] [--json]
// rotleak certify SCENE --sample N --out DIR [--t-cap T] [--threads K] [--tiers double,long_double,dd] [--force]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "run/certify_shared.hpp"
#include "sim/model/sampling.hpp"
#include "verify/certify_sample.hpp"
#include "verify/reports.hpp"

namespace rotleak::cli {

namespace {

struct CertifyArgs {
  std::string scene;
  std::vector<std::string> sets;
  long long particle = -1, bits = 64, max_bits = 1 << 16, collisions = 100000;
  std::string method = "lohner";
  bool json_out = false;
  // a sample
  long long sample = 0, threads = 0;
  double t_cap = 0, dt = 0;
  std::string out, tiers = "double,long_double,dd";
  bool force = false, quiet = false;
};

std::vector<std::string> tier_list(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string name = text.substr(at, comma - at);
    if (name != "double" && name != "long_double" && name != "dd" && name != "float128" && name != "float")
      throw InputError("--tiers", text,
                       "must be a comma-separated list of point tiers (float, double, long_double, dd, float128)");
    out.push_back(name);
    at = comma + 1;
  }
  return out;
}

int run_sample(const CertifyArgs& a, const Scene& scene) {
  if (a.sample < 1 || static_cast<std::uint64_t>(a.sample) > scene.particles)
    throw InputError("--sample", std::to_string(a.sample),
                     "must be in [1, " + std::to_string(scene.particles) + "] (the scene's particles)");
  if (scene.sampling.weighted())
    throw InputError("ensemble.sampling", "mupo", "certify --sample follows unweighted particles: uniform only");
  if (a.out.empty()) throw InputError("--out", "", "a directory for escapes.csv, bracket.csv and summary.json");
  if (a.t_cap < 0 || a.t_cap > scene.t_max)
    throw InputError("--t-cap", std::to_string(a.t_cap), "must be in (0, run.t_max] (0: run.t_max)");
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  if (a.dt < 0) throw InputError("--dt", std::to_string(a.dt), "must be > 0 (0: the cap / 400)");
  SampleOptions opt;
  opt.sample = static_cast<std::uint64_t>(a.sample);
  opt.t_cap = a.t_cap;
  opt.start_bits = a.bits;
  opt.max_bits = a.max_bits;
  opt.threads = static_cast<int>(a.threads);
  opt.tiers = tier_list(a.tiers);
  opt.dt = a.dt;
  opt.progress = !a.quiet;
  // under mpirun every rank certifies its share; rank 0 stages the directory (before any work) and writes
  const Team& team = current_team();
  const bool lead = team.rank() == 0;
  std::unique_ptr<RunDirectory> dir;
  std::exception_ptr failure;
  try {
    if (lead) dir = std::make_unique<RunDirectory>(a.out, a.force);
  } catch (...) {
    failure = std::current_exception();
  }
  agree(team, failure);
  // DIR.checkpoint beside the target while the sample runs: a killed run goes on from it (one process)
  opt.checkpoint = RunDirectory::normalise(a.out);
  opt.checkpoint += ".checkpoint";
  const SampleCertificate c = certify_shared(scene, opt, team);
  if (!lead) return 0;
  write_sample_certificate(dir->file("summary.json").parent_path(), scene, opt, c);
  dir->commit();
  std::filesystem::remove(opt.checkpoint);
  std::fputs(sample_text(c, opt).c_str(), stdout);
  return 0;
}

int run_certify(const CertifyArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  // each bound blames its own option (--max-bits 100000000 once blamed --bits)
  if (a.max_bits < Tier::kMinBits || a.max_bits > (1L << 22))
    throw InputError("--max-bits", std::to_string(a.max_bits),
                     "must be in [" + std::to_string(Tier::kMinBits) + ", 4194304 = 2^22]");
  if (a.bits < Tier::kMinBits || a.bits > a.max_bits)
    throw InputError(
        "--bits", std::to_string(a.bits),
        "must be in [" + std::to_string(Tier::kMinBits) + ", --max-bits = " + std::to_string(a.max_bits) + "]");
  if (a.sample != 0) return run_sample(a, scene);
  if (current_team().size() > 1)
    throw InputError("mpirun -np", std::to_string(current_team().size()),
                     "certify --particle runs as one process; under MPI only --sample shares its work");
  if (a.particle == -1) throw InputError("--particle", "", "give --particle ID (one particle) or --sample N --out DIR");
  if (a.particle < 0 || static_cast<std::uint64_t>(a.particle) >= scene.particles)
    throw InputError("--particle", std::to_string(a.particle),
                     "must be a particle id in [0, " + std::to_string(scene.particles) + ")");
  if (a.method != "lohner" && a.method != "interval")
    throw InputError("--method", a.method, "must be lohner (mean-value sets) or interval (plain MPFI)");
  const auto attempts =
      certify(scene, make_sampler(scene)->draw(static_cast<std::uint64_t>(a.particle)), a.bits, a.max_bits,
              static_cast<std::size_t>(a.collisions), a.method == "lohner" ? Enclosure::lohner : Enclosure::interval);
  if (a.json_out)
    std::cout << certify_json(static_cast<std::uint64_t>(a.particle), attempts).dump(2) << "\n";
  else
    std::fputs(certify_text(attempts).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_certify(CLI::App& app) {
  auto a = std::make_shared<CertifyArgs>();
  CLI::App* sub =
      app.add_subcommand("certify", "Prove a particle's escape with MPFI interval arithmetic (raising the bits)");
  sub->add_option("scene", a->scene, "Scene file (TOML)")->required();
  auto* particle = sub->add_option("--particle", a->particle, "Particle id");
  auto* sample = sub->add_option("--sample", a->sample, "Certify particles 0 .. N-1 and write DIR (with --out)");
  particle->excludes(sample);
  sub->add_option("--out", a->out, "Directory for a sample's escapes.csv, bracket.csv, summary.json");
  sub->add_option("--t-cap", a->t_cap, "Follow a sample's particles to this time (default: run.t_max)");
  sub->add_option("--threads", a->threads, "OpenMP threads for a sample (default: all cores)");
  sub->add_option("--tiers", a->tiers, "Point tiers judged against a sample's bracket (default double,long_double,dd)");
  sub->add_option("--dt", a->dt, "The bracket's grid step (default: the cap / 400)");
  sub->add_flag("--force", a->force, "Replace an existing --out directory");
  sub->add_flag("--no-progress", a->quiet, "No progress line on stderr");
  sub->add_option("--bits", a->bits, "Starting precision (default 64)");
  sub->add_option("--max-bits", a->max_bits, "Give up above this precision (default 65536)");
  sub->add_option("--method", a->method,
                  "lohner (default: mean-value sets, ~1.4 bits lost a collision) or interval (plain MPFI, ~4)");
  sub->add_option("--collisions", a->collisions, "Collision cap (default 1e5)");
  sub->add_option("--set", a->sets, "Override a scene key (repeatable)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_certify(*a); }};
}

}  // namespace rotleak::cli
