#include "verify/reports.hpp"

#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/text.hpp"

namespace rotleak {

namespace {

json tier_json(const TierShadow& t) {
  return {{"name", t.name},
          {"collisions", t.collisions},
          {"horizon_collision", nullable(t.horizon)},
          {"horizon_time", t.horizon ? json(t.horizon_time) : json(nullptr)},
          {"decision_differs_at", nullable(t.decision)},
          {"escape_collision", nullable(t.escape)},
          {"escape_time", t.escape ? json(t.escape_time) : json(nullptr)},
          {"escape_time_exact", t.escape_exact},
          {"growth_per_collision", t.growth_per_collision},
          {"growth_per_time", t.growth_per_time},
          {"growth_points", t.growth_points},
          {"stopped", t.stopped},
          {"seconds", t.seconds}};
}

json q_json(const Quantiles& q) {
  return {{"q10", q.q10}, {"q25", q.q25}, {"median", q.median}, {"q75", q.q75}, {"q90", q.q90}, {"n", q.n}};
}

json estimate_json(const LyapunovEstimate& e) {
  return {{"per_time", e.per_time},
          {"per_time_error", e.per_time_error},
          {"per_collision", e.per_collision},
          {"per_collision_error", e.per_collision_error},
          {"samples", e.samples},
          {"collisions", e.collisions}};
}

}  // namespace

json shadow_json(const ShadowResult& r, double tolerance) {
  json doc;
  doc["execution"] = execution_json(json::object());
  doc["particle"] = r.id;
  doc["weight"] = r.weight;
  doc["initial"] = {{"s", r.draw.s}, {"p", r.draw.p}, {"tau", r.draw.tau}};
  doc["collisions"] = r.horizon_collisions;
  doc["tolerance"] = tolerance;
  std::size_t mupo = 0;
  for (auto m : r.truth.mupo) mupo += m;
  doc["truth"] = {{"bits", r.truth.bits},
                  {"bits_tried", r.truth.bits_tried},
                  {"agreement", r.truth.agreement},
                  {"escape_collision", nullable(r.truth.escape)},
                  {"escape_time", r.truth.escape ? json(r.truth.t[*r.truth.escape - 1]) : json(nullptr)},
                  {"mupo_collisions", mupo}};
  json tiers = json::array();
  for (const auto& t : r.tiers) tiers.push_back(tier_json(t));
  doc["tiers"] = tiers;
  return doc;
}

std::string shadow_csv(const ShadowResult& r) {
  std::string csv = "k,t,s,p,in_leak,mupo";
  for (const auto& t : r.tiers) csv += ",div_" + t.name + ",t_" + t.name + ",s_" + t.name + ",p_" + t.name;
  csv += "\n";
  for (std::size_t i = 0; i < r.truth.t.size(); ++i) {
    csv += std::to_string(i + 1) + "," + shortest(r.truth.t[i]) + "," + shortest(r.truth.s[i]) + "," +
           shortest(r.truth.p[i]) + "," + std::to_string(r.truth.in_leak[i]) + "," + std::to_string(r.truth.mupo[i]);
    for (const auto& t : r.tiers)
      csv += i < t.collisions ? "," + shortest(t.divergence[i]) + "," + shortest(t.t[i]) + "," + shortest(t.s[i]) +
                                    "," + shortest(t.p[i])
                              : ",,,,";
    csv += "\n";
  }
  return csv;
}

std::string shadow_text(const ShadowResult& r) {
  std::string out;
  std::size_t mupo = 0;
  for (auto m : r.truth.mupo) mupo += m;
  appendf(out, "particle %llu: s0 = %.17g, p0 = %.17g, created at t = %.17g; %zu collisions, %zu in MUPO phases\n",
          static_cast<unsigned long long>(r.id), r.draw.s, r.draw.p, r.draw.tau, r.horizon_collisions, mupo);
  appendf(out, "truth: MPFR at %ld bits (%ld bits agree to %.1e)", r.truth.bits, r.truth.bits / 2, r.truth.agreement);
  if (r.truth.escape)
    appendf(out, ", escapes at collision %zu, t = %.12g\n", *r.truth.escape, r.truth.t[*r.truth.escape - 1]);
  else
    appendf(out, ", does not escape within the horizon\n");
  appendf(out, "%-12s %10s %12s %10s %10s %8s %11s %9s\n", "tier", "horizon", "horizon t", "decision", "escape",
          "exact", "ln-growth/k", "seconds");
  for (const auto& t : r.tiers) {
    char when[32] = "-";  // six digits in the table (summary.json and shadow.csv keep every digit)
    if (t.horizon) std::snprintf(when, sizeof when, "%.6g", t.horizon_time);
    appendf(out, "%-12s %10s %12s %10s %10s %8s %11.3g %9.3g%s\n", t.name.c_str(),
            t.horizon ? std::to_string(*t.horizon).c_str() : "-", when,
            t.decision ? std::to_string(*t.decision).c_str() : "-", t.escape ? std::to_string(*t.escape).c_str() : "-",
            t.escape_exact ? "yes" : "no", t.growth_per_collision, t.seconds,
            t.stopped.empty() ? "" : ("  (" + t.stopped + ")").c_str());
  }
  return out;
}

namespace {

json audit_execution_json(const AuditReport& r) {
  json by_tier = json::object();
  for (const auto& [tier, seconds] : r.ensemble_seconds_by_tier) by_tier[tier] = seconds;
  return execution_json({{"seconds", r.seconds},
                         {"timing",
                          {{"stratify_seconds", r.stratify_seconds},
                           {"shadow_seconds", r.shadow_seconds},
                           {"ensemble_seconds", r.ensemble_seconds},
                           {"ensemble_seconds_by_tier", by_tier},
                           {"analysis_seconds", r.analysis_seconds}}},
                         {"threads", r.threads},
                         {"ranks", r.ranks}});
}

json audit_tiers_json(const AuditReport& r) {
  json tiers = json::array();
  for (const auto& t : r.tiers)
    tiers.push_back({{"name", t.name},
                     {"median_horizon_collisions", t.horizon_collisions.median},
                     {"median_horizon_time", t.horizon_time.median},
                     {"escape_time_exact_fraction", t.escape_time_exact_fraction},
                     {"escapes_compared", t.escapes_compared},
                     {"beyond_horizon", t.beyond_horizon},
                     {"horizon_collisions", q_json(t.horizon_collisions)},
                     {"horizon_time", q_json(t.horizon_time)},
                     {"horizon_collisions_mupo", q_json(t.horizon_collisions_mupo)},
                     {"horizon_collisions_chaotic", q_json(t.horizon_collisions_chaotic)},
                     {"growth_per_collision_mupo", t.growth.mupo_per_collision},
                     {"growth_per_collision_chaotic", t.growth.chaotic_per_collision}});
  return tiers;
}

json audit_statistics_json(const AuditReport& r) {
  json stats = json::array();
  for (const auto& s : r.statistics) {
    json w = json::array();
    for (const auto& x : s.windows)
      w.push_back({{"from", x.from},
                   {"to", x.to},
                   {"escapes", x.escapes_tier},
                   {"at_risk", x.at_risk_tier},
                   {"escapes_ref", x.escapes_ref},
                   {"at_risk_ref", x.at_risk_ref},
                   {"z", x.z}});
    stats.push_back({{"tier", s.tier},
                     {"windows", w},
                     {"max_abs_z", s.max_abs_z},
                     {"kappa", s.kappa},
                     {"kappa_error", s.kappa_error},
                     {"kappa_diff", s.kappa_diff},
                     {"kappa_diff_error", s.kappa_diff_error},
                     {"alpha", nullable(s.alpha)},
                     {"alpha_error", s.alpha_error},
                     {"alpha_diff", nullable(s.alpha_diff)},
                     {"alpha_diff_error", s.alpha_diff_error},
                     {"consistent", s.consistent},
                     {"identical_to_scalar_double", s.identical_to_scalar_double}});
  }
  return stats;
}

json audit_scalars_json(const AuditReport& r) {
  json scal = json::array();
  for (const auto& s : r.scalars)
    scal.push_back({{"tier", s.tier},
                    {"phase_error_at_tmax", s.phase_error_at_tmax},
                    {"omega_single_drift", s.omega_single_drift},
                    {"omega_split_drift", s.omega_split_drift},
                    {"time_ulp_at_tmax", s.time_ulp_at_tmax},
                    {"omega_is_rounded", s.omega_is_rounded},
                    {"phase_resolved", s.phase_resolved},
                    {"note", s.note}});
  return scal;
}

}  // namespace

json audit_json(const AuditReport& r, const std::string& source) {
  json doc;
  doc["scene"] = source;
  doc["sample"] = r.sample;
  doc["execution"] = audit_execution_json(r);
  doc["max_truth_bits"] = r.max_truth_bits;
  doc["lyapunov"] = {
      {"per_time", r.lyapunov_tangent.per_time},
      {"per_collision", r.lyapunov_tangent.per_collision},
      {"tangent", {{"per_time", r.lyapunov_tangent.per_time}, {"error", r.lyapunov_tangent.per_time_error}}},
      {"divergence",
       {{"per_time", r.lyapunov_divergence.per_time},
        {"error", r.lyapunov_divergence.per_time_error},
        {"per_collision", r.lyapunov_divergence.per_collision},
        {"particles", r.lyapunov_divergence.samples}}}};
  doc["tiers"] = audit_tiers_json(r);
  doc["statistics"] = audit_statistics_json(r);
  doc["scalars"] = audit_scalars_json(r);
  json verdicts = json::array();
  for (const auto& v : r.verdicts)
    verdicts.push_back({{"tier", v.tier}, {"statistic", v.statistic}, {"verdict", v.verdict}, {"reason", v.reason}});
  doc["verdicts"] = verdicts;
  return doc;
}

std::string audit_text(const AuditReport& r, const std::string& source) {
  std::string out;
  appendf(out, "audit of %s: %zu particles shadowed (truth up to %ld bits), %.1f s%s\n", source.c_str(), r.sample,
          r.max_truth_bits, r.seconds, r.ranks > 1 ? (" on " + std::to_string(r.ranks) + " MPI ranks").c_str() : "");
  appendf(out,
          "  time: stratification %.1f s, shadows %.1f s, statistics ensembles %.1f s, Lyapunov and verdicts %.1f s\n",
          r.stratify_seconds, r.shadow_seconds, r.ensemble_seconds, r.analysis_seconds);
  appendf(out,
          "Lyapunov exponent: %.4f per time, %.4f per collision (tangent); shadow divergence %.4f +- %.4f per time\n",
          r.lyapunov_tangent.per_time, r.lyapunov_tangent.per_collision, r.lyapunov_divergence.per_time,
          r.lyapunov_divergence.per_time_error);
  appendf(out,
          "trust horizons in collisions (quantiles over particles that reached theirs; 'later' = escaped first),\n"
          "escape times reproduced, ln-divergence growth per collision by class:\n");
  appendf(out, "%-12s %6s %6s %6s %8s %6s %6s %6s %10s %9s %9s\n", "tier", "h10", "h50", "h90", "h50 time", "n",
          "later", "h50 MUPO", "escape ok", "g(MUPO)", "g(chaos)");
  for (const auto& t : r.tiers) {
    const std::string mupo =
        t.horizon_collisions_mupo.n ? std::to_string(static_cast<long>(t.horizon_collisions_mupo.median)) : "-";
    appendf(out, "%-12s %6.0f %6.0f %6.0f %8.1f %6zu %6zu %6s %9.1f%% %9.3f %9.3f\n", t.name.c_str(),
            t.horizon_collisions.q10, t.horizon_collisions.median, t.horizon_collisions.q90, t.horizon_time.median,
            t.horizon_collisions.n, t.beyond_horizon, mupo.c_str(), 100 * t.escape_time_exact_fraction,
            t.growth.mupo_per_collision, t.growth.chaotic_per_collision);
  }
  appendf(out, "statistics (same ids, %s ensembles):\n", "float / double / long double");
  for (const auto& s : r.statistics)
    appendf(out, "  %-12s max |z| %.2f, kappa %.5g (diff %.2g +- %.1g): %s\n", s.tier.c_str(), s.max_abs_z, s.kappa,
            s.kappa_diff, s.kappa_diff_error, s.consistent ? "consistent" : "DIFFERS");
  appendf(out, "scalars:\n");
  for (const auto& s : r.scalars) appendf(out, "  %-12s %s\n", s.tier.c_str(), s.note.c_str());
  appendf(out, "verdicts:\n");
  for (const auto& v : r.verdicts)
    appendf(out, "  %-12s %-12s %-22s %s\n", v.tier.c_str(), v.statistic.c_str(), v.verdict.c_str(), v.reason.c_str());
  return out;
}

json lyapunov_json(const LyapunovStudy& s) {
  const double rel = s.relative_difference();
  json doc;
  doc["lyapunov"] = {{"per_time", s.tangent.per_time},      {"per_collision", s.tangent.per_collision},
                     {"tangent", estimate_json(s.tangent)}, {"divergence", estimate_json(s.divergence)},
                     {"divergence_tier", s.options.tier},   {"divergence_window", {s.options.from, s.options.to}},
                     {"relative_difference", rel}};
  doc["growth_by_class"] = {{"tier", s.options.tier},
                            {"mupo_per_collision", s.by_class.mupo_per_collision},
                            {"mupo_steps", s.by_class.mupo_steps},
                            {"chaotic_per_collision", s.by_class.chaotic_per_collision},
                            {"chaotic_steps", s.by_class.chaotic_steps}};
  doc["mupo_orbit"] = {{"p0", s.options.mupo_p},
                       {"collisions", s.mupo_collisions},
                       {"tier", "double"},
                       {"power", s.mupo_law.power},
                       {"power_r2", s.mupo_law.power_r2},
                       {"exp_rate_per_collision", s.mupo_law.rate},
                       {"exp_r2", s.mupo_law.rate_r2},
                       {"polynomial", s.mupo_law.polynomial()}};
  return doc;
}

std::string lyapunov_text(const LyapunovStudy& s, const std::string& source) {
  std::string out;
  const double rel = s.relative_difference();
  appendf(out, "Lyapunov exponent of %s\n", source.c_str());
  appendf(out, "  tangent dynamics (%zu collisions, double): %.5f +- %.5f per time, %.5f +- %.5f per collision\n",
          s.tangent.collisions, s.tangent.per_time, s.tangent.per_time_error, s.tangent.per_collision,
          s.tangent.per_collision_error);
  appendf(out,
          "  shadow divergence (%zu particles, %s vs truth, t in [%g, %g]): %.5f +- %.5f per time, %.5f +- %.5f per "
          "collision\n",
          s.divergence.samples, s.options.tier.c_str(), s.options.from, s.options.to, s.divergence.per_time,
          s.divergence.per_time_error, s.divergence.per_collision, s.divergence.per_collision_error);
  appendf(out, "  relative difference: %.2f%%\n", 100 * rel);
  appendf(out, "growth of ln(divergence) per collision: MUPO phases %.4f (%zu steps), chaotic %.4f (%zu steps)\n",
          s.by_class.mupo_per_collision, s.by_class.mupo_steps, s.by_class.chaotic_per_collision,
          s.by_class.chaotic_steps);
  if (s.mupo_collisions == 0) return out;  // another table: no bouncing-ball orbit was followed
  appendf(out,
          "bouncing-ball orbit, p0 = %g, %zu collisions in double: divergence ~ k^%.2f (R^2 %.4f) vs exp(%.4f k) (R^2 "
          "%.4f): %s\n",
          s.options.mupo_p, s.mupo_collisions, s.mupo_law.power, s.mupo_law.power_r2, s.mupo_law.rate,
          s.mupo_law.rate_r2, s.mupo_law.polynomial() ? "polynomial" : "exponential");
  return out;
}

json certify_json(std::uint64_t particle, const std::vector<Certificate>& attempts) {
  json doc, list = json::array();
  for (const auto& c : attempts)
    list.push_back({{"bits", c.bits},
                    {"certified_collisions", c.certified_collisions},
                    {"escape_certified", c.escape_certified},
                    {"escape_collision", c.escape_collision},
                    {"escape_time", {c.escape_time_lo, c.escape_time_hi}},
                    {"last_width", c.last_width}});
  doc["particle"] = particle;
  doc["attempts"] = list;
  doc["escape_certified"] = attempts.back().escape_certified;
  return doc;
}

std::string certify_text(const std::vector<Certificate>& attempts) {
  std::string out;
  for (const auto& c : attempts)
    appendf(out, "%6ld bits: %zu collisions certified%s\n", c.bits, c.certified_collisions,
            c.escape_certified ? (", escape at collision " + std::to_string(c.escape_collision) + " proven, t in [" +
                                  std::to_string(c.escape_time_lo) + ", " + std::to_string(c.escape_time_hi) + "]")
                                     .c_str()
                               : "");
  return out;
}

std::string sample_text(const SampleCertificate& c, const SampleOptions& opt) {
  const SampleBracket b = bracket_of(c, opt.dt > 0 ? opt.dt : c.t_cap / 400);
  const SampleTotals t = totals_of(c, b);
  const double n = static_cast<double>(c.particles.size());
  std::string out;
  appendf(out, "certified %zu particles to t = %g on %d threads in %.1f s (%.2f ms a particle)\n", c.particles.size(),
          c.t_cap, c.threads, c.seconds, 1e3 * c.seconds / n);
  appendf(out,
          "proven: %zu escapes, %zu survivors past the cap = %.4f%%; undecided %zu; bits up to %ld; escape times "
          "within %.3g\n",
          t.proven, t.survives, 100.0 * static_cast<double>(t.proven + t.survives) / n, t.undecided, t.bits_max,
          t.escape_width_max);
  appendf(out, "bracket: widest %.3g (at t = %g)\n", t.bracket_width_max, t.bracket_widest_at);
  for (const TierJudgement& j : judge_tiers(c, b))
    appendf(out,
            "%-12s outside the bracket at %zu of %zu grid points (%zu by more than 3 errors; %zu where the bracket is "
            "tighter than one error, of %zu); KS D = %.4f, p = %.3g; same escape collision %.1f%%\n",
            j.tier.c_str(), j.outside, j.grid_points, j.outside_beyond_3s, j.outside_where_tight, j.tight, j.ks_d,
            j.ks_p,
            100.0 * static_cast<double>(j.same_escape_collision) / std::max(1.0, static_cast<double>(t.proven)));
  return out;
}

}  // namespace rotleak
