// Numerical stability at the extremes, each a named test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analysis/output/run_output.hpp"
#include "io/scene_file.hpp"
#include "numeric/input.hpp"
#include "numeric/tiers.hpp"
#include "paths.hpp"
#include "run/pipeline.hpp"
#include "sim/engine/engine.hpp"
#include "verify/audit.hpp"
#include "verify/auto_tier.hpp"
#include "verify/certify.hpp"
#include "verify/shadow.hpp"
#include "verify/trace.hpp"

using namespace rotleak;

namespace {

Scene scene_with(const std::vector<std::string>& sets) { return parse_scene("", sets); }

double off_boundary(const Stadium<double>& st, Piece p, const Vec2<double>& q) {
  if (p == Piece::top) return std::abs(q.y - 1);
  if (p == Piece::bottom) return std::abs(q.y + 1);
  return std::abs(std::hypot(q.x - st.arc_centre_x(p), q.y) - 1);
}

}  // namespace

// |p| -> 1: whispering-gallery orbits along an arc with flights of ~1e-6; they must neither stick
// nor leave the boundary, and the arc's flight formula must stay accurate (no cancellation).
TEST(Extremes, GrazingHitsAlongTheArc) {
  const Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const BoundaryPoint<double> b = st.at(0.2);
  ASSERT_EQ(b.piece, Piece::right_arc);
  Vec2<double> q = b.q, v = st.velocity(b, 1 - 1e-12);
  std::size_t arc_hits = 0;
  for (int k = 0; k < 20000; ++k) {
    const Hit<double> h = st.next_hit(q, v);
    ASSERT_GT(h.t, 0.0) << "collision " << k;
    ASSERT_LT(off_boundary(st, h.piece, h.q), 1e-12) << "collision " << k;
    arc_hits += h.piece == Piece::right_arc;
    v = st.reflect(h.piece, h.q, v);
    q = h.q;
  }
  EXPECT_GT(arc_hits, 1000u);
  EXPECT_NEAR(std::hypot(v.x, v.y), 1.0, 1e-12);
}

// A ray aimed exactly at a junction: whichever piece rounding picks, the point is the junction and
// the outgoing direction the same (both pieces share the normal there).
TEST(Extremes, HitsExactlyAtTheFourJunctions) {
  const Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const Vec2<double> junctions[] = {{1, 1}, {1, -1}, {-1, -1}, {-1, 1}};
  for (const auto& j : junctions) {
    const Vec2<double> from{0.25 * j.x, -j.y};  // on the opposite straight edge
    const double len = std::hypot(j.x - from.x, j.y - from.y);
    const Vec2<double> v{(j.x - from.x) / len, (j.y - from.y) / len};
    const Hit<double> h = st.next_hit(from, v);
    EXPECT_NEAR(h.q.x, j.x, 1e-14);
    EXPECT_NEAR(h.q.y, j.y, 1e-14);
    EXPECT_NEAR(h.t, len, 1e-14);
    const Vec2<double> out = st.reflect(h.piece, h.q, v);
    EXPECT_NEAR(out.x, v.x, 1e-7);  // an arc's normal at its end is vertical to ~sqrt(eps)
    EXPECT_NEAR(out.y, -v.y, 1e-7);
  }
  // the boundary coordinate is continuous across each junction
  for (int k = 0; k < 4; ++k) {
    const double s = st.junction(k);
    const BoundaryPoint<double> before = st.at(std::nextafter(s, 0.0)), after = st.at(s);
    EXPECT_LT(std::hypot(before.q.x - after.q.x, before.q.y - after.q.y), 1e-14) << "junction " << k;
  }
}

// p = 0 on a straight edge: v = (0, -1) exactly, so the orbit is periodic in every tier, forever.
template <class R>
void expect_exactly_periodic(double s0) {
  const Stadium<R> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const BoundaryPoint<R> b = st.at(R(s0));
  Vec2<R> q = b.q, v = st.velocity(b, R(0));
  R t(0);
  for (int k = 0; k < 100000; ++k) {
    const Hit<R> h = st.next_hit(q, v);
    t += h.t;
    v = st.reflect(h.piece, h.q, v);
    q = h.q;
  }
  EXPECT_TRUE(q.x == b.q.x && q.y == b.q.y) << num_traits<R>::name();
  EXPECT_TRUE(t == R(200000)) << num_traits<R>::name();  // 10^5 flights of exactly 2
}

TEST(Extremes, BouncingBallWithPZeroIsPeriodicInEveryTier) {
  for (double s0 : {0.0, 0.03, 0.5, 0.95}) {
    expect_exactly_periodic<float>(s0);
    expect_exactly_periodic<double>(s0);
    expect_exactly_periodic<long double>(s0);
    expect_exactly_periodic<dd_real>(s0);
    MpfrPrecision p(256);
    expect_exactly_periodic<Mpfr>(s0);
  }
}

// lambda = 1e-9 and 0.5: a tiny leak is almost never hit, a huge one at once; the engine handles both.
TEST(Extremes, TinyAndHugeLeaks) {
  const Scene tiny = scene_with({"leak.width=1e-9", "ensemble.particles=2000", "run.t_max=2000"});
  const Scene huge = scene_with({"leak.width=0.5", "ensemble.particles=2000", "run.t_max=2000"});
  const RunResult a = run_ensemble(tiny, RunOptions{}), b = run_ensemble(huge, RunOptions{});
  // expected escapes ~ N * (1 - exp(-lambda t / mean free time)): ~0.002 for the tiny leak
  EXPECT_LE(a.tally.escaped, 3u);
  EXPECT_EQ(b.tally.escaped, 2000u);
  EXPECT_LT(static_cast<double>(b.tally.collisions) / 2000, 3.0);  // half the boundary: ~2 collisions each
}

// omega = 0, 1e-9, 1e6, 1e12 at t_max = 2e4: the audit's scalar check flags lost phase resolution.
TEST(Extremes, LeakPhaseResolutionAtLargeOmega) {
  auto resolved = [](const char* omega, const char* tier) {
    return scalar_check(scene_with({std::string("leak.omega=") + omega}), tier).phase_resolved;
  };
  for (const char* tier : {"float", "double", "long_double", "dd"}) {
    EXPECT_TRUE(resolved("0", tier)) << tier;
    EXPECT_TRUE(resolved("1e-9", tier)) << tier;
  }
  EXPECT_FALSE(resolved("1e6", "float"));
  EXPECT_TRUE(resolved("1e6", "double"));
  EXPECT_FALSE(resolved("1e12", "double"));  // omega t_max = 2e16 > 2^53: the phase is lost
  EXPECT_FALSE(resolved("1e12", "long_double"));
  EXPECT_TRUE(resolved("1e12", "dd"));
}

// One trust verdict (verify/audit.cpp verdicts): every verdict of an audit follows the one rule. A tier
// whose scalars fail (scalar_rejection) trusts none of its statistics; "more precise than X" rests only on
// an X that is trusted; an ensemble compared with a reference the rule rejects proves nothing; the
// vectorised double engine never trusts what the double tier does not.
void expect_one_rule(const Scene& scene, const AuditReport& rep) {
  const auto verdict = [&rep](const std::string& tier, const std::string& stat) -> std::string {
    for (const Verdict& v : rep.verdicts)
      if (v.tier == tier && v.statistic == stat) return v.verdict;
    return "";
  };
  const auto trusted = [](const std::string& v) { return v == "trusted" || v == "trusted as a statistic"; };
  for (const ScalarCheck& sc : rep.scalars) {
    if (!scalar_rejection(scene, sc)) continue;
    for (const char* stat : {"P(t)", "kappa", "alpha"})
      EXPECT_EQ(verdict(sc.tier, stat), "not trusted") << sc.tier << " " << stat;
  }
  for (const Verdict& v : rep.verdicts) {
    if (v.statistic == "trajectories") continue;
    for (const char* base : {"float", "double", "long_double"}) {
      if (v.reason.find(std::string("more precise than ") + base + ",") != std::string::npos) {
        EXPECT_TRUE(trusted(verdict(base, v.statistic))) << v.tier << " leans on " << base << ": " << v.reason;
      }
    }
    if (v.tier == "double_simd") {
      EXPECT_TRUE(!trusted(v.verdict) || trusted(verdict("double", v.statistic))) << v.reason;
      EXPECT_EQ(trusted(v.verdict), trusted(verdict("double", v.statistic))) << v.reason;
    }
  }
}

AuditOptions small_audit() {
  AuditOptions o;
  o.tiers = {"float", "double", "long_double", "dd", "float128"};
  o.sample = 8;
  o.stratify_particles = 2000;
  o.stats_particles = 4000;
  o.max_collisions = 200;
  return o;
}

// omega = 1e15 at t_max = 2e4 (omega t_max = 2e19, beyond long double's 2^64): the issue that asked for one
// verdict saw double's P(t) "not trusted" beside double_simd "trusted as a statistic", and dd "trusted: more
// precise than long double" beside long double "not trusted". Now float, double, long double and the
// vectorised engine are not trusted (their phase is lost), dd and float128 untested (no ensemble of their
// own and nothing trusted below them). On omega = 2/3 the same rule trusts the ensemble tiers.
TEST(Extremes, OneTrustVerdictAtOmega1e15) {
  const Scene fast = scene_with({"leak.omega=1e15", "ensemble.particles=4000", "run.t_max=2000"});
  const AuditReport rep = audit(fast, small_audit());
  expect_one_rule(fast, rep);
  for (const Verdict& v : rep.verdicts) {
    if (v.statistic == "trajectories") continue;
    if (v.tier == "dd" || v.tier == "float128")
      EXPECT_EQ(v.verdict, "untested") << v.tier << " " << v.statistic << ": " << v.reason;
    else
      EXPECT_EQ(v.verdict, "not trusted") << v.tier << " " << v.statistic << ": " << v.reason;
  }
  const Scene slow = scene_with({"leak.omega=2/3", "ensemble.particles=4000", "run.t_max=2000"});
  const AuditReport ok = audit(slow, small_audit());
  expect_one_rule(slow, ok);
  for (const Verdict& v : ok.verdicts) {
    if (v.statistic == "P(t)" && (v.tier == "double" || v.tier == "double_simd" || v.tier == "long_double")) {
      EXPECT_NE(v.verdict, "not trusted") << v.tier << ": " << v.reason;
    }
  }
}

// simulate applies the same rule to the tier it runs: at omega = 1e15 it warns (text and summary.json's
// precision_warning); at omega = 2/3 it does not. run.tier = auto finds no ensemble tier it may trust there
// and refuses with one line naming run.tier; where one is trusted, the run says which it chose and why.
TEST(Extremes, SimulateWarnsWhereTheAuditWouldNotTrustItsTier) {
  RunOptions o;
  const Scene fast = scene_with({"leak.omega=1e15", "ensemble.particles=2000", "run.t_max=2000"});
  const RunSummary r = run_scene(plan_run(fast, o), o);
  ASSERT_TRUE(r.precision_warning.has_value());
  EXPECT_NE(r.precision_warning->find("leak phase not resolved at double"), std::string::npos) << *r.precision_warning;
  EXPECT_NE(summary_text(r).find("warning: the audit does not trust P(t), kappa or alpha at the double tier"),
            std::string::npos)
      << summary_text(r);
  EXPECT_TRUE(summary_json(r, {}).at("precision_warning").is_string());
  const Scene slow = scene_with({"leak.omega=2/3", "ensemble.particles=2000", "run.t_max=2000"});
  const RunSummary q = run_scene(plan_run(slow, o), o);
  EXPECT_FALSE(q.precision_warning.has_value()) << *q.precision_warning;
  EXPECT_TRUE(summary_json(q, {}).at("precision_warning").is_null());

  Scene auto_fast = fast;
  auto_fast.tier = Tier::auto_;
  try {
    run_scene(plan_run(auto_fast, o), o);
    ADD_FAILURE() << "run.tier = auto ran a tier the audit does not trust";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("run.tier"), std::string::npos) << what;
    EXPECT_NE(what.find("no ensemble tier is trusted"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  Scene auto_slow = slow;
  auto_slow.tier = Tier::auto_;
  const RunSummary a = run_scene(plan_run(auto_slow, o), o);
  ASSERT_TRUE(a.tier_choice.has_value());
  EXPECT_NE(summary_text(a).find("tier  : auto chose " + to_string(a.scene.tier)), std::string::npos)
      << summary_text(a);
}

namespace {

// A report of two tiers (double, long double) filled by hand and judged (verify/audit.hpp, judge): each tier
// reproduces `share` of its `compared` sampled escapes, and its ensemble agrees with its reference or not.
AuditReport judged(const std::string& omega, double share, std::size_t compared, bool consistent) {
  AuditReport rep;
  for (const char* t : {"double", "long_double"}) {
    TierAudit ta;
    ta.name = t;
    ta.escape_time_exact_fraction = share;
    ta.escapes_compared = compared;
    rep.tiers.push_back(ta);
    StatisticsCheck st;
    st.tier = t;
    st.consistent = consistent;
    rep.statistics.push_back(st);
  }
  judge(parse_scene("[leak]\nomega = \"" + omega + "\"\n"), rep);
  return rep;
}

std::string verdict_of(const AuditReport& rep, const std::string& tier, const std::string& statistic) {
  for (const Verdict& v : rep.verdicts)
    if (v.tier == tier && v.statistic == statistic) return v.verdict;
  return "(no verdict)";
}

}  // namespace

// The trajectories rule on either side of its edge: 99% of the sampled escapes reproduced is trusted, and with it
// every statistic, whatever the ensembles say; one ulp under 99% is not, and the statistics then follow the
// ensemble ("trusted as a statistic" where it agrees, "not trusted" where it differs); nothing compared is not
// trusted, however perfect its share.
TEST(Trust, TrajectoriesAreTrustedFromTheirShareOfReproducedEscapes) {
  const double under = std::nextafter(kTrustedEscapeShare, 0.0);
  for (const char* tier : {"double", "long_double"}) {
    EXPECT_EQ(verdict_of(judged("0", kTrustedEscapeShare, 100, false), tier, "trajectories"), "trusted") << tier;
    EXPECT_EQ(verdict_of(judged("0", kTrustedEscapeShare, 100, false), tier, "P(t)"), "trusted") << tier;
    EXPECT_EQ(verdict_of(judged("0", under, 100, false), tier, "trajectories"), "not trusted") << tier;
    EXPECT_EQ(verdict_of(judged("0", under, 100, false), tier, "P(t)"), "not trusted") << tier;
    EXPECT_EQ(verdict_of(judged("0", under, 100, true), tier, "kappa"), "trusted as a statistic") << tier;
    EXPECT_EQ(verdict_of(judged("0", 1.0, 0, true), tier, "trajectories"), "not trusted") << tier;
    EXPECT_EQ(verdict_of(judged("0", 1.0, 0, true), tier, "alpha"), "trusted as a statistic") << tier;
  }
}

// A tier whose scalars fail trusts none of its statistics even where every escape is reproduced, and a comparison
// against a reference whose scalars fail tests nothing: at omega = 1e9 (t_max = 20000) double's phase error is
// above 1e-3 of the width and long double's below, so long double's ensemble against double's is "untested" where
// it agrees and "not trusted" where it differs; at omega = 0 the same agreement is trusted as a statistic.
TEST(Trust, AReferenceThatFailsItsScalarsLeavesTheComparisonUntested) {
  const Scene fast = parse_scene("[leak]\nomega = \"1e9\"\n");
  ASSERT_TRUE(scalar_rejection(fast, scalar_check(fast, "double")).has_value());
  ASSERT_FALSE(scalar_rejection(fast, scalar_check(fast, "long_double")).has_value());
  EXPECT_EQ(verdict_of(judged("1e9", 1.0, 100, true), "double", "P(t)"), "not trusted");
  EXPECT_EQ(verdict_of(judged("1e9", 1.0, 100, true), "long_double", "P(t)"), "trusted");
  const double under = std::nextafter(kTrustedEscapeShare, 0.0);
  EXPECT_EQ(verdict_of(judged("1e9", under, 100, true), "long_double", "P(t)"), "untested");
  EXPECT_EQ(verdict_of(judged("1e9", under, 100, false), "long_double", "P(t)"), "not trusted");
  EXPECT_EQ(verdict_of(judged("0", under, 100, true), "long_double", "P(t)"), "trusted as a statistic");
}

// The ensemble rule's three tests, each on either side of 4 standard errors: the windows' largest |z| (strictly
// below 4), kappa's difference and alpha's (at most 4 errors); alpha in one ensemble and not the other differs.
TEST(Trust, EnsemblesAgreeWithinFourErrorsOnEachTest) {
  StatisticsCheck c;
  c.kappa_diff_error = 1e-4;
  c.max_abs_z = std::nextafter(kEnsembleSigmas, 0.0);
  c.kappa_diff = -kEnsembleSigmas * c.kappa_diff_error;
  EXPECT_TRUE(ensemble_consistent(c, true));
  c.max_abs_z = kEnsembleSigmas;
  EXPECT_FALSE(ensemble_consistent(c, true));
  c.max_abs_z = 0;
  c.kappa_diff = std::nextafter(kEnsembleSigmas * c.kappa_diff_error, 1.0);
  EXPECT_FALSE(ensemble_consistent(c, true));
  c.kappa_diff = 0;
  c.alpha_diff_error = 1e-3;
  c.alpha_diff = kEnsembleSigmas * c.alpha_diff_error;
  EXPECT_TRUE(ensemble_consistent(c, false));  // both have alpha: its difference decides, not their presence
  c.alpha_diff = std::nextafter(*c.alpha_diff, 1.0);
  EXPECT_FALSE(ensemble_consistent(c, true));
  c.alpha_diff.reset();
  EXPECT_TRUE(ensemble_consistent(c, true));
  EXPECT_FALSE(ensemble_consistent(c, false));
}

// The scalar rules on either side of their edges: time steps at t_max of survival_dt / 100 pass and one ulp
// coarser fail; a moving leak's phase error just under 1e-3 of its width passes and just over fails (omega = 5e6 is
// held exactly, so the phase error is t's rounding alone, whatever the width).
TEST(Trust, ScalarRulesDecideOnEitherSide) {
  const Scene s = parse_scene("");
  ScalarCheck c = scalar_check(s, "double");
  ASSERT_TRUE(c.phase_resolved);
  c.time_ulp_at_tmax = s.survival_dt / 100;
  EXPECT_FALSE(scalar_rejection(s, c).has_value());
  c.time_ulp_at_tmax = std::nextafter(s.survival_dt / 100, 1.0);
  ASSERT_TRUE(scalar_rejection(s, c).has_value());
  EXPECT_NE(scalar_rejection(s, c)->find("coarse against survival_dt"), std::string::npos) << *scalar_rejection(s, c);
  const ScalarCheck fast = scalar_check(parse_scene("", {"leak.omega=5e6"}), "double");
  ASSERT_EQ(fast.omega_split_drift, 0.0);
  const auto resolved_at = [&](double f) {
    char w[64];
    std::snprintf(w, sizeof w, "leak.width=%.17g", 1e3 * fast.phase_error_at_tmax * f);
    const Scene t = parse_scene("", {"leak.omega=5e6", w});
    const ScalarCheck k = scalar_check(t, "double");
    EXPECT_EQ(k.phase_error_at_tmax, fast.phase_error_at_tmax) << w;
    EXPECT_EQ(scalar_rejection(t, k).has_value(), !k.phase_resolved) << w;
    return k.phase_resolved;
  };
  EXPECT_TRUE(resolved_at(1 + 1e-9));
  EXPECT_FALSE(resolved_at(1 - 1e-9));
}

// Which leak of a list the scalars are judged by: the one whose phase error is the largest share of its own width,
// not the one with the largest error. A narrow slow leak (width 1e-4 at omega = 1e6) beside a wide fast one (0.5 at
// 2e6): the narrow one is the least resolved, although its phase error is half the other's; with the widths
// swapped, the fast one; two equal leaks, the first. Judging by the error alone (mutant
// tests/mutants/audit-share-unscaled.patch) names leaks.1 in both.
TEST(Extremes, TheLeastResolvedLeakIsJudgedAgainstItsOwnWidth) {
  const auto list = [](const char* w0, const char* w1, const char* om1) {
    return parse_scene(std::string("[[leaks]]\nwidth = \"") + w0 + "\"\nomega = \"1e6\"\n[[leaks]]\nwidth = \"" + w1 +
                       "\"\nstart = \"1/2\"\nomega = \"" + om1 + "\"\n[run]\nt_max = 2000\n");
  };
  const ScalarCheck narrow_slow = scalar_check(list("1e-4", "0.5", "2e6"), "double");
  EXPECT_EQ(narrow_slow.note.rfind("leaks.0 (the least resolved of 2)", 0), 0u) << narrow_slow.note;
  EXPECT_FALSE(narrow_slow.phase_resolved) << narrow_slow.note;
  const ScalarCheck narrow_fast = scalar_check(list("0.5", "1e-4", "2e6"), "double");
  EXPECT_EQ(narrow_fast.note.rfind("leaks.1 (the least resolved of 2)", 0), 0u) << narrow_fast.note;
  const ScalarCheck tie = scalar_check(list("0.01", "0.01", "1e6"), "double");
  EXPECT_EQ(tie.note.rfind("leaks.0 (the least resolved of 2)", 0), 0u) << tie.note;
  // the warning a run prints names it too
  const std::optional<std::string> why = scalar_rejection(list("1e-4", "0.5", "2e6"), narrow_slow);
  ASSERT_TRUE(why.has_value());
  EXPECT_EQ(why->rfind("leak phase not resolved at double: leaks.0", 0), 0u) << *why;
}

// The same rule on a table with a list of leaks (docs/tables.md): the scalars are judged by the leak whose phase is
// resolved least well. On the two-leak stadium with its second leak at omega = 1e15 the audit trusts no ensemble
// tier and run.tier = auto refuses; with both leaks stationary (and on the Sinai table) auto runs a trusted tier.
TEST(Extremes, OneTrustVerdictOnATableWithALeakList) {
  const std::string dir = std::string(rotleak::test::source_dir()) + "/data/scenes/tables/";
  const Scene fast =
      load_scene(dir + "stadium_two_leaks.toml", {"leaks.1.omega=1e15", "ensemble.particles=4000", "run.t_max=2000"});
  const ScalarCheck sc = scalar_check(fast, "double");
  EXPECT_FALSE(sc.phase_resolved);
  EXPECT_EQ(sc.note.rfind("leaks.1 (the least resolved of 2)", 0), 0u) << sc.note;
  const AuditReport rep = audit(fast, small_audit());
  expect_one_rule(fast, rep);
  for (const Verdict& v : rep.verdicts) {
    if (v.statistic == "trajectories" || v.tier == "dd" || v.tier == "float128") continue;
    EXPECT_EQ(v.verdict, "not trusted") << v.tier << " " << v.statistic << ": " << v.reason;
  }
  RunOptions o;
  Scene auto_fast = fast;
  auto_fast.tier = Tier::auto_;
  EXPECT_THROW(run_scene(plan_run(auto_fast, o), o), InputError);
  for (const char* file : {"stadium_two_leaks.toml", "sinai.toml"}) {
    Scene slow = load_scene(dir + file, {"ensemble.particles=4000", "run.t_max=1000"});
    EXPECT_TRUE(scalar_check(slow, "double").phase_resolved) << file;
    slow.tier = Tier::auto_;
    const RunSummary a = run_scene(plan_run(slow, o), o);
    ASSERT_TRUE(a.tier_choice.has_value()) << file;
    EXPECT_NE(summary_text(a).find("tier  : auto chose " + to_string(a.scene.tier)), std::string::npos)
        << summary_text(a);
  }
}

TEST(Extremes, LongRunsCoarsenFloatTime) {
  const Scene s = scene_with({"run.t_max=1e7"});
  EXPECT_EQ(scalar_check(s, "float").time_ulp_at_tmax, 1.0);  // 2^23 <= 1e7 < 2^24: ulp 1
  EXPECT_LT(scalar_check(s, "double").time_ulp_at_tmax, 2e-9);
  // and the run itself: a long-lived bouncing ball reaches t_max = 1e7 in double (tiny leak, no escape
  // route for it), survival bins of 1000 keep the histogram small
  const Scene run = scene_with({"run.t_max=1e7", "observe.survival_dt=1000", "ensemble.particles=10", "leak.width=1e-6",
                                "fit.kappa_window=[0, 1e6]"});
  const RunResult r = run_ensemble(run, RunOptions{});
  EXPECT_EQ(r.tally.escaped + r.tally.survived, 10u);
  EXPECT_EQ(r.tally.stuck, 0u);
  // a survivor makes t_max / mean free path = 4.6e6 collisions; a leak of 1e-6 lets each escape with
  // probability 1 - exp(-4.6) ~ 0.99 somewhere along the way, on average after ~1e6 collisions
  EXPECT_GT(r.tally.collisions, 10u * 100000u);
}

// liouville(10) in double is a nearby rational; the audit says so and over what horizon it does not matter.
TEST(Extremes, LiouvilleOmegaIsHeldAsANearbyRational) {
  const ScalarCheck c = scalar_check(scene_with({"leak.omega=liouville(10)"}), "double");
  EXPECT_TRUE(c.omega_is_rounded);
  EXPECT_GT(c.omega_single_drift, 0);
  EXPECT_LT(c.omega_single_drift, 1e-12);                           // |omega - fl(omega)| <= 2^-57, times 2e4
  EXPECT_GT(c.single_matters_after, 1e8);                           // rounded once, drift reaches 1e-5 only after ~1e12
  EXPECT_GT(c.split_matters_after, c.single_matters_after * 1e10);  // hi + lo: far longer
  EXPECT_TRUE(c.phase_resolved);
  EXPECT_NE(c.note.find("nearby rational"), std::string::npos);
}

// MPFI: more bits certify more collisions, and a certified escape is the truth's escape.
TEST(Extremes, IntervalCertificatesGrowWithBits) {
  const Scene s = scene_with({});
  const InitialConditions ic(s.seed, s.init, 4, 1, 1);
  const InitialDraw d = ic.draw(1);
  const Certificate c64 = certify_at(s, d, 64, 1000), c256 = certify_at(s, d, 256, 1000);
  EXPECT_LT(c64.certified_collisions, c256.certified_collisions);
  const auto attempts = certify(s, d, 64, 4096, 1000);
  ASSERT_TRUE(attempts.back().escape_certified);
  ShadowOptions opt;
  opt.tiers = {"double"};
  const ShadowResult truth = shadow(s, 1, opt);
  ASSERT_TRUE(truth.truth.escape.has_value());
  EXPECT_EQ(attempts.back().escape_collision, *truth.truth.escape);
  const double t_true = truth.truth.t[*truth.truth.escape - 1];
  EXPECT_LE(attempts.back().escape_time_lo, t_true);
  EXPECT_GE(attempts.back().escape_time_hi, t_true);
}
