#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "run/pipeline.hpp"

namespace rotleak::cli {

/// A subcommand: its CLI11 node and the function that runs it once parsed (returns the exit status).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};
Command add_simulate(CLI::App& app);
Command add_plot(CLI::App& app);
Command add_omega(CLI::App& app);
Command add_covering(CLI::App& app);
Command add_shadow(CLI::App& app);
Command add_lyapunov(CLI::App& app);
Command add_audit(CLI::App& app);
Command add_certify(CLI::App& app);
Command add_verify(CLI::App& app);
Command add_scan(CLI::App& app);
Command add_fit(CLI::App& app);
Command add_regimes(CLI::App& app);
Command add_merge(CLI::App& app);
Command add_calibrate(CLI::App& app);
Command add_predict(CLI::App& app);
Command add_orbits(CLI::App& app);

/// The run options of a command that runs a scan (scan, calibrate): --threads (>= 0), --engine, the
/// progress line on a terminal and the per-point status lines unless --no-progress.
void scan_run_options(int threads, const std::string& engine, bool no_progress, RunOptions& run, Note& note);

/// Exit statuses: 0 done, 1 failed while running, 2 bad input.
inline constexpr int kExitBadInput = 2;

/// `python3 -m rotleak.plot DIR` (Debian's python3, matplotlib) with the installed or built package
/// first on PYTHONPATH (io/locations.hpp): it draws whatever DIR holds (a run, a scan, a shadow, a
/// covering, a regimes search). Returns its exit status. With quiet_stdout its stdout goes to stderr
/// (stdout then carries one JSON document only). `formats`: png, pdf, svg or a comma list (the plotter checks it).
int run_plotter(const std::string& dir, bool quiet_stdout = false, const std::string& formats = "png");
/// The plots after a completed command: stdout flushed first, a failure reported (exit 1), the output kept.
int plot_after_run(const std::string& dir, bool quiet_stdout = false);

}  // namespace rotleak::cli
