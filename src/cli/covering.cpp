// rotleak covering --omega 2/3 [--omega ...] --delta 1e-7 [1e-9 ...] --lambda 0.01 [--d 2 --r 1] [--json] [--out DIR]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/covering_output.hpp"
#include "io/files.hpp"
#include "numeric/input.hpp"

namespace rotleak::cli {

namespace {

struct CoveringArgs {
  std::vector<std::string> omegas;
  std::vector<std::string> deltas{"1e-7"};
  std::string lambda = "0.01", d = "2", r = "1";
  std::string out;
  int resolution = 10000;
  bool json_out = false, force = false, segments = false, plot = true;
};

/// The exact inputs, each checked against its range (before any output is staged).
CoveringInput parse_input(const CoveringArgs& a) {
  if (a.omegas.empty()) throw InputError("--omega", "(none)", "give at least one omega");
  if (a.resolution < 1 || a.resolution > 10000000)
    throw InputError("--resolution", std::to_string(a.resolution), "must be in [1, 10^7]");
  auto exact = [](const std::string& key, const std::string& text, bool open_unit) {
    const ExactReal v = parse_exact_input(key, text);
    if (v.sign() <= 0 || (open_unit && (v - ExactReal::parse("1")).sign() >= 0))
      throw InputError(key, "\"" + text + "\"", open_unit ? "must be in (0, 1)" : "must be > 0");
    return v;
  };
  CoveringInput in;
  for (const std::string& delta : a.deltas) in.delta = exact("--delta", delta, true);
  in.lambda = exact("--lambda", a.lambda, true);
  in.d = exact("--d", a.d, false);
  in.r = exact("--r", a.r, false);
  return in;
}

int run_covering(const CoveringArgs& a) {
  CoveringInput in = parse_input(a);
  std::vector<ExactReal> omegas;
  for (const auto& o : a.omegas) omegas.push_back(parse_exact_input("--omega", o));
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);

  // every omega at every delta; with several deltas each entry is labelled "omega @ delta D"
  std::vector<Covering> results;
  std::vector<std::string> labels;
  std::string delta_list;
  for (const std::string& delta : a.deltas) delta_list += (delta_list.empty() ? "" : ",") + delta;
  for (std::size_t k = 0; k < omegas.size(); ++k)
    for (const std::string& delta : a.deltas) {
      in.omega = omegas[k];
      in.delta = parse_exact_input("--delta", delta);
      try {
        results.push_back(mupo_covering(in));
      } catch (const std::invalid_argument& e) {
        throw InputError("--delta", "\"" + delta + "\"", e.what());
      }
      labels.push_back(a.deltas.size() > 1 ? a.omegas[k] + " @ delta " + delta : a.omegas[k]);
    }
  json doc = covering_document({delta_list, a.lambda, a.d, a.r}, labels, results);
  if (a.deltas.size() > 1)  // each entry names its delta
    for (std::size_t i = 0; i < labels.size(); ++i) doc["covering"][i]["delta"] = a.deltas[i % a.deltas.size()];

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
    std::printf("MUPO covering: delta = %s, lambda = %s, d = %s, r = %s\n", delta_list.c_str(), a.lambda.c_str(),
                a.d.c_str(), a.r.c_str());
    std::fputs(covering_text(labels, results).c_str(), stdout);
  }
  return dir && a.plot ? plot_after_run(dir->final_path().string(), "plot_covering.py", a.json_out) : 0;
}

}  // namespace

Command add_covering(CLI::App& app) {
  auto a = std::make_shared<CoveringArgs>();
  CLI::App* sub =
      app.add_subcommand("covering", "The MUPO covering f_L(s) of the leak during a bouncing-ball crossing");
  sub->add_option("--omega", a->omegas, "omega (exact; repeat or list several to draw them together)")->required();
  sub->add_option("--delta", a->deltas, "1 + delta = 1/sqrt(1 - p^2) (default 1e-7; several: each omega at each)");
  sub->add_option("--lambda", a->lambda, "leak width in s (default 0.01)");
  sub->add_option("--d", a->d, "straight edge length (default 2)");
  sub->add_option("--r", a->r, "arc radius (default 1)");
  sub->add_option("--out", a->out, "Directory for f_L.csv, summary.json and f_L.png");
  sub->add_option("--resolution", a->resolution, "Bins of the exported f_L profile (default 10000)");
  sub->add_flag("--segments", a->segments, "Also export the exact breakpoints (segments_K.csv)");
  sub->add_flag("--force", a->force, "Replace an existing output directory");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_covering(*a); }};
}

}  // namespace rotleak::cli
