// rotleak orbits --period-max N --out DIR [--d 2] [--r 1] [--bits 160] [--starts 48] [--threads T] [--force]
// rotleak orbits --code TRBL [--d 2] [--r 1] [--bits 160] [--json]
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "analysis/cycle_expansion.hpp"
#include "cli/commands.hpp"
#include "io/files.hpp"
#include "io/json.hpp"
#include "numeric/input.hpp"
#include "verify/orbits.hpp"

namespace rotleak::cli {

namespace {

struct OrbitsArgs {
  std::string d = "2", r = "1", code, out;
  int period_max = 0, threads = 0, starts = 48;
  long bits = 160;
  long long seed = 1;
  bool force = false, json_out = false, quiet = false;
};

ExactReal positive(const std::string& key, const std::string& text) {
  ExactReal x;
  try {
    x = ExactReal::parse(text);
  } catch (const std::exception&) {
    throw InputError(key, text, "an exact positive number (e.g. 2, 1/3, 0.7, sqrt(2))");
  }
  if (x.sign() <= 0) throw InputError(key, text, "must be > 0");
  return x;
}

json orbit_json(const ProvenOrbit& o) {
  return {{"code", orbit_code_text(o.code)},
          {"period", o.code.size()},
          {"length", orbit_digits(o.length)},
          {"multiplier", orbit_digits(o.multiplier)},
          {"trace", orbit_digits(o.trace)},
          {"stability", o.stability()},
          {"weight", o.weight},
          {"box_width", o.box_width}};
}

int run_code(const OrbitsArgs& a, const ExactReal& d, const ExactReal& r, const OrbitOptions& opt) {
  const OrbitCode code = parse_orbit_code(a.code);
  const CodeOrbits got = code_orbits(d, r, code, opt);
  const std::string refusal =
      !got.orbits.empty() ? ""
      : got.family        ? "the bouncing-ball family: a continuum of parabolic orbits (trace 2), none isolated"
      : got.unproven > 0  ? "candidates found, none proven"
                          : "no orbit found from " + std::to_string(opt.starts) + " Newton starts";
  if (a.json_out) {
    json orbits = json::array();
    for (const ProvenOrbit& o : got.orbits) orbits.push_back(orbit_json(o));
    std::cout << json{{"code", orbit_code_text(code)},
                      {"orbits", orbits},
                      {"candidates", got.candidates},
                      {"unproven", got.unproven},
                      {"refused", refusal.empty() ? json(nullptr) : json(refusal)}}
                     .dump(2)
              << "\n";
  } else {
    for (const ProvenOrbit& o : got.orbits)
      std::printf("%s  length %s  multiplier %s  %s  box %.3g\n", orbit_code_text(o.code).c_str(),
                  orbit_digits(o.length).c_str(), orbit_digits(o.multiplier).c_str(), o.stability().c_str(),
                  o.box_width);
    if (!refusal.empty()) std::printf("%s refused: %s\n", orbit_code_text(code).c_str(), refusal.c_str());
  }
  return 0;
}

void print_period(const PeriodTally& t) {
  std::fprintf(stderr, "orbits: period %d: %zu proven (%zu prime cycles) of %zu codes, %zu unproven, %.1f s\n",
               t.period, t.proven, t.prime_cycles, t.codes, t.unproven, t.seconds);
}

int run_orbits(const OrbitsArgs& a) {
  const ExactReal d = positive("--d", a.d), r = positive("--r", a.r);
  if (a.bits < 64 || a.bits > 4096) throw InputError("--bits", std::to_string(a.bits), "must be in [64, 4096]");
  if (a.starts < 1 || a.starts > 100000)
    throw InputError("--starts", std::to_string(a.starts), "must be in [1, 100000]");
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  if (a.seed < 0) throw InputError("--seed", std::to_string(a.seed), "must be >= 0");
  OrbitOptions opt;
  opt.bits = a.bits;
  opt.starts = a.starts;
  opt.seed = static_cast<std::uint64_t>(a.seed);
  if (!a.code.empty()) {
    if (a.period_max != 0 || !a.out.empty())
      throw InputError("--code", a.code, "one code is printed: without --period-max and --out");
    return run_code(a, d, r, opt);
  }
  if (a.period_max < 2 || a.period_max > 16)
    throw InputError("--period-max", std::to_string(a.period_max), "must be in [2, 16]");
  if (a.out.empty()) throw InputError("--out", "", "a directory for orbits.csv and summary.json");
  RunDirectory dir(a.out, a.force);
  // DIR.checkpoint beside the target while the search runs: a killed search goes on from its last period
  std::filesystem::path checkpoint = RunDirectory::normalise(a.out);
  checkpoint += ".checkpoint";
  const OrbitSearch s = find_orbits(d, r, a.period_max, opt, a.threads, a.quiet ? nullptr : print_period, checkpoint);
  write_orbits(dir.file("orbits.csv").parent_path(), d, r, s, opt);
  dir.commit();
  std::filesystem::remove(checkpoint);
  if (!a.quiet)
    std::fprintf(stderr, "orbits: %zu proven in %.1f s on %d threads -> %s\n", s.orbits.size(), s.seconds, s.threads,
                 a.out.c_str());
  const CycleAverages e = cycle_averages(prime_cycles(s, opt), a.period_max).back();
  std::printf(
      "cycle expansion to period %d: entropy %.5f (from the count %.5f), Lyapunov %.5f a unit time, %.5f a "
      "collision, mean free path %.4f\n",
      e.order, e.entropy, e.entropy_count, e.lyapunov_time, e.lyapunov_collision, e.mean_free_path);
  return 0;
}

}  // namespace

Command add_orbits(CLI::App& app) {
  auto a = std::make_shared<OrbitsArgs>();
  CLI::App* sub = app.add_subcommand(
      "orbits", "Periodic orbits of the stadium: enumerated by code, found by Newton, proven by the Krawczyk test");
  sub->add_option("--period-max", a->period_max, "Every code of period 2 .. N (at most 16)");
  sub->add_option("--out", a->out, "Directory for orbits.csv and summary.json");
  sub->add_option("--code", a->code, "One code (letters T, R, B, L: top, right arc, bottom, left arc): its orbits");
  sub->add_option("--d", a->d, "Straight edge length, exact (default 2)");
  sub->add_option("--r", a->r, "Arc radius, exact (default 1)");
  sub->add_option("--bits", a->bits, "MPFR/MPFI precision of the refinement and the proof (default 160)");
  sub->add_option("--starts", a->starts, "Newton starts a code (default 48)");
  sub->add_option("--seed", a->seed, "Seed of the starts (default 1)");
  sub->add_option("--threads", a->threads, "OpenMP threads (default: all cores)");
  sub->add_flag("--force", a->force, "Replace an existing --out directory");
  sub->add_flag("--json", a->json_out, "--code: one JSON document on stdout");
  sub->add_flag("--no-progress", a->quiet, "No per-period lines on stderr");
  return {sub, [a] { return run_orbits(*a); }};
}

}  // namespace rotleak::cli
