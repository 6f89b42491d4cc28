#include "analysis/output/run_output.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <string_view>

#include "io/scene_file.hpp"
#include "io/text.hpp"
#include "numeric/input.hpp"
#include "sim/model/sampling.hpp"
#include "version.hpp"

namespace rotleak {

namespace {

/// The grid indices summary.json reports a curve at: t_max / 8, / 4, / 2 and t_max.
std::vector<std::size_t> report_points(const SurvivalCurve& curve) {
  const std::size_t n = curve.t.size();
  return {(n - 1) / 8, (n - 1) / 4, (n - 1) / 2, n - 1};
}

}  // namespace

json sampling_json(const Scene& scene, const SurvivalCurve& curve) {
  json j = {{"scheme", to_string(scene.sampling.kind)}};
  if (!scene.sampling.weighted()) return j;
  j["eps"] = scene.sampling.eps;
  j["p_range"] = {scene.sampling.p_min, scene.sampling.p_max};
  j["max_weight"] = scene.sampling.max_weight();
  j["ride"] = scene.sampling.ride;
  json bands = json::array();
  if (scene.sampling.ride > 0 && scene.init == InitKind::birkhoff)
    for (const RidingBand& b : riding_bands(scene))
      bands.push_back({{"rational", std::to_string(b.a) + "/" + std::to_string(b.b)},
                       {"eta", b.eta},
                       {"p", b.p},
                       {"p_range", {b.lo, b.hi}}});
  j["riding_bands"] = bands;
  // effective sample size (sum w)^2 / sum w^2 of the survivors at a few times
  json ess = json::array();
  for (std::size_t i : report_points(curve)) {
    ess.push_back({{"t", curve.t[i]},
                   {"survivors", curve.survivors[i]},
                   {"P", curve.P(i)},
                   {"P_err", curve.P_err(i)},
                   {"effective_survivors", curve.effective(i)}});
  }
  j["effective_survivors"] = ess;
  return j;
}

json start_splitting_json(const Scene& scene, const IcSplitRun& run, const SurvivalCurve& curve) {
  const StartSplitSpec& g = scene.start_splitting;
  std::uint64_t proposals = 0, accepted = 0, stuck = 0;
  for (const IcReplicate& r : run.replicates) proposals += r.proposals, accepted += r.accepted, stuck += r.stuck;
  // the scene's keys as the scene writes them (but on, and p and edges, which the stratum names)
  json j = scene_json(scene).at("start_splitting");
  for (const char* k : {"on", "p", "edges"}) j.erase(k);
  j.update(json{{"starts", scene.particles},
                {"stratum", {{"p", {g.p_lo, g.p_hi}}, {"edges", g.edges}, {"share", run.stratum.share()}}},
                {"levels", run.levels},
                {"factors", run.factors},
                {"pilot_collisions", run.pilot_collisions},
                {"proposals", proposals},
                {"accepted", accepted},
                {"stuck", stuck}});
  // each level's halvings and whether double resolves its moves; past the first that it does not, P is the double
  // clock's (null: every level resolved)
  json windows = json::array();
  for (std::size_t k = 0; k < run.scales.size(); ++k) {
    const IcScales& sc = run.scales[k];
    const int bits = k >= run.handover ? ic_tier_bits(run.spec.deep_tier) : 53;
    json w = {{"halvings", {sc.lo, sc.halvings}}, {"resolved", sc.resolved(run.stratum, bits)}};
    // its chains (stage k + 1 of the replicates that reached it): the share of proposals accepted, and the fewest and
    // mean distinct stage-0 starts behind the stage
    const IcSplitRun::LevelChains c = run.chains(k);
    w["acceptance"] =
        c.proposals ? json(static_cast<double>(c.accepted) / static_cast<double>(c.proposals)) : json(nullptr);
    w["ancestors"] = c.reached ? json{{"fewest", c.fewest}, {"mean", c.mean_ancestors}} : json(nullptr);
    windows.push_back(w);
  }
  j["windows"] = windows;
  // the hand-over to the deep clock: its level (null: none), the starts it timed again there and those it dropped
  std::uint64_t handed = 0, disagreed = 0;
  for (const IcReplicate& r : run.replicates) handed += r.handed_over, disagreed += r.handover_disagreed;
  j["handover"] = {{"level", run.handover < run.levels.size() ? json(run.levels[run.handover]) : json(nullptr)},
                   {"timed_again", handed},
                   {"disagreed", disagreed}};
  const double from = run.unresolved_from();
  j["unresolved_from"] = std::isfinite(from) ? json(from) : json(nullptr);
  json at = json::array();
  for (std::size_t i : report_points(curve))
    at.push_back({{"t", curve.t[i]},
                  {"P", curve.P(i)},
                  {"P_err", curve.P_err(i)},
                  {"replicates_nonzero", curve.replicates_nonzero[i]},
                  {"states_alive", curve.survivors[i]}});
  j["at"] = at;
  return j;
}

json splitting_json(const Scene& scene, const Tally& tally, const SurvivalCurve& curve) {
  const auto& t = tally.as<LinesEstimator>();
  json j = {{"rule", "chaotic"},
            {"split_every", scene.splitting.every},
            {"split_delta", scene.splitting.delta},
            {"split_cap", scene.splitting.cap},
            {"levels", t.levels},
            {"splits", t.splits},
            {"roulette_removed", t.culls},
            {"max_population", t.max_population},
            {"max_line", t.max_line}};
  // lines alive and the effective number of lines at a few times, and the deepest resolved P
  json at = json::array();
  for (std::size_t i : report_points(curve)) {
    at.push_back({{"t", curve.t[i]},
                  {"lines_alive", curve.lines_alive[i]},
                  {"members", curve.survivors[i]},
                  {"P", curve.P(i)},
                  {"P_err", curve.P_err(i)},
                  {"effective_lines", curve.effective(i)},
                  {"unsplit_lines", curve.unsplit_lines.empty() ? json(nullptr) : json(curve.unsplit_lines[i])},
                  {"unsplit_P", curve.unsplit_P.empty() ? json(nullptr) : json(curve.unsplit_P[i])},
                  {"bounded", p_bounded(curve, i)}});
  }
  j["lines"] = at;
  json groups = json::array();
  for (const SurvivalCurve::UnsplitGroup& k : curve.unsplit)
    if (k.allowance) {
      // the group's weight range: from its lightest class's lower end to its heaviest's upper (null: none)
      const int lightest = k.classes.back(), heaviest = k.classes.front();
      groups.push_back({{"weights",
                         {lightest == kUnsplitClasses - 1 ? 0.0 : std::ldexp(1.0, -3 * lightest - 2),
                          heaviest == 0 ? json(nullptr) : json(std::ldexp(1.0, -3 * heaviest + 1))}},
                        {"reliable_until", k.reliable_until},
                        {"rate_from", k.rate_from},
                        {"decay_rate", k.decay_rate},
                        {"typical_weight", k.typical_weight}});
    }
  j["unsplit_allowance"] =
      groups.empty() ? json(nullptr)
                     : json{{"unresolved_from", nullable(curve.allowance_unresolved_from)}, {"groups", groups}};
  std::size_t deepest = 0;
  for (std::size_t i = 0; i < curve.t.size(); ++i)
    if (curve.P(i) > 0 && curve.P(i) < curve.P(deepest)) deepest = i;
  j["smallest_P"] = {{"t", curve.t[deepest]},
                     {"P", curve.P(deepest)},
                     {"P_err", curve.P_err(deepest)},
                     {"lines_alive", curve.lines_alive[deepest]}};
  return j;
}

namespace {

json kappa_json(const KappaFit& kappa) {
  json k = {{"value", kappa.ok ? json(kappa.value) : json(nullptr)},
            {"error", kappa.std_error},
            {"window", {kappa.from, kappa.to}},
            {"points", kappa.points},
            {"log_amplitude", kappa.log_amplitude},
            {"method", kappa.method}};
  json family = json::array();
  for (const auto& m : kappa.window_family) family.push_back({{"window", {m.from, m.to}}, {"value", m.value}});
  k["window_systematic"] = nullable(kappa.window_systematic);
  k["window_family"] = family;
  return k;
}

json alpha_json(const AlphaResult& alpha, const AlphaFromAmplitude& from_amplitude) {
  json a = {{"value", nullable(alpha.value)},
            {"error", alpha.value ? json(alpha.std_error) : json(nullptr)},
            {"systematic", nullable(alpha.systematic)},
            {"shift_factor", alpha.value ? json(alpha.shift_factor) : json(nullptr)},
            {"uniform_reach", nullable(alpha.uniform_reach)},
            {"upper_bound", nullable(alpha.upper_bound)},
            {"crossing_time", alpha.value ? json(alpha.crossing_time) : json(nullptr)},
            {"factor", alpha.factor},
            {"sigma", alpha.sigma},
            {"min_survivors", alpha.min_survivors},
            {"resolved_until", alpha.resolved_until},
            {"bound_until", alpha.value || alpha.crossing_not_significant ? json(nullptr) : json(alpha.bound_until)},
            {"note", alpha.note}};
  a["from_amplitude"] = from_amplitude.value ? json{{"value", *from_amplitude.value},
                                                    {"error", from_amplitude.std_error},
                                                    {"crossing_time", from_amplitude.crossing_time},
                                                    {"note", from_amplitude.note}}
                                             : json(nullptr);
  return a;
}

json amplitude_json(const TailAmplitude& am) {
  return {{"value", nullable(am.value)},
          {"error", am.value ? json(am.std_error) : json(nullptr)},
          {"systematic", am.value ? json(am.drift) : json(nullptr)},
          {"from", am.from > 0 ? json(am.from) : json(nullptr)},
          {"to", am.from > 0 ? json(am.to) : json(nullptr)},
          {"points", am.points},
          {"height", am.from > 0 ? json(am.height) : json(nullptr)},
          {"height_error", am.from > 0 ? json(am.height_error) : json(nullptr)},
          {"slope", am.value || am.slope_error > 0 ? json(am.slope) : json(nullptr)},
          {"slope_error", am.value || am.slope_error > 0 ? json(am.slope_error) : json(nullptr)},
          {"note", am.note}};
}

json tail_json(const TailClass& tc, const TailAmplitude& amplitude) {
  json t = {{"class", tc.tail},
            {"regime", tc.regime},
            {"tail_end", nullable(tc.tail_end)},
            {"tail_end_range",
             tc.tail_end_range ? json::array({tc.tail_end_range->first, tc.tail_end_range->second}) : json(nullptr)},
            {"end_exponent", tc.end_exponent},
            {"resolve_particles", nullable(tc.resolve_particles)},
            {"rule", tc.note}};
  t["near_rational"] =
      tc.near ? json{{"rational", tc.near->rational}, {"eps", tc.near->eps}, {"omega_near", tc.near->omega_rational}}
              : json(nullptr);
  t["amplitude"] = amplitude_json(amplitude);
  return t;
}

}  // namespace

void put_fits(json& s, const RunSummary& r) {
  const TailFit& tail = r.tail;
  s["kappa"] = kappa_json(r.kappa);
  s["alpha"] = alpha_json(r.alpha, r.alpha_c);
  s["tail_exponent"] = {{"value", nullable(tail.z)},      {"error", tail.z ? json(tail.std_error) : json(nullptr)},
                        {"window", {tail.from, tail.to}}, {"points", tail.points},
                        {"method", tail.method},          {"note", tail.note}};
  s["tail"] = tail_json(r.tail_class, r.amplitude);
  json jumps = json::array();
  for (const RateJump& j : r.rate_jumps)
    jumps.push_back({{"t", j.t}, {"rate_before", j.rate_before}, {"rate_after", j.rate_after}});
  s["rate_jumps"] = jumps;
  s["predicted"] = {{"tau1", nullable(r.leak_times.tau1)},
                    {"tau2", nullable(r.leak_times.tau2)},
                    {"omega_sweep", r.leak_times.omega_sweep}};
  s["predicted"]["tail"] = r.prediction ? prediction_json(*r.prediction) : json(nullptr);
}

void put_table(json& s, const RunSummary& r) {
  const Scene& scene = r.scene;
  const TableSpec t = table_spec(scene);
  s["table"] = {{"kind", t.name},
                {"loops", t.loops.size()},
                {"area", t.area.to_double()},
                {"perimeter", t.perimeter.to_double()},
                {"mean_free_path", std::numbers::pi * t.area.to_double() / t.perimeter.to_double()},
                {"small_hole_rate", small_hole_rate(scene)}};
  const std::vector<LeakSpec> specs = leak_specs(scene);
  const Tally& tally = r.result.tally;
  const double n = static_cast<double>(scene.particles);
  json leaks = json::array();
  for (std::size_t j = 0; j < specs.size(); ++j) {
    const std::uint64_t escaped = tally.leak_escaped(j);
    const double f = static_cast<double>(escaped) / n;
    const bool listed = !scene.leaks.empty();
    leaks.push_back({{"loop", specs[j].loop},
                     {"width", listed ? scene.leaks[j].width.text : scene.width_text},
                     {"start", listed ? scene.leaks[j].start.text : scene.start_text},
                     {"omega", listed ? scene.leaks[j].omega.text : scene.omega_text},
                     {"escaped", escaped},
                     {"fraction", f},
                     {"fraction_error", std::sqrt(f * (1 - f) / n)}});
  }
  s["leaks"] = leaks;
}

json execution_json(json fields) {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  json e = {{"rotleak", {{"version", kVersion}, {"git", kGitDescribe}}}, {"host", std::string(host)}};
  for (auto it = fields.begin(); it != fields.end(); ++it) e[it.key()] = it.value();
  return e;
}

json summary_json(const RunSummary& r, const std::vector<std::string>& files) {
  const Scene& scene = r.scene;
  json s;
  json how = {{"engine", to_string(r.result.engine)}};
  if (r.result.simd_lanes > 0) how["simd_lanes"] = r.result.simd_lanes;  // 4: AVX2, 8: AVX-512 (same bits)
  how["threads"] = r.result.threads;                                     // per rank
  how["ranks"] = r.result.ranks;
  how["wall_seconds"] = r.result.wall_seconds;
  how["collisions_per_second"] = r.collisions_per_second();
  s["execution"] = execution_json(std::move(how));
  s["command"] = "simulate";
  s["schema"] = kRunSchema;
  s["scene"] = scene_json(scene);
  s["seed"] = scene.seed;
  s["tier"] = to_string(scene.tier);
  if (r.tier_choice)
    s["tier_choice"] = {{"requested", "auto"}, {"chosen", to_string(scene.tier)}, {"reason", *r.tier_choice}};
  s["precision_warning"] = nullable(r.precision_warning);
  s["particles"] = scene.particles;
  if (r.result.of != 0)  // a shard: ids [first, end) of a run of `of` particles (rotleak merge)
    s["ids"] = {{"first", r.result.first_id}, {"end", r.result.first_id + scene.particles}, {"of", r.result.of}};
  s["collisions"] = r.result.tally.collisions;
  s["escaped"] = r.result.tally.escaped;
  s["survivors_at_t_max"] = r.result.tally.survived;
  s["stuck"] = r.result.tally.stuck;
  s["sampling"] = sampling_json(scene, r.curve);
  if (scene.on_table()) put_table(s, r);
  if (r.curve.lines) s["splitting"] = splitting_json(scene, r.result.tally, r.curve);
  if (r.start_splitting) s["start_splitting"] = start_splitting_json(scene, *r.start_splitting, r.curve);
  put_fits(s, r);
  s["files"] = files;
  return s;
}

namespace {

/// The riding bands a mupo run draws on (sampling_ride > 0), or nothing.
void riding_line(std::string& out, const Scene& scene) {
  if (!(scene.sampling.ride > 0) || scene.init != InitKind::birkhoff) return;
  const std::vector<RidingBand> bands = riding_bands(scene);
  if (bands.empty()) {
    out += "riding: no riding band (2 r omega's pattern rides at rest or outside [p_min, p_max])\n";
    return;
  }
  appendf(out, "riding: %g of the mupo draws on", scene.sampling.ride);
  for (const RidingBand& b : bands) appendf(out, " |p| in [%.3g, %.3g] (%lld/%lld)", b.lo, b.hi, b.a, b.b);
  out += "\n";
}

/// The population line of a split or weighted run (nothing for a uniform one).
void population_lines(std::string& out, const RunSummary& r) {
  if (r.curve.lines) {
    const std::size_t last = r.curve.t.size() - 1;
    appendf(out,
            "splitting: every %g, turn %g rad, cap %llu; %llu levels, %llu of %llu lines alive and %.3g effective at "
            "t_max, ",
            r.scene.splitting.every, r.scene.splitting.delta, static_cast<unsigned long long>(r.scene.splitting.cap),
            static_cast<unsigned long long>(r.result.tally.as<LinesEstimator>().levels),
            static_cast<unsigned long long>(r.curve.lines_alive[last]),
            static_cast<unsigned long long>(r.scene.particles), r.curve.effective(last));
    if (p_bounded(r.curve, last))  // the error is mostly the allowance: P is bounded there, not measured
      appendf(out,
              "P(t_max) < %.2g (P + 3 errors: from t = %g P's error is mostly the allowance for unsplit lines not "
              "drawn, docs/model.md; the lines drawn give %.3g)\n",
              r.curve.P(last) + 3 * r.curve.P_err(last), *r.curve.allowance_unresolved_from, r.curve.P(last));
    else
      appendf(out, "P(t_max) = %.3g +- %.2g\n", r.curve.P(last), r.curve.P_err(last));
  } else if (r.curve.replicated) {
    const std::size_t last = r.curve.t.size() - 1;
    const StartSplitSpec& g = r.scene.start_splitting;
    appendf(out,
            "start splitting: %d replicates of %llu starts with |p| in [%g, %g]%s (a share %.3g of the map's "
            "measure), %zu levels; P(t_max | those starts) = %.3g +- %.2g (%d of %d replicates nonzero)\n",
            g.replicates, static_cast<unsigned long long>(r.scene.particles), g.p_lo, g.p_hi,
            g.edges ? " on the straight edges" : "", r.start_splitting ? r.start_splitting->stratum.share() : 0.0,
            r.start_splitting ? r.start_splitting->levels.size() : std::size_t(0), r.curve.P(last), r.curve.P_err(last),
            r.curve.replicates_nonzero.empty() ? 0 : r.curve.replicates_nonzero[last], r.curve.replicates);
    if (const IcSplitRun* run = r.start_splitting ? &*r.start_splitting : nullptr) {
      if (run->handover < run->levels.size()) {
        std::uint64_t handed = 0, disagreed = 0;
        for (const IcReplicate& x : run->replicates) handed += x.handed_over, disagreed += x.handover_disagreed;
        appendf(out,
                "start splitting: from t = %.0f the starts are timed in %s (double's moves fell below 2^%d ulps); of "
                "the %llu outliving it in double, %llu did not in %s\n",
                run->levels[run->handover], Tier{run->spec.deep_tier, 0}.name().c_str(), run->spec.handover_bits,
                static_cast<unsigned long long>(handed), static_cast<unsigned long long>(disagreed),
                Tier{run->spec.deep_tier, 0}.name().c_str());
      }
      if (const auto [fewest, from] = run->fewest_ancestors(); fewest > 0 && fewest < 10)
        appendf(out,
                "start splitting: past t = %.0f a replicate's states descend from %llu stage-0 start%s: its P there "
                "rests on few independent draws (more starts; the spread of the replicates stays honest)\n",
                from, static_cast<unsigned long long>(fewest), fewest == 1 ? "" : "s");
      if (std::isfinite(run->unresolved_from()))
        appendf(out,
                "start splitting: past t = %.0f the moves are below 2^8 ulps of the clock's tier: P there is that "
                "clock's, whose trajectories' stretch times the unit roundoff is near 1 (docs/model.md)\n",
                run->unresolved_from());
    }
  } else if (r.curve.weighted)
    appendf(
        out,
        "sampling: mupo, eps = %g, |p| log-uniform in [%g, %g]; %.3g effective survivors at t_max (%llu particles)\n",
        r.scene.sampling.eps, r.scene.sampling.p_min, r.scene.sampling.p_max, r.curve.effective(r.curve.t.size() - 1),
        static_cast<unsigned long long>(r.curve.survivors.back()));
  riding_line(out, r.scene);
}

/// kappa's line and alpha's (its value, or its bound and why), with the mupo reach's warning.
void kappa_alpha_lines(std::string& out, const KappaFit& kappa, const AlphaResult& alpha) {
  if (kappa.ok)
    appendf(out, "kappa = %.5g +- %.2g (stat.) +- %.2g (window)   (least squares of ln P on [%g, %g])\n", kappa.value,
            kappa.std_error, kappa.window_systematic.value_or(0), kappa.from, kappa.to);
  else
    appendf(out, "kappa: not resolved (%s in [%g, %g])\n", kappa.points < 3 ? "too few grid points" : "no escape",
            kappa.from, kappa.to);
  if (alpha.value) {
    appendf(out, "alpha = %.3g +- %.2g (stat.)", *alpha.value, alpha.std_error);
    if (alpha.systematic)
      appendf(out, " +- %.2g (window)", *alpha.systematic);
    else
      out += " +- ? (window: fewer than two of kappa's windows resolve alpha)";
    appendf(out, "   (P at t = %.6g, where P first exceeds %g x the fit)\n", alpha.crossing_time, alpha.factor);
  } else if (alpha.upper_bound && alpha.crossing_not_significant)
    appendf(out, "alpha < %.3g   (P crosses %g x the fit at t = %g, but not %g standard errors above the fit)\n",
            *alpha.upper_bound, alpha.factor, alpha.resolved_until, alpha.sigma);
  else if (alpha.upper_bound)
    appendf(out, "alpha < %.3g   (P + %g errors stays below %g x the fit up to t = %g; >= %llu survive until t = %g)\n",
            *alpha.upper_bound, alpha.sigma, alpha.factor, alpha.bound_until,
            static_cast<unsigned long long>(alpha.min_survivors), alpha.resolved_until);
  if (alpha.uniform_reach && (alpha.value || alpha.upper_bound) &&
      alpha.value.value_or(alpha.upper_bound.value_or(0.0)) < *alpha.uniform_reach)
    appendf(out,
            "warning: alpha is unreliable below %.3g, the reach of the mupo scheme's uniform share at this particle "
            "count; set run.splitting = true\n",
            *alpha.uniform_reach);
}

/// alpha from C, z and C's lines.
void tail_fit_lines(std::string& out, const RunSummary& r) {
  if (r.alpha_c.value)
    appendf(out, "alpha_C = %.3g +- %.2g   (from A exp(-kappa t) + C / t: %g x the fit at t = %.6g)\n",
            *r.alpha_c.value, r.alpha_c.std_error, r.alpha.factor, r.alpha_c.crossing_time);
  if (r.tail.z)
    appendf(out, "z     = %.3g +- %.2g   (P ~ t^-z on [%g, %g])\n", *r.tail.z, r.tail.std_error, r.tail.from,
            r.tail.to);
  if (r.amplitude.value)
    appendf(out, "C     = %.4g +- %.2g (stat.) +- %.2g (drift)   (P ~ C / t: mean of t P on [%g, %g])\n",
            *r.amplitude.value, r.amplitude.std_error, r.amplitude.drift, r.amplitude.from, r.amplitude.to);
  else if (r.amplitude.from > 0 && r.amplitude.slope_error > 0)
    appendf(out,
            "C     : none, t P(t) is not flat (d ln(t P) / d ln t = %.3g +- %.2g on [%g, %g]); t P = %.3g +- %.2g at t "
            "= %g\n",
            r.amplitude.slope, r.amplitude.slope_error, r.amplitude.from, r.amplitude.to, r.amplitude.height,
            r.amplitude.height_error, r.amplitude.from);
}

/// The tail's class and regime with the geometry's times, the model's verdict, and what would decide it.
void tail_class_lines(std::string& out, const RunSummary& r) {
  appendf(out, "tail  = %s, regime %s", r.tail_class.tail.c_str(), r.tail_class.regime.c_str());
  if (r.tail_class.tail_end) appendf(out, " (gone by t = %g)", *r.tail_class.tail_end);
  if (r.leak_times.tau1)
    appendf(out, "; predicted: leading edge on the lower edge from tau1 = %.6g to tau2 = %.6g", *r.leak_times.tau1,
            *r.leak_times.tau2);
  out += "\n";
  if (r.prediction) {
    const std::string check = prediction_check(*r.prediction, r.amplitude, r.tail_class);
    if (!check.empty()) out += "model : " + check + "\n";
  }
  if (r.tail_class.resolve_particles)
    appendf(out, "        %s: about %.2g particles would %s (%s)\n",
            r.tail_class.tail == "none" ? "undecided, no tail seen above the bound only"
                                        : "a tail is seen but alpha is not resolved",
            static_cast<double>(*r.tail_class.resolve_particles),
            r.tail_class.tail == "none" ? "decide it" : "resolve it",
            (to_string(r.scene.sampling.kind) + " sampling").c_str());
}

}  // namespace

std::string fit_text(const RunSummary& r) {
  std::string out;
  kappa_alpha_lines(out, r.kappa, r.alpha);
  tail_fit_lines(out, r);
  tail_class_lines(out, r);
  return out;
}

std::string summary_text(const RunSummary& r) {
  std::string out;
  // under MPI the ranks and each one's threads (the header once said "1 threads" and never the ranks)
  const std::string workers =
      r.result.ranks > 1 ? std::to_string(r.result.ranks) + " ranks x " + std::to_string(r.result.threads) + " threads"
                         : std::to_string(r.result.threads) + " threads";
  appendf(out, "%s: %llu particles, %s tier, %s, %.2f s, %.3g collisions/s\n", r.scene.source.c_str(),
          static_cast<unsigned long long>(r.scene.particles), to_string(r.scene.tier).c_str(), workers.c_str(),
          r.result.wall_seconds, r.collisions_per_second());
  population_lines(out, r);
  out += fit_text(r);
  if (r.result.tally.stuck)
    appendf(out, "warning: %llu particles stuck (zero-length flights); counted as not escaped\n",
            static_cast<unsigned long long>(r.result.tally.stuck));
  if (r.tier_choice) out += "tier  : auto chose " + to_string(r.scene.tier) + ": " + *r.tier_choice + "\n";
  if (r.precision_warning)
    out += "warning: the audit does not trust P(t), kappa or alpha at the " + to_string(r.scene.tier) +
           " tier here: " + *r.precision_warning + "\n";
  return out;
}

void write_directory_summary(RunDirectory& dir, const std::string& command, const std::string& scene_source,
                             std::vector<std::string> files) {
  files.push_back("summary.json");
  const json s = {
      {"execution", execution_json(json::object())}, {"command", command}, {"scene", scene_source}, {"files", files}};
  write_file_atomic(dir.file("summary.json"), s.dump(2) + "\n");
  dir.commit();
}

RunTexts run_texts(const RunSummary& r, const std::vector<std::string>& written) {
  RunTexts out;
  out.files.emplace_back("survival.csv", survival_csv(r.curve));
  if (r.curve.lines) out.files.emplace_back("lines.csv", lines_csv(r.curve));
  if (r.scene.collision_density) out.files.emplace_back("fc.csv", density_csv(r.scene, r.result.tally));
  if (r.scene.escape_records)
    out.files.emplace_back("escapes.csv",
                           escapes_csv(r.result.first_id, r.result.records, !r.result.tally.escapes_by_leak.empty()));
  if (!r.result.tally.escapes_by_leak.empty()) out.files.emplace_back("leaks.csv", leaks_csv(r.scene, r.result.tally));
  out.files.emplace_back("scene.toml", scene_to_toml(r.scene));
  std::vector<std::string> names;
  for (const auto& f : out.files) names.push_back(f.first);
  names.insert(names.end(), written.begin(), written.end());
  names.push_back("summary.json");
  out.summary = summary_json(r, names);
  out.files.emplace_back("summary.json", out.summary.dump(2) + "\n");
  return out;
}

json write_run(RunDirectory& dir, RunTexts t) {
  for (const auto& [name, text] : t.files)  // summary.json last: its presence marks a complete run
    write_file_atomic(dir.file(name), text);
  dir.commit();
  return std::move(t.summary);
}

}  // namespace rotleak

namespace rotleak {

namespace {

/// A JSON document of a directory, or an InputError (DIR) naming the file: the reason the readers share.
json parse_document(const std::string& shown, const std::string& text, const std::string& file) {
  try {
    return json::parse(text);
  } catch (const json::exception&) {
    throw InputError("DIR", shown, file + ": not valid JSON (damaged or truncated)");
  }
}

}  // namespace

json read_run_summary(const std::filesystem::path& dir, const std::string& text) {
  const std::string shown = "\"" + dir.string() + "\"";
  const json s = parse_document(shown, text, "summary.json");
  if (!s.is_object() || !s.contains("command") || s["command"] != "simulate" || !s.contains("scene") ||
      !s["scene"].is_object())
    throw InputError("DIR", shown, "summary.json: not a simulate run's summary");
  return s;
}

json read_scan_document(const std::filesystem::path& dir, const std::string& text) {
  const std::string shown = "\"" + dir.string() + "\"";
  const json doc = parse_document(shown, text, "scan.json");
  const auto bad = [&] { return InputError("DIR", shown, "scan.json: not a scan's document"); };
  if (!doc.is_object() || !doc.contains("command") || doc["command"] != "scan" || !doc.contains("axes") ||
      !doc["axes"].is_array() || !doc.contains("points") || !doc["points"].is_array())
    throw bad();
  for (const json& a : doc["axes"]) {
    if (!a.is_object() || !a.contains("key") || !a["key"].is_string() || !a.contains("values") ||
        !a["values"].is_array())
      throw bad();
    for (const json& v : a["values"])
      if (!v.is_string()) throw bad();
  }
  for (const json& p : doc["points"]) {
    if (!p.is_object() || !p.contains("point") || !p["point"].is_string() || !p.contains("values") ||
        !p["values"].is_object() || !p.contains("number_theory"))
      throw bad();
    const std::string name = p["point"].get<std::string>();
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos) throw bad();
    for (const json& a : doc["axes"]) {
      const std::string key = a["key"].get<std::string>();
      if (!p["values"].contains(key) || !p["values"][key].is_string()) throw bad();
    }
  }
  if (doc.contains("fit_overrides") && !doc["fit_overrides"].is_array()) throw bad();
  return doc;
}

}  // namespace rotleak
