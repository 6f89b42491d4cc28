// [table], [[leaks]] and what only the stadium with one leak has: the scene reader's part for any table
// (docs/scenes.md, "Tables and several leaks"; docs/tables.md).
#include <algorithm>
#include <cmath>

#include "io/scene_reader.hpp"

namespace rotleak {

namespace scene_detail {

/// [table]'s keys: its kind, a polygon's vertices, and every standard table's parameters.
std::set<std::string> table_keys() {
  std::set<std::string> keys = {"kind", "vertices"};
  for (const TableKind& k : table_kinds()) keys.insert(k.params.begin(), k.params.end());
  return keys;
}

/// The text of a --set value: a value quoted as in a scene file ("2/3") is the text inside.
std::string unquoted(const std::string& value) {
  const bool quoted = value.size() >= 2 && value.front() == '"' && value.back() == '"';
  return quoted ? value.substr(1, value.size() - 2) : value;
}

bool set_value(toml::table& section, const std::string& key, const std::string& value) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    section.insert_or_assign(key, value);
    return false;
  }
  parsed.get("v")->visit([&](auto&& node) { section.insert_or_assign(key, node); });
  return true;
}

/// --set leaks.N.key=value: a key of the listed leak N (from 0) of the scene's [[leaks]].
void override_listed_leak(toml::table& root, const std::string& rest, const std::string& value) {
  const std::string path = "leaks." + rest;
  const auto dot = rest.find('.');
  const std::string index = rest.substr(0, dot), key = dot == std::string::npos ? "" : rest.substr(dot + 1);
  if (index.empty() || index.size() > 2 || index.find_first_not_of("0123456789") != std::string::npos ||
      !kListedLeakKeys.count(key))
    throw InputError(path, "\"" + value + "\"",
                     "unknown key; a listed leak's key is leaks.N.KEY with N its place in [[leaks]] (from 0) and KEY "
                     "one of " +
                         listed(kListedLeakKeys));
  toml::array* list = root.get_as<toml::array>("leaks");
  const std::size_t n = std::stoul(index);
  if (!list || n >= list->size() || !list->get(n)->is_table())
    throw InputError(path, "\"" + value + "\"",
                     "the scene lists " + std::to_string(list ? list->size() : 0) +
                         " leaks in [[leaks]]; --set changes a listed one (leaks.0 ... )");
  toml::table& leak = *list->get(n)->as_table();
  if (key != "loop") {
    leak.insert_or_assign(key, unquoted(value));
    return;
  }
  set_value(leak, key, value);  // a word: the loop's own check refuses it
}

/// One leak's width, start and omega, checked (`prefix` names its keys: "leak", "leaks.1"): a width in (0, 1) that
/// double holds, a start whose whole turns are decidable, an omega within 10^15 turns per unit time.
void check_leak_values(const std::string& prefix, const ExactInput& width, const ExactInput& start,
                       const ExactInput& omega) {
  if (width.value.sign() <= 0 || (width.value - ExactReal::parse("1")).sign() >= 0)
    throw InputError(prefix + ".width", "\"" + width.text + "\"", "must be in (0, 1) (a fraction of the perimeter)");
  if (!std::isnormal(width.value.to_double()))  // the tiers run it rounded
    throw InputError(prefix + ".width", "\"" + width.text + "\"",
                     "rounds to " + shortest(width.value.to_double()) +
                         " in double, which the tiers run: give a value of at least 2.3e-308");
  // omega beyond 1e15 turns per unit time: 1e100000 once became inf in double and no particle
  // escaped. Below the bound the audit's scalar check says up to where each tier resolves the phase
  // (double loses it near omega t_max = 2^53; dd keeps omega = 1e12 at t_max = 2e4).
  if ((ExactReal::parse("1e15") - (omega.value.sign() < 0 ? -omega.value : omega.value)).sign() < 0)
    throw InputError(prefix + ".omega", "\"" + omega.text + "\"",
                     "must be within [-10^15, 10^15] turns per unit time (rotleak audit tells which tiers resolve the "
                     "leak phase at a given omega and t_max)");
  try {
    (void)floor_exact(start.value);  // the leak's start is reduced modulo 1 exactly: it must be decidable
  } catch (const std::domain_error& e) {
    throw InputError(prefix + ".start", "\"" + start.text + "\"", e.what());
  }
}

/// A polygon's vertices: [[x, y], ...], each coordinate exact (a string or an integer).
template <class Check>
void read_vertices(const Reader& in, TableInput& t, const Check& check_size) {
  const toml::node* n = in.find("table", "vertices");
  const std::string allowed =
      "must be a list of 3 to " + std::to_string(kMaxTablePieces) +
      " vertices [x, y] in clockwise order, each coordinate exact (\"0.5\", \"1/3\" or an integer)";
  const auto a = n ? n->as_array() : nullptr;
  if (!a) throw InputError("table.vertices", n ? shown(*n) : "(not given)", allowed);
  if (a->size() < 3 || a->size() > static_cast<std::size_t>(kMaxTablePieces))
    throw InputError("table.vertices", shown(*n), allowed);
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto xy = a->get(i)->as_array();
    const std::string name = "table.vertices." + std::to_string(i);
    if (!xy || xy->size() != 2) throw InputError(name, shown(*a->get(i)), allowed);
    t.vertices.emplace_back(Reader::exact_node(name, *xy->get(0)), Reader::exact_node(name, *xy->get(1)));
    check_size(name, t.vertices.back().first);
    check_size(name, t.vertices.back().second);
  }
}

/// A table other than the stadium: [table]'s kind and exactly its parameters (or a polygon's vertices), each nonzero
/// one within [1e-100, 1e100] in double; the table built (its own checks: closed, the sizes it needs) and its pieces
/// within a factor 1e12 of each other in length (doubles resolve them all).
void read_table(const Reader& in, Scene& s) {
  std::set<std::string> names;
  for (const TableKind& k : table_kinds()) names.insert(k.name);
  TableInput t;
  t.kind = in.word("table", "kind", "stadium", names);
  const TableKind& kind = *find_table_kind(t.kind);
  const std::set<std::string> takes(kind.params.begin(), kind.params.end());
  const std::string what = t.kind == "polygon" ? std::string("vertices") : listed(takes);
  if (in.root.contains("stadium"))
    throw InputError("stadium", shown(*in.root.get("stadium")),
                     "applies to the stadium only; table.kind = \"" + t.kind + "\" takes " + what + " in [table]");
  for (auto&& [k, v] : *in.root.get_as<toml::table>("table")) {
    const std::string key(k.str());
    if (key != "kind" && !takes.count(key) && !(key == "vertices" && t.kind == "polygon"))
      throw InputError("table." + key, shown(v),
                       "does not apply to table.kind = \"" + t.kind + "\", which takes " + what);
  }
  const auto check_size = [](const std::string& name, const ExactInput& x) {
    const double v = std::abs(x.value.to_double());
    if (x.value.sign() != 0 && !(v >= 1e-100 && v <= 1e100))
      throw InputError(name, "\"" + x.text + "\"",
                       "must be 0 or of magnitude within [1e-100, 1e100] (doubles square it)");
  };
  for (const std::string& p : kind.params) {
    const toml::node* n = in.find("table", p);
    if (!n) throw InputError("table." + p, "(not given)", "table.kind = \"" + t.kind + "\" needs " + what);
    t.params.push_back(Reader::exact_node("table." + p, *n));
    check_size("table." + p, t.params.back());
  }
  if (t.kind == "polygon") read_vertices(in, t, check_size);
  s.table = t;
  TableSpec spec;
  try {
    spec = table_spec(s);
  } catch (const std::invalid_argument& e) {
    throw InputError("table", "{kind = \"" + t.kind + "\", ...}", e.what());
  }
  double shortest_piece = HUGE_VAL, longest_piece = 0;
  for (const PieceSpec& p : spec.pieces)
    shortest_piece = std::min(shortest_piece, p.length.to_double()),
    longest_piece = std::max(longest_piece, p.length.to_double());
  if (!(shortest_piece >= 1e-12 * longest_piece))
    throw InputError("table", "{kind = \"" + t.kind + "\", ...}",
                     "its pieces' lengths run from " + shortest(shortest_piece) + " to " + shortest(longest_piece) +
                         "; they must lie within a factor 1e12 of each other (doubles resolve them all)");
}

/// [[leaks]]: each leak's loop (an integer naming one of the table's loops, 0 by default), width (required), start
/// and omega (0 by default). A list of one leak on the outer boundary is that scene's [leak].
void read_leak_list(const Reader& in, Scene& s) {
  if (in.root.contains("leak"))
    throw InputError("leak", shown(*in.root.get("leak")), "give one leak as [leak] or a list as [[leaks]], not both");
  const int loops = static_cast<int>(table_spec(s).loops.size());
  const toml::array& list = *in.root.get_as<toml::array>("leaks");
  if (list.size() > static_cast<std::size_t>(kMaxLeaks))
    throw InputError("leaks", std::to_string(list.size()) + " leaks",
                     "at most " + std::to_string(kMaxLeaks) + " are allowed");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const toml::table& t = *list.get(i)->as_table();
    const std::string prefix = "leaks." + std::to_string(i);
    LeakInput l{0, {ExactReal(), ""}, {ExactReal(), "0"}, {ExactReal(), "0"}};
    if (const toml::node* n = t.get("loop")) {
      const auto k = n->as_integer();
      if (!k || k->get() < 0 || k->get() >= loops)
        throw InputError(prefix + ".loop", shown(*n),
                         "must be an integer in [0, " + std::to_string(loops - 1) +
                             "]: 0 the outer boundary, k the table's scatterer k");
      l.loop = static_cast<int>(k->get());
    }
    const toml::node* width = t.get("width");
    if (!width)
      throw InputError(prefix + ".width", "(not given)",
                       "every leak needs its width, a share of its loop's length in (0, 1)");
    l.width = Reader::exact_node(prefix + ".width", *width);
    if (const toml::node* n = t.get("start")) l.start = Reader::exact_node(prefix + ".start", *n);
    if (const toml::node* n = t.get("omega")) l.omega = Reader::exact_node(prefix + ".omega", *n);
    check_leak_values(prefix, l.width, l.start, l.omega);
    s.leaks.push_back(l);
  }
  if (s.leaks.size() == 1 && s.leaks[0].loop == 0) {  // one leak on the outer boundary: the scene's [leak]
    const LeakInput& l = s.leaks[0];
    s.width = l.width.value, s.width_text = l.width.text;
    s.start = l.start.value, s.start_text = l.start.text;
    s.omega = l.omega.value, s.omega_text = l.omega.text;
    s.leaks.clear();
  }
}

/// What only the stadium with one leak has, refused on any other table or with a list of leaks (docs/tables.md).
void check_table_needs(const Scene& s) {
  if (!s.on_table()) return;
  const std::string here =
      s.table ? "table.kind = \"" + s.table->kind + "\"" : std::to_string(leak_count(s)) + " leaks";
  if (s.sampling.kind == SamplingKind::mupo)
    throw InputError("ensemble.sampling", "\"mupo\"",
                     "draws near the stadium's bouncing-ball family: the stadium with one leak only (here " + here +
                         "); use \"uniform\"");
  if (s.fast_forward)
    throw InputError("run.fast_forward", "true",
                     "jumps the stadium's bouncing-ball phases: the stadium with one leak only (here " + here + ")");
}

}  // namespace scene_detail

void require_stadium(const Scene& scene, const std::string& command) {
  if (!scene.on_table()) return;
  throw InputError("SCENE", "\"" + scene.source + "\"",
                   command + " runs the stadium with one leak so far; this scene has " +
                       (scene.table ? "table.kind = \"" + scene.table->kind + "\"" : "") +
                       (scene.table && !scene.leaks.empty() ? " and " : "") +
                       (scene.leaks.empty() ? "" : std::to_string(scene.leaks.size()) + " leaks in [[leaks]]") +
                       " (rotleak simulate runs any table: docs/tables.md)");
}

}  // namespace rotleak
