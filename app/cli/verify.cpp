// rotleak verify [--tier T|all]... [--engine E|all]... [--orbit CODE|default|none]... [--reference DIR] [--ignore-bits]
// [--json] rotleak verify --regenerate [--reference DIR]
#include <cstdio>
#include <ctime>
#include <iostream>

#include "cli/commands.hpp"
#include "io/json.hpp"
#include "io/locations.hpp"
#include "io/progress.hpp"
#include "numeric/input.hpp"
#include "numeric/tier.hpp"
#include "verify/reference.hpp"
#include "version.hpp"

namespace rotleak::cli {

namespace {

/// The reference set rotleak ships: DATA/trajectories (io/locations.hpp).
std::string default_reference() { return (data_dir() / "trajectories").string(); }

struct VerifyArgs {
  std::vector<std::string> tiers{"all"}, engines{"all"}, orbits{"default"};
  std::string reference;  ///< empty: default_reference()
  bool json_out = false, ignore_bits = false, regenerate = false;
  int threads = 0;
};

std::string provenance(const std::string& dir, bool default_dir) {
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  json p;
  p["command"] = "rotleak verify --regenerate" + (default_dir ? std::string() : " --reference " + dir);
  p["version"] = std::string(kVersion) + " (" + kGitDescribe + ")";
  p["compiler"] = __VERSION__;
  p["date"] = date;
  p["certification"] = "MPFI, from " + std::to_string(kReferenceStartBits) +
                       " bits doubled until every decision of the first K collisions is proven (bits per case)";
  p["gains"] = "MPFR runs at the error model's gain_bits against the certified values";
  return p.dump();
}

int regenerate(VerifyArgs a) {
  const bool default_dir = a.reference.empty();
  if (default_dir) a.reference = default_reference();
  const auto specs = read_case_specs(a.reference + "/cases.toml");
  std::optional<ReferenceSet> before;
  try {
    before = read_reference(a.reference);
  } catch (const std::runtime_error&) {
    // no earlier set (or an unreadable one): everything is new
  }
  const ReferenceSet after = build_reference(
      specs, provenance(a.reference, default_dir), a.threads,
      [](std::size_t d, std::size_t n) { std::fprintf(stderr, "\rverify: %zu of %zu cases certified", d, n); });
  std::fprintf(stderr, "\n");
  write_reference(a.reference, after);
  const auto lines = before ? compare_references(*before, after) : std::vector<std::string>{"(no earlier reference)"};
  std::printf("wrote %s: %zu cases\n", a.reference.c_str(), after.cases.size());
  if (lines.empty()) std::printf("no change against the earlier reference\n");
  for (const auto& l : lines) std::printf("  %s\n", l.c_str());
  return 0;
}

int run_verify(const VerifyArgs& a) {
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  if (a.regenerate) return regenerate(a);
  VerifyOptions opt;
  opt.threads = a.threads;
  opt.check_bits = !a.ignore_bits;
  opt.tiers.clear();
  for (const std::string& t : a.tiers) {
    if (t == "all") {
      for (const auto& n : reference_tiers()) opt.tiers.push_back(n);
      opt.tiers.push_back("mpfi:256");
      continue;
    }
    const auto tier = Tier::parse(t);
    if (!tier || tier->automatic()) throw InputError("--tier", t, "allowed: all, " + tier_names_allowed(true));
    opt.tiers.push_back(t);
  }
  for (const std::string& e : a.engines) {
    if (e == "all" || e == "scalar")
      opt.engines.insert(opt.engines.end(), {{Engine::scalar, false}, {Engine::scalar, true}});
    if (e == "all" || e == "simd") opt.engines.insert(opt.engines.end(), {{Engine::simd, false}, {Engine::simd, true}});
    if (e != "all" && e != "scalar" && e != "simd" && e != "none")
      throw InputError("--engine", e, "allowed: all, scalar, simd, none");
  }
  opt.orbit_codes.clear();
  for (const std::string& o : a.orbits) {
    if (o == "default") {
      for (const auto& c : default_orbit_codes()) opt.orbit_codes.push_back(c);
    } else if (o != "none") {
      parse_orbit_code(o, "--orbit");
      opt.orbit_codes.push_back(o);
    }
  }
  const std::string reference = a.reference.empty() ? default_reference() : a.reference;
  const ReferenceSet set = read_reference(reference);
  VerifyReport rep = verify_reference(set, opt);
  rep.reference_dir = reference;
  if (a.json_out)
    std::cout << verify_json(rep).dump(2) << "\n";
  else
    std::fputs(verify_text(rep).c_str(), stdout);
  return rep.pass ? 0 : 1;
}

}  // namespace

Command add_verify(CLI::App& app) {
  auto a = std::make_shared<VerifyArgs>();
  CLI::App* sub = app.add_subcommand(
      "verify", "Replay the certified reference trajectories through every tier and engine (exit 1 on a shortfall)");
  sub->add_option(
      "--tier", a->tiers, "A tier, or all (repeatable; default all: " + [] {
        std::string s;
        for (const auto& n : reference_tiers()) s += n + ",";
        return s + "mpfi:256)";
      }());
  sub->add_option("--engine", a->engines, "scalar, simd, all or none (repeatable; default all)");
  sub->add_option("--orbit", a->orbits,
                  "A periodic orbit's code replayed through the point tiers (repeatable; default: default, the "
                  "proven orbits TRBL, RRL, RRLRLLB, TRRBLLTRBL; none: no orbit)");
  sub->add_option(
      "--reference", a->reference,
      "Reference directory (default: DATA/trajectories, DATA as $ROTLEAK_DATA or the installed share/rotleak/data)");
  sub->add_flag("--ignore-bits", a->ignore_bits,
                "Check the error model only, not bit identity with the build that made the reference");
  sub->add_flag("--regenerate", a->regenerate, "Rebuild the reference from DIR/cases.toml and list what changed");
  sub->add_option("--threads", a->threads, "Threads (default: all cores)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_verify(*a); }};
}

}  // namespace rotleak::cli
