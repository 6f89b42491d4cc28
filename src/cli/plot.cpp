// rotleak plot DIR: draws survival.png (log-log and semi-log with the kappa fit) and fc.png.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "cli/commands.hpp"
#include "numeric/input.hpp"
#include "version.hpp"

extern char** environ;

namespace rotleak::cli {

int run_plot_script(const std::string& name, const std::string& dir, bool quiet_stdout) {
  namespace fs = std::filesystem;
  std::string script = std::string(kSourceDir) + "/scripts/" + name;
  if (const char* s = std::getenv("ROTLEAK_SCRIPTS")) script = std::string(s) + "/" + name;
  // Debian's interpreter has python3-matplotlib; another python3 first on PATH may not.
  std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (const char* p = std::getenv("ROTLEAK_PYTHON")) python = p;
  std::vector<std::string> argv_s{python, script, dir};
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet_stdout) posix_spawn_file_actions_adddup2(&actions, 2, 1);
  const int spawned = posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return 127;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

int draw_plots(const std::string& run_dir) {
  namespace fs = std::filesystem;
  if (fs::exists(fs::path(run_dir) / "scan.json")) return run_plot_script("plot_scan.py", run_dir);
  if (!fs::exists(fs::path(run_dir) / "summary.json"))
    throw InputError("DIR", "\"" + run_dir + "\"",
                     "must be a complete run directory (with summary.json) or a scan directory (with scan.json)");
  return run_plot_script("plot_run.py", run_dir);
}

int plot_after_run(const std::string& run_dir, const std::string& script, bool quiet_stdout) {
  std::fflush(stdout);  // our lines first, then the plotter's
  const int rc = run_plot_script(script, run_dir, quiet_stdout);
  if (rc != 0) {
    std::fprintf(stderr, "rotleak: plotting failed (exit %d); the run itself is complete\n", rc);
    return 1;
  }
  return 0;
}

Command add_plot(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("plot", "Draw P(t) (log-log and semi-log, with the fit) and f_c(s) as PNG");
  sub->add_option("dir", *dir, "Run directory (rotleak simulate) or scan directory (rotleak scan)")->required();
  return {sub, [dir] { return draw_plots(*dir); }};
}

}  // namespace rotleak::cli
