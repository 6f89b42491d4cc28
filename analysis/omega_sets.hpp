// Sets of rotation speeds a scan sweeps (docs/output.md, "Value lists"): every value an exact text the scene
// reads as it is, so a point's omega is the number named, never a rounded stand-in.
//   rationals(qmax=Q)            every reduced p/q in (0, 1] with q <= Q, ascending
//   near(x, e1, e2, ... [, signs=plus|minus|both])
//                                x + e for each e (decimals > 0), x any exact value; signs=both adds x - e,
//                                ascending
//   nobles(n)                    the noble numbers [0; k, 1, 1, 1, ...] = 1 / (k - 1 + golden), k = 1..n
//   sqrtfrac(a, b)               the fractional parts sqrt(m) - floor(sqrt(m)) of the non-squares m in [a, b]
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace rotleak {

/// The values of one set call, or nullopt when `item` calls none of the sets (a literal value, another
/// list function). A malformed call is an InputError naming `option`, the item and its usage.
std::optional<std::vector<std::string>> expand_omega_set(const std::string& option, const std::string& item);

/// Every reduced p/q in (0, 1] with q <= qmax, ascending, as "p/q" ("1" for 1/1).
std::vector<std::string> rationals_up_to(unsigned qmax);

}  // namespace rotleak
