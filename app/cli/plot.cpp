// rotleak plot DIR: the package's plotter (python3 -m rotleak.plot) on a run, scan, shadow, covering
// or regimes directory.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "cli/commands.hpp"
#include "io/locations.hpp"
#include "numeric/input.hpp"

extern char** environ;

namespace rotleak::cli {

int run_plotter(const std::string& dir, bool quiet_stdout, const std::string& formats) {
  namespace fs = std::filesystem;
  // Debian's interpreter has python3-matplotlib; another python3 first on PATH may not.
  std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (const char* p = std::getenv("ROTLEAK_PYTHON")) python = p;
  // the package this rotleak ships first on PYTHONPATH, the caller's after it
  std::string pythonpath = "PYTHONPATH=" + python_dir().string();
  std::vector<std::string> env_s{pythonpath};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "PYTHONPATH=", 11) == 0)
      env_s[0] += ":" + std::string(*e + 11);
    else
      env_s.emplace_back(*e);
  std::vector<char*> envp;
  for (auto& e : env_s) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_s{python, "-m", "rotleak.plot", dir, "--format", formats};
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet_stdout) posix_spawn_file_actions_adddup2(&actions, 2, 1);
  const int spawned = posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return 127;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

int plot_after_run(const std::string& dir, bool quiet_stdout) {
  std::fflush(stdout);  // our lines first, then the plotter's
  int rc = 0;
  try {
    rc = run_plotter(dir, quiet_stdout);
  } catch (const std::exception& e) {  // no package found: say so, keep the output
    std::fprintf(stderr, "rotleak: %s\n", e.what());
    rc = 127;
  }
  if (rc != 0) {
    std::fprintf(stderr, "rotleak: plotting failed (exit %d); the output itself is complete\n", rc);
    return 1;
  }
  return 0;
}

Command add_plot(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto formats = std::make_shared<std::string>("png");
  CLI::App* sub = app.add_subcommand("plot",
                                     "Draw a run (P(t) with the fit, f_c), a scan, a shadow, a covering, a regimes "
                                     "search, a calibration or a certified sample: PNG, PDF or SVG, with captions");
  sub->add_option("dir", *dir,
                  "A directory rotleak wrote (simulate, scan, shadow, covering, regimes, calibrate, certify)")
      ->required();
  sub->add_option("--format", *formats, "png, pdf, svg or a comma list of them (png,pdf); default png");
  return {sub, [dir, formats] {
            if (!std::filesystem::is_directory(*dir))
              throw InputError("DIR", "\"" + *dir + "\"", "must be a directory rotleak wrote");
            return run_plotter(*dir, false, *formats);
          }};
}

}  // namespace rotleak::cli
