#include "analysis/omega_sets.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <numeric>

#include "numeric/exact.hpp"
#include "numeric/input.hpp"

namespace rotleak {

namespace {

/// The arguments of `name(...)`, or nullopt when item is not a call of name.
std::optional<std::vector<std::string>> call_args(const std::string& option, const std::string& item,
                                                  const std::string& name) {
  if (item.rfind(name + "(", 0) != 0 || item.back() != ')') return std::nullopt;
  return split_top(option, item.substr(name.size() + 1, item.size() - name.size() - 2));
}

/// A whole number in [lo, hi] given as plain digits.
std::optional<unsigned> small_count(const std::string& text, unsigned lo, unsigned hi) {
  if (text.empty() || text.size() > 6 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  const unsigned v = static_cast<unsigned>(std::stoul(text));
  if (v < lo || v > hi) return std::nullopt;
  return v;
}

/// Values sorted by their exact value (the texts are parsed once; equal values keep their order).
std::vector<std::string> ascending(std::vector<std::pair<std::string, ExactReal>> v) {
  std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return (a.second - b.second).sign() < 0; });
  std::vector<std::string> out;
  for (auto& p : v) out.push_back(std::move(p.first));
  return out;
}

}  // namespace

std::vector<std::string> rationals_up_to(unsigned qmax) {
  std::vector<std::pair<mpq_class, std::string>> v;
  for (unsigned q = 1; q <= qmax; ++q)
    for (unsigned p = 1; p <= q; ++p)
      if (std::gcd(p, q) == 1)
        v.emplace_back(mpq_class(p, q), q == 1 ? std::to_string(p) : std::to_string(p) + "/" + std::to_string(q));
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (auto& p : v) out.push_back(std::move(p.second));
  return out;
}

namespace {

/// rationals(qmax=Q): every reduced p/q in (0, 1] with q <= Q.
std::vector<std::string> rationals_set(const std::string& option, const std::string& item,
                                       const std::vector<std::string>& args) {
  const std::string usage = "rationals(qmax=Q): every reduced p/q in (0, 1] with q <= Q, Q an integer in [1, 300]";
  if (args.size() != 1) throw InputError(option, item, usage);
  std::string q = args[0];
  if (q.rfind("qmax", 0) == 0) {
    const auto eq = q.find('=');
    if (eq == std::string::npos || trim(q.substr(4, eq - 4)) != "") throw InputError(option, item, usage);
    q = trim(q.substr(eq + 1));
  }
  const auto qmax = small_count(q, 1, 300);
  if (!qmax) throw InputError(option, item, usage);
  return rationals_up_to(*qmax);
}

/// near(x, e1, e2, ... [, signs=plus|minus|both]): x +- each e, in ascending order.
std::vector<std::string> near_set(const std::string& option, const std::string& item,
                                  const std::vector<std::string>& given) {
  const std::string usage =
      "near(x, e1, e2, ... [, signs=plus|minus|both]): x an exact value, each e a decimal > 0; x + e (plus, the "
      "default), x - e (minus) or both";
  std::vector<std::string> args = given;
  std::string signs = "plus";
  if (!args.empty() && args.back().rfind("signs", 0) == 0) {
    const auto eq = args.back().find('=');
    if (eq == std::string::npos) throw InputError(option, item, usage);
    signs = trim(args.back().substr(eq + 1));
    args.pop_back();
    if (signs != "plus" && signs != "minus" && signs != "both") throw InputError(option, item, usage);
  }
  if (args.size() < 2) throw InputError(option, item, usage);
  ExactReal x;
  try {
    x = parse_exact_input(option, args[0]);
  } catch (const InputError&) {
    throw InputError(option, item, usage + " (\"" + args[0] + "\" is not an exact value)");
  }
  std::vector<std::pair<std::string, ExactReal>> v;
  for (std::size_t k = 1; k < args.size(); ++k) {
    mpq_class e;
    try {
      e = parse_decimal(args[k]);
    } catch (const ExactParseError&) {
      throw InputError(option, item, usage + " (\"" + args[k] + "\" is not a decimal)");
    }
    if (sgn(e) <= 0) throw InputError(option, item, usage + " (\"" + args[k] + "\" is not > 0)");
    const ExactReal d = ExactReal::rational(e);
    if (signs != "minus") v.emplace_back(args[0] + "+" + args[k], x + d);
    if (signs != "plus") v.emplace_back(args[0] + "-" + args[k], x - d);
  }
  return ascending(std::move(v));
}

/// nobles(n): the noble numbers 1/(k-1+golden), k = 1..n.
std::vector<std::string> nobles_set(const std::string& option, const std::string& item,
                                    const std::vector<std::string>& args) {
  const std::string usage = "nobles(n): the noble numbers [0; k, 1, 1, ...] = 1/(k-1+golden), k = 1..n, n in [1, 50]";
  if (args.size() != 1) throw InputError(option, item, usage);
  const auto n = small_count(args[0], 1, 50);
  if (!n) throw InputError(option, item, usage);
  std::vector<std::string> out;
  for (unsigned k = 1; k <= *n; ++k) out.push_back(k == 1 ? "1/golden" : "1/(" + std::to_string(k - 1) + "+golden)");
  return out;
}

/// sqrtfrac(a, b): the fractional parts of the square roots of the non-squares in [a, b].
std::vector<std::string> sqrtfrac_set(const std::string& option, const std::string& item,
                                      const std::vector<std::string>& args) {
  const std::string usage =
      "sqrtfrac(a, b): sqrt(m) - floor(sqrt(m)) for every non-square m in [a, b], integers 2 <= a <= b <= 10000";
  if (args.size() != 2) throw InputError(option, item, usage);
  const auto lo = small_count(args[0], 2, 10000), hi = small_count(args[1], 2, 10000);
  if (!lo || !hi || *lo > *hi) throw InputError(option, item, usage);
  std::vector<std::string> out;
  for (unsigned m = *lo; m <= *hi; ++m) {
    unsigned root = 0;
    while ((root + 1) * (root + 1) <= m) ++root;
    if (root * root != m) out.push_back("sqrt(" + std::to_string(m) + ")-" + std::to_string(root));
  }
  if (out.empty()) throw InputError(option, item, usage + " (no non-square in the range)");
  return out;
}

}  // namespace

std::optional<std::vector<std::string>> expand_omega_set(const std::string& option, const std::string& item) {
  if (const auto a = call_args(option, item, "rationals")) return rationals_set(option, item, *a);
  if (const auto a = call_args(option, item, "near")) return near_set(option, item, *a);
  if (const auto a = call_args(option, item, "nobles")) return nobles_set(option, item, *a);
  if (const auto a = call_args(option, item, "sqrtfrac")) return sqrtfrac_set(option, item, *a);
  return std::nullopt;
}

}  // namespace rotleak
