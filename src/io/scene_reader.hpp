// The scene reader's parts shared by its files (io/scene_file.cpp: the sections of the stadium with one leak, the
// ensemble, the run, the observers and fits; io/scene_table.cpp: [table], [[leaks]] and what only the stadium has).
// Internal to the reader: every function throws InputError naming the key, the value and what is allowed.
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "io/scene_file.hpp"
#include "numeric/input.hpp"

namespace rotleak::scene_detail {

const std::set<std::string> kListedLeakKeys = {"loop", "width", "start", "omega"};
/// A TOML value as the user wrote it, for messages.
inline std::string shown(const toml::node& n) {
  std::ostringstream os;
  if (auto s = n.as_string())
    os << '"' << s->get() << '"';
  else if (auto f = n.as_floating_point()) {
    os << toml_float(f->get());  // 1000.0 as written, not 1000
  } else if (n.is_table()) {
    os << "{...}";
  } else if (auto a = n.as_array()) {  // inline, as written: toml++ would print one element a line
    os << "[";
    for (std::size_t i = 0; i < a->size(); ++i) os << (i ? ", " : "") << shown(*a->get(i));
    os << "]";
  } else {
    n.visit([&](auto&& v) { os << v; });
  }
  return os.str();
}

struct Reader {
  const toml::table& root;

  const toml::node* find(const std::string& section, const std::string& key) const {
    if (auto sec = root.get_as<toml::table>(section)) return sec->get(key);
    return nullptr;
  }

  ExactReal exact(const std::string& section, const std::string& key, std::string& text, ExactReal fallback) const {
    const toml::node* n = find(section, key);
    if (!n) return fallback;
    ExactInput in = exact_node(section + "." + key, *n);
    text = in.text;
    return in.value;
  }

  /// An exact value named `name`: a string (read exactly) or an integer, never a float (read through double).
  static ExactInput exact_node(const std::string& name, const toml::node& n) {
    std::string text;
    if (n.is_floating_point()) {
      const std::string key = name.substr(name.rfind('.') + 1);
      throw InputError(name, shown(n),
                       "write it as a string (e.g. " + key + " = \"0.01\") so it is read exactly, not through double");
    }
    if (auto i = n.as_integer())
      text = std::to_string(i->get());
    else if (auto s = n.as_string())
      text = s->get();
    else
      throw InputError(name, shown(n), "must be an exact number given as a string or an integer");
    return {parse_exact_input(name, text), text};
  }

  /// A number key, checked: a value outside `ok` is refused naming the key and what was used -- the
  /// text given, or the default when the key was not given (a default can fail too: creation_window 4
  /// with t_max 1). Every range check of a number goes through here, so no error path looks up a
  /// key that may be absent.
  template <class Ok>
  double number(const std::string& section, const std::string& key, double fallback, Ok ok,
                const std::string& allowed) const {
    const toml::node* n = find(section, key);
    const double v = n ? as_number(section + "." + key, *n) : fallback;
    if (!ok(v)) throw InputError(section + "." + key, n ? shown(*n) : toml_float(v) + " (the default)", allowed);
    return v;
  }

  static double as_number(const std::string& name, const toml::node& n) {
    double v;
    if (auto i = n.as_integer())
      v = static_cast<double>(i->get());
    else if (auto f = n.as_floating_point())
      v = f->get();
    else
      throw InputError(name, shown(n), "must be a number");
    if (!std::isfinite(v)) throw InputError(name, shown(n), "must be a finite number");
    return v;
  }

  std::uint64_t count(const std::string& section, const std::string& key, std::uint64_t fallback, std::uint64_t min,
                      const std::string& allowed) const {
    const toml::node* n = find(section, key);
    if (!n) return fallback;
    auto i = n->as_integer();
    if (n->is_floating_point())  // TOML reads 1e6 as a float; --set reads it exactly
      throw InputError(section + "." + key, shown(*n),
                       allowed + " (TOML reads 1e6 as a float: write 1000000 in a scene file, or --set " + section +
                           "." + key + "=1e6)");
    if (!i || i->get() < 0 || static_cast<std::uint64_t>(i->get()) < min)
      throw InputError(section + "." + key, shown(*n), allowed);
    return static_cast<std::uint64_t>(i->get());
  }

  std::string word(const std::string& section, const std::string& key, const std::string& fallback,
                   const std::set<std::string>& allowed) const {
    const toml::node* n = find(section, key);
    if (!n) return fallback;
    auto s = n->as_string();
    if (!s || !allowed.count(s->get())) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
      throw InputError(section + "." + key, shown(*n), "must be one of " + list);
    }
    return s->get();
  }

  static TimeWindow window(const std::string& name, const toml::node& n) {
    auto a = n.as_array();
    if (!a || a->size() != 2)
      throw InputError(name, shown(n), "must be a pair of times [from, to] with 0 <= from < to");
    TimeWindow w{as_number(name, *a->get(0)), as_number(name, *a->get(1))};
    if (!(w.from >= 0 && w.from < w.to))
      throw InputError(name, shown(n), "must be a pair of times [from, to] with 0 <= from < to");
    return w;
  }
};

inline std::string listed(const std::set<std::string>& keys) {
  std::string list;
  for (const auto& a : keys) list += (list.empty() ? "" : ", ") + a;
  return list;
}

/// [table]'s keys: its kind, a polygon's vertices, and every standard table's parameters.
std::set<std::string> table_keys();
/// --set leaks.N.key=value: a key of the listed leak N (from 0) of the scene's [[leaks]].
void override_listed_leak(toml::table& root, const std::string& rest, const std::string& value);
/// The text of a --set value: a value quoted as in a scene file ("2/3") is the text inside.
std::string unquoted(const std::string& value);
/// Sets section[key] to `value` read as a TOML value (`v = VALUE`), or to the bare word where it is none (the key's
/// own check says whether a word is allowed); false for the bare word.
bool set_value(toml::table& section, const std::string& key, const std::string& value);
/// One leak's width, start and omega, checked (`prefix` names its keys: "leak", "leaks.1").
void check_leak_values(const std::string& prefix, const ExactInput& width, const ExactInput& start,
                       const ExactInput& omega);
/// [table] with a kind other than the stadium, into s.table.
void read_table(const Reader& in, Scene& s);
/// [[leaks]], into s.leaks (a list of one leak on the outer boundary into the scene's one leak).
void read_leak_list(const Reader& in, Scene& s);
/// What only the stadium with one leak has, refused on any other table or with a list of leaks.
void check_table_needs(const Scene& s);

}  // namespace rotleak::scene_detail
