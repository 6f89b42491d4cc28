#include "run/pipeline.hpp"

#include <utility>

#include "io/files.hpp"
#include "io/run_output.hpp"
#include "io/scene_file.hpp"
#include "verify/auto_tier.hpp"

namespace rotleak {

RunSummary run_scene(Scene scene, RunOptions options, const std::string& engine, const Note& note) {
  std::optional<std::string> choice;
  if (scene.tier.automatic()) {
    if (note) note("[rotleak] run.tier = auto: auditing float, double, long double on this scene...");
    TierChoice c = choose_tier(scene, options.threads);
    scene.tier = c.tier;
    choice = std::move(c.reason);
  }
  options.engine = engine_from_name("--engine", engine, scene);
  RunSummary s = summarise(scene, run_ensemble(scene, options));
  s.tier_choice = std::move(choice);
  return s;
}

SimulateOutcome simulate(const SimulateRequest& req) {
  const Scene scene = load_scene(req.scene_path, req.overrides);
  check_resources(scene, req.run.threads);                                       // before any directory is made
  if (!scene.tier.automatic()) engine_from_name("--engine", req.engine, scene);  // a bad engine fails before any work
  RunDirectory dir(req.out, req.force);                                          // validated and staged before any work
  SimulateOutcome out;
  out.summary = run_scene(scene, req.run, req.engine, req.note);
  out.document = write_run(dir, out.summary);
  out.dir = dir.final_path();
  return out;
}

}  // namespace rotleak
