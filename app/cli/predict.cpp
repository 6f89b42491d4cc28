// rotleak predict SCENE [--set key=value]... [--json]: the covering model's tail for a scene, in milliseconds
#include <cstdio>
#include <iostream>

#include "analysis/output/run_output.hpp"
#include "analysis/tail_model.hpp"
#include "cli/commands.hpp"
#include "io/scene_file.hpp"

namespace rotleak::cli {

namespace {

struct PredictArgs {
  std::string scene;
  std::vector<std::string> overrides;
  bool json_out = false;
};

int run_predict(const PredictArgs& a) {
  const Scene scene = load_scene(a.scene, a.overrides);
  require_stadium(scene, "rotleak predict");
  const TailPrediction p = predict_tail(scene);
  if (a.json_out) {
    std::cout << prediction_document(scene, p).dump(2) << "\n";
    return 0;
  }
  std::printf("%s: omega = %s, leak width %s, d = %s, r = %s, t_max = %g\n", a.scene.c_str(), scene.omega_text.c_str(),
              scene.width_text.c_str(), scene.d_text.c_str(), scene.r_text.c_str(), scene.t_max);
  std::fputs(prediction_text(p).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_predict(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  CLI::App* sub = app.add_subcommand(
      "predict", "The covering model's tail for a scene: whether it forms, its amplitude C and its end (no run)");
  sub->add_option("scene", a->scene, "Scene file (TOML)")->required();
  sub->add_option("--set", a->overrides, "Override a scene key (leak.omega=2/3)");
  sub->add_flag("--json", a->json_out, "Print the prediction as JSON (the fields of summary.json predicted.tail)");
  return {sub, [a] { return run_predict(*a); }};
}

}  // namespace rotleak::cli
