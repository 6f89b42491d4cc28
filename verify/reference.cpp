#include "verify/reference.hpp"

#include <gmpxx.h>
#include <mpfr.h>
#include <omp.h>

#include <toml++/toml.h>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "io/files.hpp"
#include "io/json.hpp"
#include "io/scene_file.hpp"
#include "io/text.hpp"
#include "numeric/input.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "verify/trace.hpp"

namespace rotleak {

namespace {

/// Precision at which reported values are compared (the stored digits need far less).
constexpr long kCompareBits = 1024;

const char* piece_name(Piece p) {
  switch (p) {
    case Piece::top:
      return "top";
    case Piece::right_arc:
      return "right_arc";
    case Piece::bottom:
      return "bottom";
    case Piece::left_arc:
      return "left_arc";
  }
  return "?";
}

Piece piece_of(const std::string& s) {
  for (int k = 0; k < 4; ++k)
    if (s == piece_name(static_cast<Piece>(k))) return static_cast<Piece>(k);
  throw std::runtime_error("unknown piece \"" + s + "\"");
}

/// An MPFR number at kCompareBits (heap: the comparisons are few).
struct Big {
  mpfr_t v;
  Big() { mpfr_init2(v, kCompareBits); }
  Big(const Big&) = delete;
  Big& operator=(const Big&) = delete;
  ~Big() { mpfr_clear(v); }
};

void parse_big(Big& out, const std::string& text) {
  if (mpfr_set_str(out.v, text.c_str(), 10, MPFR_RNDN) != 0 && !mpfr_number_p(out.v))
    throw std::runtime_error("not a number: \"" + text + "\"");
}

/// |a - b| rounded up to a double; `circular`: the distance on the circle of length 1.
double distance(const Big& a, const Big& b, bool circular = false) {
  Big d;
  mpfr_sub(d.v, a.v, b.v, MPFR_RNDN);
  if (circular) {  // d - round(d)
    Big n;
    mpfr_round(n.v, d.v);
    mpfr_sub(d.v, d.v, n.v, MPFR_RNDN);
  }
  return std::abs(mpfr_get_d(d.v, MPFR_RNDU));
}

std::string decimal(mpfr_srcptr x, int digits) {
  char* buf = nullptr;
  mpfr_asprintf(&buf, "%.*Re", digits - 1, x);
  std::string s(buf);
  mpfr_free_str(buf);
  return s;
}

/// Significant digits of a stored decimal.
int digits_of(const std::string& s) {
  int n = 0;
  bool started = false;
  for (char ch : s) {
    if (ch == 'e' || ch == 'E') break;
    if (ch >= '1' && ch <= '9') started = true;
    if (ch >= '0' && ch <= '9' && started) ++n;
  }
  return std::max(n, 1);
}

std::string hex(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

double from_hex(const std::string& s, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') throw std::runtime_error(what + ": not a number: \"" + s + "\"");
  return v;
}

// FNV-1a, 64 bits.
void mix(std::uint64_t& h, const void* data, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 1099511628211ULL;
  }
}
constexpr std::uint64_t kHashSeed = 14695981039346656037ULL;

/// Mixes the exact value of x (sign, exponent, odd significand in hex): independent of the type's layout.
template <class R>
void mix_value(std::uint64_t& h, const R& x) {
  mpfr_t m;
  mpfr_init2(m, 4096);  // exact for every tier here (a double-double's two parts included)
  num_traits<R>::to_mpfr(m, x);
  std::string text = "0";
  if (!mpfr_zero_p(m)) {
    mpz_class z;
    long e = mpfr_get_z_2exp(z.get_mpz_t(), m);
    const mp_bitcnt_t tz = mpz_scan1(z.get_mpz_t(), 0);
    z >>= tz;
    e += static_cast<long>(tz);
    text = z.get_str(16) + "p" + std::to_string(e);
  }
  mpfr_clear(m);
  mix(h, text.data(), text.size());
  mix(h, "|", 1);
}

/// One collision as the replays see it: reported values at kCompareBits.
struct Seen {
  Piece piece;
  bool in_leak;
  Big t, s, p, phase;
  std::uint64_t hash;
};

/// Follows c's particle through at most K collisions in R (the trace of verify/trace.hpp), calling
/// on(k, Seen&, step) after each; stops when on returns false. Interval tiers may throw UncertainDecision.
template <class R, class On>
void follow(const Scene& scene, const InitialDraw& draw, std::size_t K, On&& on) {
  const Model<R> model = model_of<R>(scene);
  std::uint64_t h = kHashSeed;
  trace(model, draw, K, [&](const TraceStep<R>& st) {
    Seen seen;
    seen.piece = st.piece;
    seen.in_leak = st.in_leak;
    const R s = model.stadium.s_of(st.piece, st.q);
    const R p = model.stadium.birkhoff_p(st.piece, st.q, st.v);
    const R c = model.leak.schedule().phase(st.t);
    num_traits<R>::to_mpfr(seen.t.v, st.t);
    num_traits<R>::to_mpfr(seen.s.v, s);
    num_traits<R>::to_mpfr(seen.p.v, p);
    num_traits<R>::to_mpfr(seen.phase.v, c);
    const int code = static_cast<int>(st.piece) * 2 + (st.in_leak ? 1 : 0);
    mix(h, &code, sizeof code);
    mix_value(h, st.t);
    mix_value(h, st.q.x);
    mix_value(h, st.q.y);
    mix_value(h, st.v.x);
    mix_value(h, st.v.y);
    seen.hash = h;
    return on(st.k, seen, st, model);
  });
}

double perimeter(const Scene& sc) { return Stadium<double>(sc.d, sc.r).perimeter(); }
double omega_of(const Scene& sc) { return round_exact<double>(sc.omega); }

/// max(|dt|, L |ds| on the circle, |dp|) between what a tier saw and the reference.
double divergence(const Seen& a, const Big& t, const Big& s, const Big& p, double L) {
  return std::max({distance(a.t, t), L * distance(a.s, s, true), distance(a.p, p)});
}

struct ParsedStep {
  Big t, s, p;
  double resolution = 0;  ///< what the stored digits cannot say, in the metric
  double t_abs = 0;
  double junction = 0;  ///< distance along the boundary to the nearest junction (which piece is hit)
};

std::vector<ParsedStep> parse_steps(const RefCase& c, double L) {
  std::vector<ParsedStep> out(c.steps.size());
  MpfrPrecision working(kCompareBits);
  const Stadium<Mpfr> stadium(c.scene.d, c.scene.r);
  Big j[4];
  for (int k = 0; k < 4; ++k) mpfr_set(j[k].v, stadium.junction(k).data(), MPFR_RNDN);
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    const RefStep& st = c.steps[i];
    parse_big(out[i].t, st.t);
    parse_big(out[i].s, st.s);
    parse_big(out[i].p, st.p);
    out[i].t_abs = std::abs(mpfr_get_d(out[i].t.v, MPFR_RNDN));
    const int d = std::min({digits_of(st.t), digits_of(st.s), digits_of(st.p)});
    out[i].resolution = std::pow(10.0, 1 - d) * std::max({out[i].t_abs, L, 1.0});
    out[i].junction = L * std::min({distance(out[i].s, j[0], true), distance(out[i].s, j[1], true),
                                    distance(out[i].s, j[2], true), distance(out[i].s, j[3], true)});
  }
  return out;
}

/// The leak margin of a collision, in length, that a run at roundoff u resolves.
bool decision_required(const RefStep& st, double u, double L, double omega) {
  return std::abs(st.margin) * L > kSafety * u * st.gain * (1 + std::abs(omega) * L);
}

/// The last collision a run at roundoff u can follow: its predicted error below kHorizonTolerance,
/// and every hit so far further from a junction than that error (else which piece it hits is moot).
std::size_t horizon(const RefCase& c, const std::vector<ParsedStep>& ref, double u) {
  std::size_t h = 0;
  for (std::size_t i = 0; i < c.steps.size(); ++i) {
    const double e = u * c.steps[i].gain;
    if (e > kHorizonTolerance || ref[i].junction <= kSafety * e) break;
    h = c.steps[i].k;
  }
  return h;
}

double unit_roundoff(const std::string& tier) { return std::ldexp(1.0, -static_cast<int>(tier_bits(tier))); }

json error_model_json() {
  return {{"metric", "max(|dt|, L |ds|, |dp|)"},
          {"safety", kSafety},
          {"horizon_tolerance", kHorizonTolerance},
          {"gain_bits", std::vector<long>(std::begin(kGainBits), std::end(kGainBits))},
          {"gain_saturation", kGainSaturation}};
}

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

// ---- reading and writing ----

std::string steps_csv(const RefCase& c) {
  std::string out = "k,piece,t,s,p,phase,in_leak,margin,radius,gain\n";
  char buf[200];
  for (const RefStep& st : c.steps) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g\n", st.margin, st.radius, st.gain);
    out += std::to_string(st.k) + "," + piece_name(st.piece) + "," + st.t + "," + st.s + "," + st.p + "," + st.phase +
           "," + (st.in_leak ? "1" : "0") + "," + buf;
  }
  return out;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

std::vector<RefStep> read_steps(const std::filesystem::path& path) {
  // strtod, not stod: a radius of 1e-310 is a fine (subnormal) number, which stod refuses
  auto number = [&](const std::string& text) { return from_hex(text, path.string()); };
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::string line;
  std::getline(in, line);
  if (line != "k,piece,t,s,p,phase,in_leak,margin,radius,gain")
    throw std::runtime_error(path.string() + ": unexpected header");
  std::vector<RefStep> out;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto f = split(line, ',');
    if (f.size() != 10) throw std::runtime_error(path.string() + ": a line without 10 fields: " + line.substr(0, 80));
    RefStep st;
    st.k = std::stoul(f[0]);
    st.piece = piece_of(f[1]);
    st.t = f[2];
    st.s = f[3];
    st.p = f[4];
    st.phase = f[5];
    st.in_leak = f[6] == "1";
    st.margin = number(f[7]);
    st.radius = number(f[8]);
    st.gain = number(f[9]);
    if (st.k != out.size() + 1) throw std::runtime_error(path.string() + ": collisions out of order at " + f[0]);
    out.push_back(std::move(st));
  }
  return out;
}

}  // namespace

std::optional<std::size_t> RefCase::escape() const {
  for (const RefStep& st : steps)
    if (st.in_leak) return st.k;
  return std::nullopt;
}

std::vector<std::string> reference_tiers() { return {"float", "double", "long_double", "dd", "float128", "mpfr:256"}; }

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

void write_reference(const std::string& dir, const ReferenceSet& set) {
  namespace fs = std::filesystem;
  fs::create_directories(fs::path(dir) / "steps");
  json doc;
  doc["format"] = 1;
  doc["provenance"] = json::parse(set.provenance_json);
  doc["error_model"] = error_model_json();
  json cases = json::array();
  for (const RefCase& c : set.cases) {
    const std::string file = "steps/" + c.name + ".csv";
    write_file_atomic(fs::path(dir) / file, steps_csv(c));
    json j;
    j["name"] = c.name;
    j["kind"] = c.kind;
    j["note"] = c.note;
    j["particle"] = nullable(c.id);
    j["draw"] = {{"s", hex(c.draw.s)}, {"p", hex(c.draw.p)},     {"x", hex(c.draw.x)}, {"y", hex(c.draw.y)},
                 {"u", hex(c.draw.u)}, {"tau", hex(c.draw.tau)}, {"flow", c.draw.flow}};
    j["bits"] = c.bits;
    j["collisions_requested"] = c.requested;
    j["collisions"] = c.steps.size();
    j["escape"] = nullable(c.escape());
    j["steps"] = file;
    json fp = json::object();
    for (const auto& [tier, list] : c.fingerprints) {
      json a = json::array();
      for (const auto& [k, h] : list) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
        a.push_back({k, buf});
      }
      fp[tier] = a;
    }
    j["fingerprints"] = fp;
    j["scene"] = c.scene_toml;
    cases.push_back(j);
  }
  doc["cases"] = cases;
  write_file_atomic(fs::path(dir) / "reference.json", doc.dump(1) + "\n");
  // step files of cases no longer in the set go (after the new index no longer names them)
  std::set<std::string> keep;
  for (const RefCase& c : set.cases) keep.insert(c.name + ".csv");
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "steps"))
    if (entry.path().extension() == ".csv" && !keep.count(entry.path().filename().string())) fs::remove(entry.path());
}

ReferenceSet read_reference(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path index = fs::path(dir) / "reference.json";
  std::ifstream in(index);
  if (!in) throw std::runtime_error("cannot read " + index.string() + " (regenerate with rotleak verify --regenerate)");
  ReferenceSet set;
  try {
    const json doc = json::parse(in);
    if (doc.at("format").get<int>() != 1) throw std::runtime_error("unknown format");
    set.provenance_json = doc.at("provenance").dump();
    for (const json& j : doc.at("cases")) {
      RefCase c;
      c.name = j.at("name").get<std::string>();
      c.kind = j.at("kind").get<std::string>();
      c.note = j.at("note").get<std::string>();
      if (!j.at("particle").is_null()) c.id = j.at("particle").get<std::uint64_t>();
      const json& d = j.at("draw");
      const std::string what = c.name + ".draw";
      c.draw = {from_hex(d.at("s"), what), from_hex(d.at("p"), what), from_hex(d.at("x"), what),
                from_hex(d.at("y"), what), from_hex(d.at("u"), what), from_hex(d.at("tau"), what),
                d.at("flow").get<bool>()};
      c.bits = j.at("bits").get<long>();
      c.requested = j.at("collisions_requested").get<std::size_t>();
      c.scene_toml = j.at("scene").get<std::string>();
      c.scene = parse_scene(c.scene_toml, {}, "reference case " + c.name);
      c.steps = read_steps(fs::path(dir) / j.at("steps").get<std::string>());
      if (c.steps.size() != j.at("collisions").get<std::size_t>())
        throw std::runtime_error(c.name + ": the step file does not hold the collisions the index says");
      for (const auto& [tier, list] : j.at("fingerprints").items())
        for (const json& e : list)
          c.fingerprints[tier].emplace_back(e.at(0).get<std::size_t>(),
                                            std::stoull(e.at(1).get<std::string>(), nullptr, 16));
      set.cases.push_back(std::move(c));
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(index.string() + ": " + e.what());
  }
  return set;
}

TierCheck check_tier(const RefCase& c, const std::string& tier, bool check_bits) {
  TierCheck out;
  out.tier = tier;
  out.case_name = c.name;
  out.collisions = c.steps.size();
  const double L = perimeter(c.scene), omega = omega_of(c.scene);
  const std::vector<ParsedStep> ref = parse_steps(c, L);
  const auto parsed = Tier::parse(tier);
  if (!parsed || parsed->automatic()) throw std::invalid_argument(tier);

  if (parsed->interval()) {
    // An enclosure must contain the reference wherever it answers, and answer through the collisions
    // its width allows: those where the reference's own enclosure, scaled to these bits, is below the
    // horizon tolerance and every leak margin is wider than it.
    const double scale = std::ldexp(1.0, static_cast<int>(c.bits - parsed->bits));
    for (std::size_t i = 0; i < c.steps.size(); ++i) {
      const RefStep& st = c.steps[i];
      const double w = kSafety * st.radius * scale;
      if (w > kHorizonTolerance || std::abs(st.margin) * L <= w || ref[i].junction <= w) break;
      out.must_reach = st.k;
    }
    bool contained = true;
    with_tier(*parsed, [&](auto) {
      const Model<Mpfi> model = model_of<Mpfi>(c.scene);
      try {
        trace(model, c.draw, c.steps.size(), [&](const TraceStep<Mpfi>& st) {
          const std::size_t i = st.k - 1;
          const Mpfi s = model.stadium.s_of(st.piece, st.q);
          const Mpfi p = model.stadium.birkhoff_p(st.piece, st.q, st.v);
          const double slack = c.steps[i].radius + ref[i].resolution;
          auto inside = [&](const Mpfi& x, const Big& r, double stretch) {
            Big lo, hi;
            mpfr_set(lo.v, &x.data()->left, MPFR_RNDD);
            mpfr_set(hi.v, &x.data()->right, MPFR_RNDU);
            return mpfr_cmp(lo.v, r.v) <= 0 ? (mpfr_cmp(r.v, hi.v) <= 0 || distance(r, hi) * stretch <= slack)
                                            : distance(lo, r) * stretch <= slack;
          };
          const bool ok = st.piece == c.steps[i].piece && st.in_leak == c.steps[i].in_leak &&
                          inside(st.t, ref[i].t, 1) && inside(s, ref[i].s, L) && inside(p, ref[i].p, 1);
          if (!ok) {
            contained = false;
            return false;
          }
          out.matched_through = st.k;
          return true;
        });
      } catch (const UncertainDecision&) {
        out.stopped = "undecided branch at collision " + std::to_string(out.matched_through + 1);
      }
      return 0;
    });
    out.bits = "not stored";
    out.pass = contained && out.matched_through >= out.must_reach;
    if (!contained) out.first_wrong_decision = out.matched_through + 1;
    return out;
  }

  const double u = unit_roundoff(tier);
  out.must_reach = horizon(c, ref, u);
  const auto fp = c.fingerprints.find(tier);
  const bool have_fp = check_bits && fp != c.fingerprints.end();
  std::size_t fp_next = 0;
  std::optional<std::size_t> bits_differ;
  std::size_t last_fp_match = 0;
  bool matching = true;
  with_tier(*parsed, [&](auto type) {
    using R = typename decltype(type)::type;
    follow<R>(c.scene, c.draw, c.steps.size(), [&](std::size_t k, const Seen& seen, const auto&, const auto&) {
      const std::size_t i = k - 1;
      const RefStep& st = c.steps[i];
      const double e = u * st.gain;
      const double d = seen.piece == st.piece ? divergence(seen, ref[i].t, ref[i].s, ref[i].p, L)
                                              : std::numeric_limits<double>::infinity();
      const bool required = k <= out.must_reach && decision_required(st, u, L, omega);
      if (required) {
        ++out.decisions_required;
        if (seen.in_leak == st.in_leak)
          ++out.decisions_reproduced;
        else if (!out.first_wrong_decision)
          out.first_wrong_decision = k;
      }
      // the error over the model, the reference's own uncertainty included: at 300 or 1024 bits the tier
      // is finer than the reference's radius, and d / (u W_k) alone read 6.9e10 and 6.1e228 beside "pass"
      const double allowed = kSafety * e + st.radius + ref[i].resolution;
      if (k <= out.must_reach && allowed > 0) out.worst_ratio = std::max(out.worst_ratio, kSafety * d / allowed);
      const bool within = d <= allowed && (!required || seen.in_leak == st.in_leak);
      if (matching && within)
        out.matched_through = k;
      else
        matching = false;
      if (have_fp && fp_next < fp->second.size() && fp->second[fp_next].first == k) {
        if (fp->second[fp_next].second == seen.hash) {
          if (!bits_differ) last_fp_match = k;
        } else if (!bits_differ) {
          bits_differ = k;
        }
        ++fp_next;
      }
      return true;
    });
    return 0;
  });
  out.bits_compared = have_fp;
  if (!check_bits) {
    out.bits = "not checked";
  } else if (!have_fp) {
    out.bits = "not stored";
  } else if (bits_differ) {
    out.bits = "differ by collision " + std::to_string(*bits_differ) + " (identical through " +
               std::to_string(last_fp_match) + ")";
    out.bits_ok = false;
  } else if (fp_next < fp->second.size()) {
    out.bits = "trajectory shorter than the reference";
    out.bits_ok = false;
  } else {
    out.bits = "identical";
  }
  out.pass = out.matched_through >= out.must_reach && !out.first_wrong_decision && out.bits_ok;
  return out;
}

EngineCheck check_engine(const RefCase& c, Engine engine, bool fast_forward) {
  EngineCheck out;
  out.engine = to_string(engine) + (fast_forward ? "+ff" : "");
  out.case_name = c.name;
  const double u = unit_roundoff("double"), L = perimeter(c.scene), omega = omega_of(c.scene);
  const std::vector<ParsedStep> ref = parse_steps(c, L);
  std::size_t h = std::min(horizon(c, ref, u), c.steps.size() > 0 ? c.steps.size() - 1 : 0);
  if (engine == Engine::simd && !simd::available()) {
    out.expected = "not run: this CPU has no AVX2 and FMA";
    return out;
  }
  // the expected end: the first escape within the horizon, provided every decision before it is one double resolves
  std::optional<std::size_t> escape;
  for (std::size_t k = 1; k <= h; ++k) {
    const RefStep& st = c.steps[k - 1];
    if (!decision_required(st, u, L, omega)) {
      out.expected = "not decidable in double: collision " + std::to_string(k) + " lies " +
                     std::to_string(std::abs(st.margin)) + " (in s) from the leak's edge";
      return out;
    }
    if (st.in_leak) {
      escape = k;
      break;
    }
  }
  // t_max goes between collisions h and h + 1: they must be further apart than double's error there
  while (h > 0 && escape != h) {
    Big a, b;
    parse_big(a, c.steps[h - 1].t);
    parse_big(b, c.steps[h].t);
    if (distance(a, b) / 2 > kSafety * u * c.steps[h].gain) break;
    --h;
  }
  if (h == 0) {
    out.expected = "not decidable in double: no collision within its horizon";
    return out;
  }
  out.checked = true;
  out.horizon = h;
  Scene sc = c.scene;
  sc.particles = 1;
  sc.tier = Tier::double_;
  sc.collision_density.reset();
  sc.escape_records = true;
  sc.fast_forward = fast_forward;
  const double t_h = mpfr_get_d(ref[h - 1].t.v, MPFR_RNDN), t_next = mpfr_get_d(ref[h].t.v, MPFR_RNDN);
  sc.t_max = escape ? t_next + 1 : (t_h + t_next) / 2;
  std::vector<InitialDraw> draws{c.draw};
  RunOptions opt;
  opt.threads = 1;
  opt.engine = engine;
  opt.draws = &draws;
  const RunResult run = run_ensemble(sc, opt);
  const EscapeRecord& rec = run.records.at(0);
  char buf[200];
  if (escape) {
    const RefStep& st = c.steps[*escape - 1];
    const double tol = kSafety * u * st.gain + st.radius + ref[*escape - 1].resolution;
    Big t;
    mpfr_set_d(t.v, rec.t, MPFR_RNDN);
    const double dt = distance(t, ref[*escape - 1].t);
    std::snprintf(buf, sizeof buf, "escape at collision %zu, t within %.3g of %.17g", *escape, tol,
                  mpfr_get_d(ref[*escape - 1].t.v, MPFR_RNDN));
    out.expected = buf;
    std::snprintf(buf, sizeof buf, "%s at collision %llu, t = %.17g",
                  rec.fate == Fate::escaped ? "escape" : "no escape", static_cast<unsigned long long>(rec.collisions),
                  rec.t);
    out.got = buf;
    out.pass = rec.fate == Fate::escaped && rec.collisions == *escape && dt <= tol;
  } else {
    std::snprintf(buf, sizeof buf, "alive after %zu collisions at t_max = %.17g", h, sc.t_max);
    out.expected = buf;
    std::snprintf(buf, sizeof buf, "%s after %llu collisions",
                  rec.fate == Fate::survived  ? "alive"
                  : rec.fate == Fate::escaped ? "escaped"
                                              : "stuck",
                  static_cast<unsigned long long>(rec.collisions));
    out.got = buf;
    out.pass = rec.fate == Fate::survived && rec.collisions == h;
  }
  return out;
}

VerifyReport verify_reference(const ReferenceSet& set, const VerifyOptions& opt) {
  VerifyReport rep;
  rep.provenance_json = set.provenance_json;
  rep.cases = set.cases.size();
  const std::size_t n = set.cases.size();
  rep.tiers.resize(opt.tiers.size() * n);
  rep.engines.resize(opt.engines.size() * n);
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const std::size_t jobs = rep.tiers.size() + rep.engines.size();
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t j = 0; j < jobs; ++j) {
    try {
      if (j < rep.tiers.size()) {
        rep.tiers[j] = check_tier(set.cases[j % n], opt.tiers[j / n], opt.check_bits);
      } else {
        const std::size_t e = j - rep.tiers.size();
        rep.engines[e] = check_engine(set.cases[e % n], opt.engines[e / n].first, opt.engines[e / n].second);
      }
    } catch (...) {
#pragma omp critical(rotleak_verify_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  for (const TierCheck& t : rep.tiers) rep.pass = rep.pass && t.pass;
  for (const EngineCheck& e : rep.engines) rep.pass = rep.pass && e.pass;
  return rep;
}

json verify_json(const VerifyReport& rep) {
  json doc;
  doc["reference"] = rep.reference_dir;
  doc["provenance"] = json::parse(rep.provenance_json);
  doc["error_model"] = error_model_json();
  doc["pass"] = rep.pass;
  json tiers = json::array();
  for (const TierCheck& t : rep.tiers)
    tiers.push_back({{"tier", t.tier},
                     {"case", t.case_name},
                     {"collisions", t.collisions},
                     {"must_reach", t.must_reach},
                     {"matched_through", t.matched_through},
                     {"worst_error_over_model", t.worst_ratio},
                     {"decisions_required", t.decisions_required},
                     {"decisions_reproduced", t.decisions_reproduced},
                     {"first_wrong_decision", nullable(t.first_wrong_decision)},
                     {"bits", t.bits},
                     {"stopped", t.stopped},
                     {"pass", t.pass}});
  doc["tiers"] = tiers;
  json engines = json::array();
  for (const EngineCheck& e : rep.engines)
    engines.push_back({{"engine", e.engine},
                       {"case", e.case_name},
                       {"checked", e.checked},
                       {"horizon", e.horizon},
                       {"expected", e.expected},
                       {"got", e.got},
                       {"pass", e.pass}});
  doc["engines"] = engines;
  return doc;
}

std::string verify_text(const VerifyReport& rep) {
  std::string out;
  const json prov = json::parse(rep.provenance_json);
  appendf(out, "reference: %s (%zu cases; made by %s, %s)\n", rep.reference_dir.c_str(), rep.cases,
          prov.value("version", std::string("?")).c_str(), prov.value("date", std::string("?")).c_str());
  appendf(out,
          "error model: |tier - reference| <= %g u W_k + the reference's radius through the tier's horizon (u W_k <= "
          "%g); worst: the largest error in units of that bound / %g\n\n",
          kSafety, kHorizonTolerance, kSafety);
  appendf(out, "%-12s %6s %9s %9s %9s %10s %7s  %s\n", "tier", "cases", "horizon", "reached", "worst", "decisions",
          "bits", "verdict");
  std::vector<std::string> failures;
  for (std::size_t i = 0; i < rep.tiers.size();) {
    const std::string& name = rep.tiers[i].tier;
    std::size_t cases = 0, reached = 0, req = 0, rep_ok = 0, bits_ok = 0, bits_compared = 0, pass = 0, must = 0;
    double worst = 0;
    for (; i < rep.tiers.size() && rep.tiers[i].tier == name; ++i) {
      const TierCheck& t = rep.tiers[i];
      ++cases;
      must += t.must_reach;
      reached += t.matched_through >= t.must_reach;
      req += t.decisions_required;
      rep_ok += t.decisions_reproduced;
      bits_compared += t.bits_compared;
      bits_ok += t.bits_compared && t.bits_ok;
      pass += t.pass;
      worst = std::max(worst, t.worst_ratio);
      if (!t.pass) {
        std::string why;
        appendf(why, "%s %s: matched through collision %zu of %zu required", t.tier.c_str(), t.case_name.c_str(),
                t.matched_through, t.must_reach);
        if (t.first_wrong_decision) appendf(why, "; escape decision wrong at collision %zu", *t.first_wrong_decision);
        if (!t.bits_ok) why += "; bits " + t.bits;
        if (!t.stopped.empty()) why += "; " + t.stopped;
        failures.push_back(why);
      }
    }
    // an interval tier is checked by containment: no error ratio, its decisions are its own proofs
    const bool interval = Tier::parse(name) && Tier::parse(name)->interval();
    char dec[32], bits[32], ratio[32];
    std::snprintf(dec, sizeof dec, "%zu/%zu", rep_ok, req);
    if (bits_compared)
      std::snprintf(bits, sizeof bits, "%zu/%zu", bits_ok, bits_compared);
    else
      std::snprintf(bits, sizeof bits, "none");  // no fingerprints of this tier: nothing was compared
    std::snprintf(ratio, sizeof ratio, "%.3g", worst);
    appendf(out, "%-12s %6zu %9.1f %4zu/%-4zu %9s %10s %7s  %s\n", name.c_str(), cases,
            static_cast<double>(must) / static_cast<double>(cases), reached, cases, interval ? "contained" : ratio,
            interval ? "-" : dec, interval ? "-" : bits, pass == cases ? "pass" : "FAIL");
  }
  if (!rep.engines.empty()) {
    appendf(out, "\n%-12s %6s %8s %7s  %s\n", "engine", "cases", "checked", "agree", "verdict");
    for (std::size_t i = 0; i < rep.engines.size();) {
      const std::string& name = rep.engines[i].engine;
      std::size_t cases = 0, checked = 0, agree = 0;
      bool ok = true;
      for (; i < rep.engines.size() && rep.engines[i].engine == name; ++i) {
        const EngineCheck& e = rep.engines[i];
        ++cases;
        checked += e.checked;
        agree += e.checked && e.pass;
        ok = ok && e.pass;
        if (!e.pass) failures.push_back(e.engine + " " + e.case_name + ": expected " + e.expected + ", got " + e.got);
      }
      appendf(out, "%-12s %6zu %8zu %7zu  %s\n", name.c_str(), cases, checked, agree, ok ? "pass" : "FAIL");
    }
  }
  out += "\n";
  for (const std::string& f : failures) out += "FAIL " + f + "\n";
  out += rep.pass ? "verify: pass\n" : "verify: FAIL (" + std::to_string(failures.size()) + " checks)\n";
  return out;
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

std::vector<std::string> compare_references(const ReferenceSet& before, const ReferenceSet& after) {
  std::vector<std::string> lines;
  std::map<std::string, const RefCase*> old;
  for (const RefCase& c : before.cases) old[c.name] = &c;
  for (const RefCase& c : after.cases) {
    const auto it = old.find(c.name);
    if (it == old.end()) {
      lines.push_back(c.name + ": new (" + std::to_string(c.steps.size()) + " collisions)");
      continue;
    }
    const RefCase& o = *it->second;
    old.erase(it);
    const double L = perimeter(c.scene);
    if (o.scene_toml != c.scene_toml || o.draw.s != c.draw.s || o.draw.p != c.draw.p || o.draw.x != c.draw.x ||
        o.draw.y != c.draw.y || o.draw.u != c.draw.u || o.draw.tau != c.draw.tau) {
      lines.push_back(c.name + ": another particle or scene");
      continue;
    }
    const auto a = parse_steps(o, L), b = parse_steps(c, L);
    std::optional<std::size_t> moved;
    double by = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
      const double d =
          std::max({distance(a[i].t, b[i].t), L * distance(a[i].s, b[i].s, true), distance(a[i].p, b[i].p)});
      const double allowed = o.steps[i].radius + c.steps[i].radius + a[i].resolution + b[i].resolution;
      if (o.steps[i].piece != c.steps[i].piece || o.steps[i].in_leak != c.steps[i].in_leak || d > allowed) {
        moved = i + 1;
        by = d;
        break;
      }
    }
    if (moved) {
      char buf[160];
      std::snprintf(buf, sizeof buf, ": trajectory differs from collision %zu (by %.3g)", *moved, by);
      lines.push_back(c.name + buf);
    } else if (a.size() != b.size()) {
      lines.push_back(c.name + ": certified through " + std::to_string(b.size()) + " collisions (was " +
                      std::to_string(a.size()) + ")");
    }
    for (const auto& [tier, list] : c.fingerprints) {
      const auto f = o.fingerprints.find(tier);
      if (f == o.fingerprints.end() || f->second != list) {
        std::size_t k = 0;
        if (f != o.fingerprints.end())
          for (std::size_t i = 0; i < std::min(list.size(), f->second.size()); ++i)
            if (list[i] != f->second[i]) {
              k = list[i].first;
              break;
            }
        lines.push_back(c.name + ": " + tier + " bits differ" + (k ? " by collision " + std::to_string(k) : ""));
      }
    }
  }
  for (const auto& [name, c] : old) lines.push_back(name + ": removed");
  return lines;
}

}  // namespace rotleak
