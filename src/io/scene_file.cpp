#include "io/scene_file.hpp"

#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>
#include "geometry/stadium.hpp"
#include "io/files.hpp"
#include "io/scene_reader.hpp"
#include "numeric/input.hpp"

namespace rotleak {

std::string toml_float(double x) {
  std::string text = shortest(x);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}

namespace {

using namespace scene_detail;

// The keys a scene may hold. Anything else is an error: a misspelt key must not be silently ignored.

const std::map<std::string, std::set<std::string>> kSchema = {
    {"stadium", {"d", "r"}},
    {"table", table_keys()},
    {"leak", {"width", "start", "omega"}},
    {"ensemble",
     {"particles", "seed", "init", "creation_window", "sampling", "sampling_eps", "sampling_p", "sampling_ride",
      "enter_through"}},
    {"run",
     {"t_max", "tier", "fast_forward", "checkpoint_seconds", "splitting", "split_every", "split_delta", "split_cap"}},
    {"start_splitting",
     {"on", "replicates", "factor", "moves", "halvings", "window", "deep_tier", "handover_bits", "p", "edges"}},
    {"observe", {"survival_dt", "collision_density", "escapes"}},
    {"fit", {"kappa_window", "alpha_factor", "alpha_sigma", "min_survivors", "tail_floor"}},
};

/// Keys read exactly, whose --set value is kept as text: the stadium's, the leak's, every table parameter.
bool exact_key(const std::string& path) {
  static const std::set<std::string> keys = [] {
    std::set<std::string> k = {"stadium.d", "stadium.r", "leak.width", "leak.start", "leak.omega"};
    for (const std::string& key : table_keys())
      if (key != "kind" && key != "vertices") k.insert("table." + key);
    return k;
  }();
  return keys.count(path) > 0;
}
const std::set<std::string> kDensityKeys = {"bins", "windows"};
const std::set<std::string> kCountKeys = {"ensemble.particles", "ensemble.seed", "run.split_cap", "fit.min_survivors"};

/// [[leaks]]: an array of tables, each with the keys of a listed leak only.
void check_leak_list(const toml::node& v) {
  const auto a = v.as_array();
  if (!a || a->empty() || !a->is_array_of_tables())
    throw InputError("leaks", shown(v), "must be a list of tables [[leaks]] with loop, width, start, omega");
  for (std::size_t i = 0; i < a->size(); ++i)
    for (auto&& [kk, vv] : *a->get(i)->as_table())
      if (!kListedLeakKeys.count(std::string(kk.str())))
        throw InputError("leaks." + std::to_string(i) + "." + std::string(kk.str()), shown(vv),
                         "unknown key; [[leaks]] allows " + listed(kListedLeakKeys));
}

void check_known_keys(const toml::table& root) {
  for (auto&& [k, v] : root) {
    const std::string section(k.str());
    if (section == "leaks") {
      check_leak_list(v);
      continue;
    }
    auto it = kSchema.find(section);
    if (it == kSchema.end()) {
      std::string list;
      for (const auto& [s, _] : kSchema) list += (list.empty() ? "" : ", ") + s;
      throw InputError(section, shown(v), "unknown section; allowed: " + list + ", [[leaks]]");
    }
    auto sec = v.as_table();
    if (!sec) throw InputError(section, shown(v), "must be a table [" + section + "]");
    for (auto&& [kk, vv] : *sec) {
      const std::string key(kk.str());
      if (!it->second.count(key))
        throw InputError(section + "." + key, shown(vv), "unknown key; [" + section + "] allows " + listed(it->second));
    }
  }
}

/// A nonzero decimal that double cannot hold is refused naming `name`: above the largest double (TOML
/// refuses it: `read` empty) or read as 0 (TOML rounds 1e-400 to 0 silently). `read` is what TOML made of
/// `text`. A text that is not a decimal (inf, nan, a word, .5) is left to the key's own check; one in range
/// (.5 is not a TOML number, but not beyond double either) too.
void check_representable(const std::string& name, const std::string& text, std::optional<double> read) {
  mpq_class q;
  try {
    q = parse_decimal(text);
  } catch (const ExactParseError&) {
    return;
  }
  const bool overflow = abs(q) > mpq_class(std::numeric_limits<double>::max());
  const bool underflow = sgn(q) != 0 && read && *read == 0;
  if (overflow || underflow)
    throw InputError(name, text,
                     std::string("is beyond the range of a double (it would read as ") + (overflow ? "inf" : "0") +
                         "; nonzero magnitudes from 2.2e-308 to 1.8e308)");
}

void apply_override(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", "\"" + assignment + "\"", "must look like section.key=value (e.g. leak.omega=2/3)");
  const std::string path = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  const auto dot = path.find('.');
  if (dot == std::string::npos)
    throw InputError("--set", "\"" + assignment + "\"", "the key needs its section, e.g. leak.omega=2/3");
  const std::string section = path.substr(0, dot), key = path.substr(dot + 1);
  if (section == "leaks") return override_listed_leak(root, key, value);
  auto it = kSchema.find(section);
  if (it == kSchema.end() || !it->second.count(key)) {
    std::string list;
    for (const auto& [s, keys] : kSchema)
      for (const auto& kk : keys) list += (list.empty() ? "" : ", ") + (s + "." + kk);
    throw InputError(path, "\"" + value + "\"", "unknown key; allowed: " + list);
  }
  if (!root.contains(section)) root.insert(section, toml::table{});
  toml::table* found = root.get_as<toml::table>(section);
  if (!found)  // `leak = "2/3"` in the file and --set leak.start=...: once a null dereference (found by fuzz_scene)
    throw InputError(section, shown(*root.get(section)), "must be a table [" + section + "]");
  toml::table& sec = *found;
  if (exact_key(path)) {
    sec.insert_or_assign(key, unquoted(value));  // exact keys keep the text verbatim
    return;
  }
  if (kCountKeys.count(path)) {
    // a count is read exactly, as --particles reads it: 1e6 and 2.5e5 are integers here, where TOML
    // would make them floats
    try {
      sec.insert_or_assign(key, static_cast<std::int64_t>(parse_count(path, value, 0)));
      return;
    } catch (const InputError&) {
      // not a count: the TOML value below gets the key's own message
    }
  }
  // a bare word: validation says whether it is allowed; TOML refuses what overflows a double (1e400)
  if (!set_value(sec, key, value)) return check_representable(path, value, std::nullopt);
  if (auto f = sec.get(key)->as_floating_point()) check_representable(path, value, f->get());
}

/// A run whose particles make more than 1e9 collisions each is refused: the key to blame and why.
void check_collisions_per_particle(const Scene& s, bool t_max_given) {
  if (s.table) {  // any table: its mean free path pi Area / |boundary|
    const TableSpec t = table_spec(s);
    const double mfp = std::numbers::pi * t.area.to_double() / t.perimeter.to_double();
    if (s.t_max / mfp <= 1e9) return;
    throw InputError("run.t_max", toml_float(s.t_max) + (t_max_given ? "" : " (the default)"),
                     "on this " + s.table->kind + " (mean free path " + shortest(mfp) + ") a particle makes about " +
                         shortest(s.t_max / mfp) +
                         " collisions; at most 1e9 are allowed: here run.t_max <= " + shortest(std::floor(1e9 * mfp)));
  }
  // collisions per particle ~ t_max / mean free path (pi area / perimeter): a tiny r or d makes it endless
  const double d = s.d.to_double(), r = s.r.to_double();
  const double mfp = Stadium<double>(s.d, s.r).mean_free_path();
  const double per_particle = s.t_max / mfp;
  if (per_particle <= 1e9) return;
  char why[300];
  std::snprintf(why, sizeof why,
                "with d = %s, r = %s and t_max = %s a particle makes about %.3g collisions (mean free path %.3g); "
                "at most 1e9 are allowed: make the stadium larger or t_max smaller",
                s.d_text.c_str(), s.r_text.c_str(), shortest(s.t_max).c_str(), per_particle, mfp);
  // the key to blame: t_max when even the default stadium (d = 2, r = 1) would make too many collisions
  // with it (t_max = 1e12 once blamed stadium.r, never given), else the stadium's smaller size
  const double mfp_default = Stadium<double>(ExactReal::parse("2"), ExactReal::parse("1")).mean_free_path();
  if (s.t_max / mfp_default > 1e9)
    throw InputError("run.t_max", toml_float(s.t_max) + (t_max_given ? "" : " (the default)"),
                     std::string(why) + " (here run.t_max <= " + shortest(std::floor(1e9 * mfp)) + ")");
  throw InputError(r <= d ? "stadium.r" : "stadium.d", "\"" + (r <= d ? s.r_text : s.d_text) + "\"", why);
}

/// run.splitting and its parameters; the parameters only with splitting on.
void read_splitting(const Reader& in, Scene& s) {
  if (const toml::node* n = in.find("run", "splitting")) {
    auto b = n->as_boolean();
    if (!b) throw InputError("run.splitting", shown(*n), "must be true or false");
    s.splitting.on = b->get();
  }
  for (const char* key : {"split_every", "split_delta", "split_cap"})
    if (const toml::node* n = in.find("run", key); n && !s.splitting.on)
      throw InputError(std::string("run.") + key, shown(*n), "applies to run.splitting = true only");
  if (!s.splitting.on) return;
  const double t_max = s.t_max;
  s.splitting.every = in.number(
      "run", "split_every", default_split_every(s), [&](double v) { return v > 0 && v <= t_max; },
      "must be a time in (0, run.t_max] = (0, " + shortest(t_max) +
          "] (default: ln 2 / (lambda L / (pi Area)) = " + shortest(default_split_every(s)) + ")");
  s.splitting.every = in.number(
      "run", "split_every", s.splitting.every, [&](double v) { return t_max / v <= 100000; },
      "gives more than 10^5 split times before run.t_max = " + shortest(t_max) +
          "; at most 10^5 are allowed: set run.split_every to at least " + shortest(t_max / 100000));
  s.splitting.delta = in.number(
      "run", "split_delta", s.splitting.delta, [](double v) { return v >= 0 && v <= 1e-3; },
      "must be an angle in [0, 1e-3] radians (the copy's turn)");
  s.splitting.cap = in.count("run", "split_cap", s.splitting.cap, 2, "must be an integer >= 2 (members of a line)");
  if (s.splitting.cap > 1000000)
    throw InputError("run.split_cap", std::to_string(s.splitting.cap), "must be at most 10^6 members of a line");
}

/// The stadium's d and r from [stadium] (or [table] with kind = "stadium": `section`): exact values, positive,
/// normal in double (the tiers run them rounded) and within a factor 1e12 of each other.
void read_stadium(const Reader& in, Scene& s, const std::string& section) {
  s.d = in.exact(section, "d", s.d_text, s.d);
  s.r = in.exact(section, "r", s.r_text, s.r);
  const std::string key_d = section + ".d", key_r = section + ".r";
  if (s.d.sign() <= 0) throw InputError(key_d, "\"" + s.d_text + "\"", "must be > 0");
  if (s.r.sign() <= 0) throw InputError(key_r, "\"" + s.r_text + "\"", "must be > 0");
  // positive, but the tiers run it rounded: d = 1e-400 once ran as a circle (d = 0 in double)
  for (const auto& [key, value, text] : {std::tuple{key_d, &s.d, &s.d_text}, std::tuple{key_r, &s.r, &s.r_text}})
    if (!std::isnormal(value->to_double()))
      throw InputError(key, "\"" + *text + "\"",
                       "rounds to " + shortest(value->to_double()) +
                           " in double, which the tiers run: give a value of at least 2.3e-308");
  // sizes the double tiers can resolve: r = 1e160 once ran with every flight of zero length (its squares
  // overflow) and d = 1e-30 as a circle (its straight edges below r's rounding), both complete with P = 1
  const double d = s.d.to_double(), r = s.r.to_double();
  const bool d_worse = std::abs(std::log10(d)) >= std::abs(std::log10(r));
  const std::string key = d_worse ? key_d : key_r;
  const std::string& text = d_worse ? s.d_text : s.r_text;
  if (!(std::max(d, r) <= 1e100 && std::min(d, r) >= 1e-100) || !(std::min(d, r) >= 1e-12 * std::max(d, r)))
    throw InputError(key, "\"" + text + "\"",
                     "stadium.d and stadium.r must lie in [1e-100, 1e100] (their squares stay finite in double) and "
                     "within a factor 1e12 of each other (doubles resolve both the straight edges and the arcs); "
                     "here d = " +
                         s.d_text + ", r = " + s.r_text);
}

/// The one leak of [leak].
void read_leak(const Reader& in, Scene& s) {
  s.width = in.exact("leak", "width", s.width_text, s.width);
  s.start = in.exact("leak", "start", s.start_text, s.start);
  s.omega = in.exact("leak", "omega", s.omega_text, s.omega);
  check_leak_values("leak", {s.width, s.width_text}, {s.start, s.start_text}, {s.omega, s.omega_text});
}

/// The table and its leaks: [stadium] or [table], then [leak] or [[leaks]].
void read_geometry(const Reader& in, Scene& s) {
  const toml::table* table = in.root.get_as<toml::table>("table");
  const toml::node* kind = table ? table->get("kind") : nullptr;
  const bool stadium_table = table && (!kind || (kind->as_string() && kind->as_string()->get() == "stadium"));
  if (table && !stadium_table)
    read_table(in, s);
  else
    read_stadium(in, s, stadium_table ? "table" : "stadium");
  if (stadium_table && in.root.contains("stadium"))
    throw InputError("stadium", shown(*in.root.get("stadium")),
                     "the stadium is given twice: keep [stadium] or [table] with kind = \"stadium\", not both");
  if (in.root.contains("leaks"))
    read_leak_list(in, s);
  else
    read_leak(in, s);
}

/// The ensemble's size, seed and initial conditions, and the run's length.
void read_ensemble(const Reader& in, Scene& s) {
  s.particles = in.count("ensemble", "particles", s.particles, 1, "must be an integer >= 1");
  s.seed = in.count("ensemble", "seed", s.seed, 0, "must be an integer >= 0");
  s.init =
      in.word("ensemble", "init", "birkhoff", {"birkhoff", "flow"}) == "flow" ? InitKind::flow : InitKind::birkhoff;
  s.t_max = in.number(
      "run", "t_max", s.t_max, [](double v) { return v > 0 && v <= 1e12; }, "must be a number in (0, 1e12]");
  s.creation_window = in.number(
      "ensemble", "creation_window", s.creation_window, [&](double v) { return v >= 0 && v <= s.t_max; },
      "must be in [0, run.t_max] = [0, " + shortest(s.t_max) + "] (particles are created within it)");
}

/// ensemble.sampling and its parameters (the parameters only with mupo).
void read_sampling(const Reader& in, Scene& s) {
  s.sampling.kind = in.word("ensemble", "sampling", "uniform", {"uniform", "mupo"}) == "mupo" ? SamplingKind::mupo
                                                                                              : SamplingKind::uniform;
  // a mupo parameter, refused with uniform sampling; a number of them within [lo, hi]
  const auto mupo_param = [&](const std::string& key) -> const toml::node* {
    const toml::node* n = in.find("ensemble", key);
    if (n && s.sampling.kind == SamplingKind::uniform)
      throw InputError("ensemble." + key, shown(*n), "applies to ensemble.sampling = \"mupo\" only");
    return n;
  };
  const auto mupo_number = [&](const std::string& key, double lo, double hi, const std::string& allowed, double& to) {
    if (const toml::node* n = mupo_param(key)) {
      to = Reader::as_number("ensemble." + key, *n);
      if (!(to >= lo && to <= hi)) throw InputError("ensemble." + key, shown(*n), allowed);
    }
  };
  mupo_number("sampling_eps", 0.01, 1, "must be in [0.01, 1] (the uniform share; no weight exceeds 1 / eps)",
              s.sampling.eps);
  if (const toml::node* n = mupo_param("sampling_p")) {
    const auto a = n->as_array();
    const std::string allowed = "must be [p_min, p_max] with 1e-300 <= p_min < p_max < 1";
    if (!a || a->size() != 2) throw InputError("ensemble.sampling_p", shown(*n), allowed);
    s.sampling.p_min = Reader::as_number("ensemble.sampling_p", *a->get(0));
    s.sampling.p_max = Reader::as_number("ensemble.sampling_p", *a->get(1));
    if (!(s.sampling.p_min >= 1e-300 && s.sampling.p_min < s.sampling.p_max && s.sampling.p_max < 1))
      throw InputError("ensemble.sampling_p", shown(*n), allowed);
  }
  mupo_number("sampling_ride", 0, 0.9, "must be in [0, 0.9] (the share of the mupo draws on the riding bands)",
              s.sampling.ride);
  if (s.sampling.ride > 0 && s.init == InitKind::flow)  // the bands are drawn in Birkhoff's (s, p) on the edges
    throw InputError("ensemble.sampling_ride", shown(*in.find("ensemble", "sampling_ride")),
                     "applies to ensemble.init = \"birkhoff\" only (the riding bands are drawn on the straight "
                     "edges; flow starts have none), or 0");
}

/// ensemble.enter_through: particles that enter through one stationary leak (uniform Birkhoff starts in its window).
void read_entry(const Reader& in, Scene& s) {
  const toml::node* n = in.find("ensemble", "enter_through");
  if (!n) return;
  const std::vector<LeakSpec> leaks = leak_specs(s);
  const std::string allowed =
      "must be a leak's place in the list, an integer in [0, " + std::to_string(leaks.size() - 1) + "]";
  const std::uint64_t j = in.count("ensemble", "enter_through", 0, 0, allowed);
  if (j >= leaks.size()) throw InputError("ensemble.enter_through", shown(*n), allowed);
  if (s.init == InitKind::flow)
    throw InputError("ensemble.enter_through", shown(*n),
                     "applies to ensemble.init = \"birkhoff\" only (an entering particle starts on the hole with "
                     "the Birkhoff measure restricted to it)");
  if (s.sampling.weighted())
    throw InputError("ensemble.enter_through", shown(*n),
                     "needs ensemble.sampling = \"uniform\" (the mupo draws cover the whole boundary)");
  if (leaks[j].omega.sign() != 0)
    throw InputError("ensemble.enter_through", shown(*n),
                     "needs a stationary leak (omega = 0): leak " + std::to_string(j) + " moves");
  s.enter_through = static_cast<int>(j);
}

/// The run's tier, fast-forward and checkpoint period.
void read_run_options(const Reader& in, Scene& s) {
  if (const toml::node* n = in.find("run", "tier")) {
    const auto name = n->as_string();
    const auto tier = name ? Tier::parse(name->get()) : std::nullopt;
    if (!tier || !(tier->ensemble() || tier->automatic()))
      throw InputError("run.tier", shown(*n),
                       "must be one of \"float\", \"double\", \"long_double\" (the ensemble tiers) or \"auto\"");
    s.tier = *tier;
  }

  if (const toml::node* n = in.find("run", "fast_forward")) {
    auto b = n->as_boolean();
    if (!b) throw InputError("run.fast_forward", shown(*n), "must be true or false");
    s.fast_forward = b->get();
  }
  s.checkpoint_seconds = in.number(
      "run", "checkpoint_seconds", s.checkpoint_seconds, [](double v) { return v >= 0 && v <= 1e7; },
      "must be a number of seconds in [0, 1e7] (0: no periodic checkpoints)");
}

/// What is observed: the survival grid, the collision density f_c and its windows, escape records.
void read_observe(const Reader& in, Scene& s) {
  s.survival_dt = in.number(
      "observe", "survival_dt", s.survival_dt, [&](double v) { return v > 0 && s.t_max / v <= 1e8; },
      "must be > 0 with run.t_max / survival_dt <= 1e8 bins (run.t_max = " + shortest(s.t_max) + ")");
  if (const toml::node* n = in.find("observe", "collision_density")) {
    auto t = n->as_table();
    if (!t)
      throw InputError("observe.collision_density", shown(*n),
                       "must be a table { bins = ..., windows = [[from, to], ...] }");
    for (auto&& [k, v] : *t)
      if (!kDensityKeys.count(std::string(k.str())))
        throw InputError("observe.collision_density." + std::string(k.str()), shown(v),
                         "unknown key; allowed: bins, windows");
    CollisionDensitySpec spec;
    if (auto b = t->get("bins")) {
      auto i = b->as_integer();
      if (!i || i->get() < 1 || i->get() > 10000000)
        throw InputError("observe.collision_density.bins", shown(*b), "must be an integer in [1, 10^7]");
      spec.bins = static_cast<int>(i->get());
    }
    if (auto w = t->get("windows")) {
      auto a = w->as_array();
      if (!a || a->empty())
        throw InputError("observe.collision_density.windows", shown(*w),
                         "must be a non-empty list of [from, to] pairs");
      for (auto&& item : *a) {
        spec.windows.push_back(Reader::window("observe.collision_density.windows", item));
        if (spec.windows.back().to > s.t_max)
          throw InputError("observe.collision_density.windows", shown(item),
                           "must lie within [0, run.t_max] = [0, " + shortest(s.t_max) + "]");
      }
    } else {
      spec.windows.push_back({0, s.t_max});
    }
    s.collision_density = spec;
  }
  if (const toml::node* n = in.find("observe", "escapes")) {
    auto b = n->as_boolean();
    if (!b) throw InputError("observe.escapes", shown(*n), "must be true or false");
    s.escape_records = b->get();
  }
}

/// The fits' keys.
void read_fit(const Reader& in, Scene& s) {
  if (const toml::node* n = in.find("fit", "kappa_window")) {
    s.kappa_window = Reader::window("fit.kappa_window", *n);
    if (s.kappa_window.to > s.t_max) throw InputError("fit.kappa_window", shown(*n), "must end at or before run.t_max");
  }
  if (s.kappa_window.to > s.t_max) s.kappa_window.to = s.t_max;
  s.alpha_factor = in.number(
      "fit", "alpha_factor", s.alpha_factor, [](double v) { return v > 1 && v <= 1e6; }, "must be in (1, 1e6]");
  s.alpha_sigma = in.number(
      "fit", "alpha_sigma", s.alpha_sigma, [](double v) { return v >= 1 && v <= 10; },
      "must be in [1, 10] standard errors");
  s.min_survivors = in.count("fit", "min_survivors", s.min_survivors, 1, "must be an integer >= 1");
  s.tail_floor = in.number(
      "fit", "tail_floor", s.tail_floor, [](double v) { return v > 0 && v < 1; },
      "must be in (0, 1): the weakest tail weight a regime claims to exclude");
}

/// start_splitting.deep_tier: the clock where double stops resolving the moves.
TierKind read_deep_tier(const Reader& in, TierKind fallback) {
  const toml::node* n = in.find("start_splitting", "deep_tier");
  if (!n) return fallback;
  const auto name = n->as_string();
  const auto tier = name ? Tier::parse(name->get()) : std::nullopt;
  if (!tier || !(tier->kind == TierKind::double_ || tier->kind == TierKind::dd || tier->kind == TierKind::float128))
    throw InputError("start_splitting.deep_tier", shown(*n),
                     "must be \"dd\", \"float128\" or \"double\" (the clock where double stops resolving the "
                     "moves; double: none)");
  return tier->kind;
}

/// [start_splitting]: its parameters only with on = true.
void read_start_splitting(const Reader& in, Scene& s) {
  StartSplitSpec& g = s.start_splitting;
  const auto flag = [&](const char* key, bool& to) {
    if (const toml::node* n = in.find("start_splitting", key)) {
      auto b = n->as_boolean();
      if (!b) throw InputError(std::string("start_splitting.") + key, shown(*n), "must be true or false");
      to = b->get();
    }
  };
  flag("on", g.on);
  for (const char* key :
       {"replicates", "factor", "moves", "halvings", "window", "deep_tier", "handover_bits", "p", "edges"})
    if (const toml::node* n = in.find("start_splitting", key); n && !g.on)
      throw InputError(std::string("start_splitting.") + key, shown(*n), "applies to start_splitting.on = true only");
  if (!g.on) return;
  const auto whole = [&](const char* key, int fallback, std::uint64_t lo, std::uint64_t hi, const std::string& what) {
    const std::uint64_t v = in.count("start_splitting", key, static_cast<std::uint64_t>(fallback), lo, what);
    if (v > hi) throw InputError(std::string("start_splitting.") + key, std::to_string(v), what);
    return static_cast<int>(v);
  };
  g.replicates = whole("replicates", g.replicates, 2, 100000,
                       "must be an integer in [2, 10^5] (independent replicates: their spread is P's error)");
  g.factor = whole("factor", g.factor, 2, 1000, "must be an integer in [2, 1000] (a level keeps 1 / factor)");
  g.moves = whole("moves", g.moves, 1, 1000, "must be an integer in [1, 1000] (Metropolis moves a kept state)");
  g.halvings = whole("halvings", g.halvings, 0, 100, "must be an integer in [0, 100] (proposal scales 2^-j)");
  g.window = whole("window", g.window, 0, 60,
                   "must be an integer in [0, 60] (a level's halvings: 2 window + 1 about its best)");
  g.deep_tier = read_deep_tier(in, g.deep_tier);
  g.handover_bits = whole("handover_bits", g.handover_bits, 1, 52,
                          "must be an integer in [1, 52] (hand over where a level's moves fall below 2^bits ulps)");
  if (const toml::node* n = in.find("start_splitting", "p")) {
    const auto a = n->as_array();
    const std::string allowed = "must be [lo, hi] with 0 <= lo < hi <= 1 (the starts' |p|)";
    if (!a || a->size() != 2) throw InputError("start_splitting.p", shown(*n), allowed);
    g.p_lo = Reader::as_number("start_splitting.p", *a->get(0));
    g.p_hi = Reader::as_number("start_splitting.p", *a->get(1));
    if (!(g.p_lo >= 0 && g.p_lo < g.p_hi && g.p_hi <= 1)) throw InputError("start_splitting.p", shown(*n), allowed);
  }
  flag("edges", g.edges);
  if (g.edges && s.on_table())
    throw InputError("start_splitting.edges", "true",
                     "applies to the stadium of [stadium] with one leak (its straight edges), not to a table");
  const auto refuse = [](const std::string& why) { throw InputError("start_splitting.on", "true", why); };
  if (s.splitting.on) refuse("and run.splitting = true are two samplers: choose one");
  if (s.sampling.kind != SamplingKind::uniform)
    refuse("draws its starts uniformly on its stratum: leave ensemble.sampling = \"uniform\"");
  if (s.init != InitKind::birkhoff) refuse("moves Birkhoff starts: ensemble.init = \"birkhoff\" only");
  if (s.enter_through >= 0)
    refuse("draws its starts on the boundary, not through a leak: unset ensemble.enter_through");
  if (s.tier != Tier::double_) refuse("runs the double tier only (run.tier = \"" + to_string(s.tier) + "\" asked for)");
  if (s.escape_records || s.collision_density)
    refuse(
        "keeps no escape records and no collision density (a start is run many times): drop observe.escapes "
        "and observe.collision_density");
}

/// What splitting needs of the rest of the scene: the double tier, mupo draws on the stadium (any other table: its
/// uniform draws, scene_table.cpp), no escape records.
void check_splitting_needs(const Scene& s) {
  if (s.splitting.on && s.tier != Tier::double_)
    throw InputError("run.splitting", "true",
                     "runs the double tier only (run.tier = \"" + to_string(s.tier) + "\" asked for)");
  if (s.splitting.on && s.sampling.kind != SamplingKind::mupo && !s.on_table())
    throw InputError("run.splitting", "true",
                     "needs ensemble.sampling = \"mupo\": uniform draws start few lines on the bouncing-ball family "
                     "that carries the tail, and when they die the lines' spread cannot see it (P(t_max) = 2e-38 "
                     "reported where the truth is 1.7e-5); add --set ensemble.sampling=mupo");
  if (s.splitting.on && s.escape_records)
    throw InputError("run.splitting", "true",
                     "keeps no per-particle escape records (a line has many members): set observe.escapes = false");
}

Scene build(const toml::table& root, const std::string& source) {
  check_known_keys(root);
  Reader in{root};
  Scene s;
  s.source = source;
  read_geometry(in, s);
  read_ensemble(in, s);
  check_collisions_per_particle(s, in.find("run", "t_max") != nullptr);
  read_sampling(in, s);
  read_entry(in, s);
  read_run_options(in, s);
  read_splitting(in, s);
  read_observe(in, s);
  read_fit(in, s);
  check_table_needs(s);
  read_start_splitting(in, s);  // first: beside run.splitting it is the one to name
  check_splitting_needs(s);
  return s;
}

/// A decimal that a scene file writes as nonzero but double reads as 0 or infinity (1e-400, 1e400): TOML
/// parsers round it silently, so the text of every float is read back exactly from the file and such a
/// value refused, as --set refuses it.
void check_float_range(const toml::node& n, const std::string& name, const std::vector<std::string_view>& lines) {
  if (auto t = n.as_table()) {
    for (auto&& [k, v] : *t)
      check_float_range(v, name.empty() ? std::string(k.str()) : name + "." + std::string(k.str()), lines);
    return;
  }
  if (auto a = n.as_array()) {
    for (auto&& v : *a) check_float_range(v, name, lines);
    return;
  }
  const auto f = n.as_floating_point();
  if (!f) return;
  const toml::source_region& at = n.source();
  if (at.begin.line != at.end.line || at.begin.line == 0 || at.begin.line > lines.size() ||
      at.end.column <= at.begin.column)
    return;
  const std::string_view line = lines[at.begin.line - 1];
  if (at.end.column - 1 > line.size()) return;  // columns count characters: a line with others before it is skipped
  std::string token(line.substr(at.begin.column - 1, at.end.column - at.begin.column));
  std::erase(token, '_');
  check_representable(name, token, f->get());
}

toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "line " << e.source().begin.line << ": " << e.description();
    throw InputError(source, "(TOML)", os.str());
  }
}

}  // namespace

Scene parse_scene(const std::string& text, const std::vector<std::string>& overrides, const std::string& source) {
  toml::table root = parse_toml(text, source);
  std::vector<std::string_view> lines;
  for (std::size_t at = 0; at <= text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    lines.emplace_back(text.data() + at, end - at);
    at = end + 1;
  }
  check_float_range(root, "", lines);
  for (const auto& o : overrides) apply_override(root, o);
  return build(root, source);
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError("SCENE", "\"" + path + "\"", "is a directory; give a TOML scene file");
  std::ifstream f(path);
  if (!f) throw InputError("SCENE", "\"" + path + "\"", "must be a readable TOML file");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_scene(ss.str(), overrides, path);
}

}  // namespace rotleak
