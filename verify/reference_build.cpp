// Building the reference set: choosing each case's particle, certifying its collisions in MPFI, measuring
// the error model's gains, fingerprinting every tier (rotleak verify --regenerate).
#include "verify/reference.hpp"

#include <omp.h>

#include <toml++/toml.h>
#include <atomic>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>

#include "io/scene_file.hpp"
#include "numeric/input.hpp"
#include "verify/reference_detail.hpp"

namespace rotleak {

using namespace reference_detail;

namespace {

// ---- choosing a case ----

struct Candidate {
  double score;  // smaller is better
  std::uint64_t id;
};

/// Score of an ensemble member for a search (double tier over the first K collisions); nullopt: not a candidate.
std::optional<double> search_score(const std::string& search, const Scene& scene, const InitialDraw& draw,
                                   std::size_t K) {
  const Model<double> model = model_of<double>(scene);
  const Stadium<double>& st = model.stadium;
  double best = std::numeric_limits<double>::infinity();
  long run = 0, longest = 0;
  bool found = false;
  trace(model, draw, K, [&](const TraceStep<double>& s) {
    const double sv = st.s_of(s.piece, s.q);
    if (search == "grazing") {
      if (s.piece == Piece::right_arc || s.piece == Piece::left_arc)
        best = std::min(best, 1 - std::abs(st.birkhoff_p(s.piece, s.q, s.v)));
    } else if (search == "junction") {
      for (int j = 0; j < 4; ++j) {
        double d = std::abs(sv - st.junction(j));
        d = std::min(d, 1 - d);
        best = std::min(best, d);
      }
    } else if (search == "bouncing_ball") {
      run = (s.piece == Piece::top || s.piece == Piece::bottom) ? run + 1 : 0;
      longest = std::max(longest, run);
    } else if (search == "near_edge_escape") {
      if (s.in_leak) {
        const double c = model.leak.schedule().phase(s.t);
        best = formula::distance_to_leak_end(sv, c, model.leak.half_width());
        found = true;
        return false;
      }
    }
    return true;
  });
  if (search == "bouncing_ball") return -static_cast<double>(longest);
  if (search == "near_edge_escape" && !found) return std::nullopt;
  return best;
}

InitialDraw choose_draw(const CaseSpec& spec, std::optional<std::uint64_t>& id, std::string& note) {
  const InitialConditions ic = initial_conditions(spec.scene);
  if (spec.id) {
    id = spec.id;
    return ic.draw(*spec.id);
  }
  if (!spec.search.empty()) {
    std::optional<Candidate> best;
    for (std::uint64_t i = 0; i < spec.search_ids; ++i) {
      const auto score = search_score(spec.search, spec.scene, ic.draw(i),
                                      spec.search == "bouncing_ball" ? spec.collisions : spec.search_collisions);
      if (score && (!best || *score < best->score)) best = Candidate{*score, i};
    }
    if (!best) throw std::runtime_error(spec.name + ": no ensemble member fits search \"" + spec.search + "\"");
    id = best->id;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "; chosen among ids [0, %llu) by %s in the first %zu collisions (score %.3g in double)",
                  static_cast<unsigned long long>(spec.search_ids), spec.search.c_str(),
                  spec.search == "bouncing_ball" ? spec.collisions : spec.search_collisions, best->score);
    note += buf;
    return ic.draw(best->id);
  }
  InitialDraw d;
  const Stadium<double> st(spec.scene.d, spec.scene.r);
  auto value = [&](const std::string& text, const char* key) {
    if (text.rfind("junction", 0) == 0 && text.size() == 9 && text[8] >= '0' && text[8] <= '3')
      return st.junction(text[8] - '0');
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);  // a binary initial datum: the nearest double is the datum
    if (end == text.c_str() || *end != '\0')
      throw InputError(spec.name + "." + key, text, "a number, or junction0..junction3");
    return v;
  };
  d.s = value(*spec.s, "s");
  d.p = value(*spec.p, "p");
  return d;
}

// ---- certification ----

struct Certified {
  long bits = 0;
  std::vector<RefStep> steps;
};

Certified certify_steps(const Scene& scene, const InitialDraw& draw, std::size_t K) {
  Certified best;
  const double L = perimeter(scene);
  for (long bits = kReferenceStartBits; bits <= kReferenceMaxBits; bits *= 2) {
    MpfrPrecision working(bits);
    Certified run;
    run.bits = bits;
    const Model<Mpfi> model = model_of<Mpfi>(scene);
    const int digits = static_cast<int>(static_cast<double>(bits) * 0.30103) - 4;
    try {
      trace(model, draw, K, [&](const TraceStep<Mpfi>& st) {
        const Mpfi s = model.stadium.s_of(st.piece, st.q);
        const Mpfi p = model.stadium.birkhoff_p(st.piece, st.q, st.v);
        const Mpfi c = model.leak.schedule().phase(st.t);
        RefStep r;
        r.k = st.k;
        r.piece = st.piece;
        r.in_leak = st.in_leak;
        r.radius = std::max({st.t.width(), L * s.width(), p.width()}) / 2;
        Mpfr tm, sm, pm, cm;
        mpfi_mid(tm.data(), st.t.data());
        mpfi_mid(sm.data(), s.data());
        mpfi_mid(pm.data(), p.data());
        mpfi_mid(cm.data(), c.data());
        const Mpfr hw = num_traits<Mpfr>::from_exact(scene.width / ExactReal::parse("2"));
        const Mpfr off = circular_offset(sm, cm);
        const Mpfr margin = hw - abs(off);
        r.margin = mpfr_get_d(margin.data(), MPFR_RNDN);
        // digits: the full certified precision for now; trimmed once the gains are known
        r.t = decimal(tm.data(), digits);
        r.s = decimal(sm.data(), digits);
        r.p = decimal(pm.data(), digits);
        r.phase = decimal(cm.data(), 20);
        run.steps.push_back(std::move(r));
        return true;
      });
    } catch (const UncertainDecision&) {
      // undecided at these bits: the steps so far are certified
    }
    if (run.steps.size() > best.steps.size() || best.bits == 0) best = std::move(run);
    if (best.steps.size() == K) break;
  }
  return best;
}

/// W_k: the largest error growth seen in MPFR runs at several precisions (kGainBits) against the
/// certified values, each counted while it stays well below saturation. One precision is not
/// enough: where its first operations happen to be exact on the double inputs, or the orbit is
/// near-tangent, one run's error can stay hundreds of times below another's.
void measure_gains(const Scene& scene, const InitialDraw& draw, std::vector<RefStep>& steps) {
  const double L = perimeter(scene);
  RefCase tmp;
  tmp.steps = steps;
  const std::vector<ParsedStep> ref = parse_steps(tmp, L);
  std::vector<double> seen(steps.size(), 0);
  std::vector<bool> valid(steps.size(), false);
  for (const long bits : kGainBits) {
    const double scale = std::ldexp(1.0, static_cast<int>(bits));
    MpfrPrecision working(bits);
    std::size_t i = 0;
    follow<Mpfr>(scene, draw, steps.size(), [&](std::size_t, const Seen& run, const auto&, const auto&) {
      const double d = run.piece == steps[i].piece ? divergence(run, ref[i].t, ref[i].s, ref[i].p, L)
                                                   : std::numeric_limits<double>::infinity();
      if (!(d <= kGainSaturation)) return false;
      seen[i] = std::max(seen[i], d * scale);
      valid[i] = true;
      ++i;
      return true;
    });
  }
  // The floor: rounding of t itself (1 + |t|), and at each collision an error of ~u / cos(theta) in
  // where the next flight ends (a near-tangent flight turns a rounding of its start into a long
  // slide along the boundary), summed over the collisions so far: the linear model's worst case
  // for orbits whose gain runs were lucky (whispering-gallery runs along an arc).
  double running = 0, grazing = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!valid[i]) {  // every gain run had saturated: beyond any tier's horizon
      for (; i < steps.size(); ++i) steps[i].gain = std::numeric_limits<double>::infinity();
      break;
    }
    const double p = std::abs(mpfr_get_d(ref[i].p.v, MPFR_RNDN));
    grazing += 1 / std::sqrt(std::max((1 - p) * (1 + p), 1e-300));
    running = std::max(running, seen[i]);
    steps[i].gain = std::max(running, 1 + ref[i].t_abs + grazing);
  }
}

/// Trims the stored digits to what the finest standard tier (mpfr:256) needs, with 3 to spare.
void trim_digits(std::vector<RefStep>& steps, double L) {
  const double u = std::ldexp(1.0, -256);
  for (RefStep& st : steps) {
    Big t;
    parse_big(t, st.t);
    const double scale = std::max({std::abs(mpfr_get_d(t.v, MPFR_RNDN)), L, 1.0});
    const double need = std::isfinite(st.gain) ? u * st.gain / scale : 1e-3;
    const int d = std::clamp(static_cast<int>(std::ceil(-std::log10(need))) + 3, 20, digits_of(st.t));
    for (std::string* v : {&st.t, &st.s, &st.p}) {
      Big x;
      parse_big(x, *v);
      *v = decimal(x.v, d);
    }
  }
}

template <class R>
std::vector<std::pair<std::size_t, std::uint64_t>> fingerprint(const Scene& scene, const InitialDraw& draw,
                                                               std::size_t K) {
  std::vector<std::pair<std::size_t, std::uint64_t>> out;
  follow<R>(scene, draw, K, [&](std::size_t k, const Seen& seen, const auto&, const auto&) {
    if ((k & (k - 1)) == 0 || k == K) out.emplace_back(k, seen.hash);
    return true;
  });
  return out;
}

}  // namespace

std::vector<CaseSpec> read_case_specs(const std::string& path) {
  toml::table doc;
  try {
    doc = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, std::string(e.description()), "a TOML file of [[case]] tables");
  }
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  std::vector<CaseSpec> out;
  const toml::array* cases = doc["case"].as_array();
  if (!cases) throw InputError(path, "no [[case]]", "at least one [[case]] table");
  for (const auto& node : *cases) {
    const toml::table* t = node.as_table();
    if (!t) throw InputError(path, "case", "a table");
    CaseSpec spec;
    spec.name = t->get("name") ? t->get("name")->value_or(std::string{}) : "";
    if (spec.name.empty()) throw InputError(path + ": case.name", "(missing)", "a name");
    const std::string key = "case " + spec.name;
    for (char ch : spec.name)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-' && ch != '.')
        throw InputError(path + ": case.name", spec.name, "letters, digits, '_', '-' and '.' (it names a file)");
    spec.kind = (*t)["kind"].value_or(std::string{});
    spec.note = (*t)["note"].value_or(std::string{});
    const std::string scene = (*t)["scene"].value_or(std::string{});
    if (scene.empty()) throw InputError(key + ".scene", "(missing)", "a scene file relative to " + path);
    std::vector<std::string> sets;
    if (const toml::array* a = (*t)["set"].as_array())
      for (const auto& s : *a) sets.push_back(s.value_or(std::string{}));
    spec.scene = load_scene((base / scene).string(), sets);
    spec.collisions = static_cast<std::size_t>((*t)["collisions"].value_or(int64_t{200}));
    if (auto id = (*t)["particle"].value<int64_t>()) spec.id = static_cast<std::uint64_t>(*id);
    if (auto s = (*t)["s"].value<std::string>()) spec.s = *s;
    if (auto p = (*t)["p"].value<std::string>()) spec.p = *p;
    spec.search = (*t)["search"].value_or(std::string{});
    spec.search_ids = static_cast<std::uint64_t>((*t)["search_ids"].value_or(int64_t{20000}));
    spec.search_collisions = static_cast<std::size_t>((*t)["search_collisions"].value_or(int64_t{20}));
    const int ways = (spec.id ? 1 : 0) + (spec.s || spec.p ? 1 : 0) + (spec.search.empty() ? 0 : 1);
    if (ways != 1 || (spec.s.has_value() != spec.p.has_value()))
      throw InputError(key, "particle/s,p/search", "exactly one of: particle = ID, s and p, search = ...");
    if (!spec.search.empty() && spec.search != "grazing" && spec.search != "junction" &&
        spec.search != "bouncing_ball" && spec.search != "near_edge_escape")
      throw InputError(key + ".search", spec.search, "grazing, junction, bouncing_ball or near_edge_escape");
    out.push_back(std::move(spec));
  }
  return out;
}

RefCase build_case(const CaseSpec& spec) {
  RefCase c;
  c.name = spec.name;
  c.kind = spec.kind;
  c.note = spec.note;
  c.scene = spec.scene;
  c.scene.source.clear();
  c.scene_toml = scene_to_toml(c.scene);
  c.scene = parse_scene(c.scene_toml, {}, "reference case " + c.name);
  c.draw = choose_draw(spec, c.id, c.note);
  c.requested = spec.collisions;
  Certified cert = certify_steps(c.scene, c.draw, spec.collisions);
  c.bits = cert.bits;
  c.steps = std::move(cert.steps);
  measure_gains(c.scene, c.draw, c.steps);
  trim_digits(c.steps, perimeter(c.scene));
  for (const std::string& tier : reference_tiers())
    c.fingerprints[tier] = with_tier(tier, [&](auto type) {
      using R = typename decltype(type)::type;
      return fingerprint<R>(c.scene, c.draw, c.steps.size());
    });
  return c;
}

ReferenceSet build_reference(const std::vector<CaseSpec>& specs, const std::string& provenance_json, int threads,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
  ReferenceSet set;
  set.provenance_json = provenance_json;
  set.cases.resize(specs.size());
  std::atomic<std::size_t> done{0};
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads())
  for (std::size_t i = 0; i < specs.size(); ++i) {
    try {
      set.cases[i] = build_case(specs[i]);
    } catch (...) {
#pragma omp critical(rotleak_verify_error)
      if (!error) error = std::current_exception();
    }
    const std::size_t d = ++done;
    if (progress && omp_get_thread_num() == 0) progress(d, specs.size());
  }
  if (error) std::rethrow_exception(error);
  return set;
}

}  // namespace rotleak
