// rotleak <command>: a thin shell over the library. Bad input: one line on stderr, exit status 2.
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "io/json.hpp"
#include "numeric/input.hpp"
#include "run/team.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "version.hpp"

namespace {

/// What this build and this CPU run, for --version: a cluster user checks it on each kind of node.
std::string version_line() {
  const int lanes = rotleak::simd::widest_lanes();
  return std::string(rotleak::kVersion) + " (" + rotleak::kGitDescribe +
         "); MPI: " + (rotleak::built_with_mpi() ? "yes" : "no") + "; vectorised kernel: " +
         (lanes == 8   ? "8 lanes (AVX-512)"
          : lanes == 4 ? "4 lanes (AVX2)"
                       : "none (this CPU lacks AVX2 and FMA: the scalar core runs)") +
         (std::getenv("ROTLEAK_SIMD_LANES") ? std::string("; ROTLEAK_SIMD_LANES = ") + std::getenv("ROTLEAK_SIMD_LANES")
                                            : std::string());
}

/// Every command, its options taking one value per use where it has positional arguments (`--set a=1
/// --set b=2`): a repeatable option that took every following word swallowed the scene (`--set
/// leak.omega=2/3 SCENE` said "scene is required"). Commands without positionals keep lists (`covering
/// --omega 2/3 1e-4`).
std::vector<rotleak::cli::Command> add_commands(CLI::App& app) {
  std::vector<rotleak::cli::Command> commands{
      rotleak::cli::add_simulate(app), rotleak::cli::add_plot(app),      rotleak::cli::add_omega(app),
      rotleak::cli::add_covering(app), rotleak::cli::add_shadow(app),    rotleak::cli::add_lyapunov(app),
      rotleak::cli::add_audit(app),    rotleak::cli::add_certify(app),   rotleak::cli::add_verify(app),
      rotleak::cli::add_scan(app),     rotleak::cli::add_fit(app),       rotleak::cli::add_regimes(app),
      rotleak::cli::add_merge(app),    rotleak::cli::add_calibrate(app), rotleak::cli::add_predict(app),
      rotleak::cli::add_orbits(app)};
  for (const auto& c : commands) {
    const auto positional = [](CLI::Option* opt) { return opt->get_positional(); };
    if (c.app->get_options(positional).empty()) continue;
    for (CLI::Option* o : c.app->get_options([](CLI::Option* opt) { return !opt->get_positional(); }))
      o->allow_extra_args(false);
  }
  return commands;
}

/// Runs the parsed command. Under mpirun only simulate, scan, calibrate, audit and certify --sample share their
/// work between ranks; any other command would run K times over and race on its files.
int run_parsed(const std::vector<rotleak::cli::Command>& commands, const rotleak::Team& team) {
  for (const auto& c : commands)
    if (c.app->parsed()) {
      const std::string name = c.app->get_name();
      if (team.size() > 1 && name != "simulate" && name != "scan" && name != "audit" && name != "calibrate" &&
          name != "certify")
        throw rotleak::InputError("mpirun -np", std::to_string(team.size()),
                                  "only `rotleak simulate`, `scan`, `calibrate`, `audit` and `certify --sample` run "
                                  "under MPI; run "
                                  "`rotleak " +
                                      name + "` as one process (its runs use all cores of the machine)");
      return c.run();
    }
  return 1;
}

/// A failure in one line of readable length, whatever the message quotes (an exact value can be 100 KB).
int report_failure(const std::exception& e, rotleak::Team& team) {
  std::string what = e.what();
  for (char& c : what)
    if (c == '\n') c = ' ';
  if (what.size() > 300) what = what.substr(0, 240) + "... (" + std::to_string(what.size()) + " characters)";
  std::cerr << "rotleak: failed: " << what << "\n";
  team.abort(1);  // other ranks may wait in a collective
  return 1;
}

/// Refuses an argument that is not valid UTF-8 (a file name in another encoding), its odd bytes shown as \xNN.
/// Every command writes its arguments and paths into JSON files, which are UTF-8: such an argument once
/// simulated 4.3 s and then failed in the writer with a raw JSON exception, keeping nothing.
void check_utf8_arguments(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    try {
      (void)nlohmann::json(std::string(argv[i])).dump();
    } catch (const nlohmann::json::type_error&) {
      std::string shown;
      for (const char* c = argv[i]; *c; ++c) {
        const auto b = static_cast<unsigned char>(*c);
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02x", b);
        shown += b < 0x80 ? std::string(1, *c) : std::string(hex);
      }
      throw rotleak::InputError("argument", "\"" + shown + "\"",
                                "is not valid UTF-8; rotleak writes its arguments and paths into JSON files, which "
                                "must be UTF-8: rename the file or directory");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // under mpirun: MPI is initialised here (it may take its own arguments), finalised at the end
  const std::unique_ptr<rotleak::Team> team = rotleak::join_team(&argc, &argv);
  CLI::App app{"rotleak: open chaotic billiards with a rotating leak"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_line());
  const std::vector<rotleak::cli::Command> commands = add_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "rotleak: error: " << e.what() << " (see rotleak --help)\n";
    return rotleak::cli::kExitBadInput;
  }
  try {
    check_utf8_arguments(argc, argv);
    return run_parsed(commands, *team);
  } catch (const rotleak::QuietExit& e) {
    return e.code;
  } catch (const rotleak::InputError& e) {
    // every rank reads the same arguments: rank 0 speaks for them (a rank's own trouble is printed
    // where it is found)
    if (team->rank() == 0) std::cerr << "rotleak: error: " << e.what() << "\n";
    return rotleak::cli::kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr
        << "rotleak: failed: out of memory (the inputs passed the memory estimate; try fewer particles or threads)\n";
    return 1;
  } catch (const std::exception& e) {
    return report_failure(e, *team);
  }
}
