// rotleak certify SCENE --particle ID [--bits B] [--max-bits M] [--method lohner|interval] [--json]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/scene_file.hpp"
#include "sim/model/sampling.hpp"
#include "verify/reports.hpp"

namespace rotleak::cli {

namespace {

struct CertifyArgs {
  std::string scene;
  std::vector<std::string> sets;
  long long particle = 0, bits = 64, max_bits = 1 << 16, collisions = 100000;
  std::string method = "lohner";
  bool json_out = false;
};

int run_certify(const CertifyArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.particle < 0 || static_cast<std::uint64_t>(a.particle) >= scene.particles)
    throw InputError("--particle", std::to_string(a.particle),
                     "must be a particle id in [0, " + std::to_string(scene.particles) + ")");
  if (a.bits < Tier::kMinBits || a.bits > a.max_bits || a.max_bits > (1L << 22))
    throw InputError("--bits", std::to_string(a.bits),
                     "must be in [" + std::to_string(Tier::kMinBits) + ", --max-bits], and --max-bits <= 2^22");
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
  sub->add_option("--particle", a->particle, "Particle id")->required();
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
