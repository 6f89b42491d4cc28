// rotleak covering --omega 2/3 [--omega ...] --delta 1e-7 [1e-9 ...] --lambda 0.01 [--d 2 --r 1] [--json] [--out DIR]
#include <cstdio>
#include <iostream>

#include "analysis/output/covering_output.hpp"
#include "cli/commands.hpp"
#include "io/files.hpp"
#include "numeric/input.hpp"

namespace rotleak::cli {

namespace {

struct CoveringArgs {
  CoveringRequest request;
  std::string out;
  int resolution = 10000;
  bool json_out = false, force = false, segments = false, plot = true;
};

int run_covering(const CoveringArgs& a) {
  if (a.resolution < 1 || a.resolution > 10000000)
    throw InputError("--resolution", std::to_string(a.resolution), "must be in [1, 10^7]");
  check_covering_request(a.request);  // before any output is staged
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);
  const CoveringOutcome c = compute_coverings(a.request);
  const std::vector<std::string>& labels = c.labels;
  const std::vector<Covering>& results = c.results;
  const json& doc = c.document;

  if (dir) {
    write_file_atomic(dir->file("f_L.csv"),
                      covering_profile_csv(labels, results, static_cast<std::size_t>(a.resolution)));
    if (a.segments)
      for (std::size_t i = 0; i < results.size(); ++i)
        write_file_atomic(dir->file("segments_" + std::to_string(i) + ".csv"), covering_segments_csv(results[i]));
    write_file_atomic(dir->file("summary.json"), doc.dump(2) + "\n");
    dir->commit();
  }
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
  } else {
    std::printf("MUPO covering: delta = %s, lambda = %s, d = %s, r = %s\n", c.delta_list.c_str(),
                a.request.lambda.c_str(), a.request.d.c_str(), a.request.r.c_str());
    std::fputs(covering_text(labels, results).c_str(), stdout);
  }
  return dir && a.plot ? plot_after_run(dir->final_path().string(), a.json_out) : 0;
}

}  // namespace

Command add_covering(CLI::App& app) {
  auto a = std::make_shared<CoveringArgs>();
  CLI::App* sub =
      app.add_subcommand("covering", "The MUPO covering f_L(s) of the leak during a bouncing-ball crossing");
  sub->add_option("--omega", a->request.omegas, "omega (exact; repeat or list several to draw them together)")
      ->required();
  sub->add_option("--delta", a->request.deltas,
                  "1 + delta = 1/sqrt(1 - p^2) (default 1e-7; several: each omega at each)");
  sub->add_option("--lambda", a->request.lambda, "leak width in s (default 0.01)");
  sub->add_option("--d", a->request.d, "straight edge length (default 2)");
  sub->add_option("--r", a->request.r, "arc radius (default 1)");
  sub->add_option("--out", a->out, "Directory for f_L.csv, summary.json and f_L.png");
  sub->add_option("--resolution", a->resolution, "Bins of the exported f_L profile (default 10000)");
  sub->add_flag("--segments", a->segments, "Also export the exact breakpoints (segments_K.csv)");
  sub->add_flag("--force", a->force, "Replace an existing output directory");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_covering(*a); }};
}

}  // namespace rotleak::cli
