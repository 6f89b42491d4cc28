// The tier registry: every precision the suite runs, by name, with its significand bits. Light on
// purpose (no number types): scenes, options and reports name tiers through it; the one dispatch
// from a tier to its number type is with_tier() in numeric/tier_dispatch.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace rotleak {

enum class TierKind { float_, double_, long_double, dd, float128, mpfr, mpfi, automatic };

struct Tier {
  TierKind kind = TierKind::double_;
  long bits = 53;  ///< significand bits (0 for automatic)

  /// "float", "double", "long_double", "dd", "float128", "mpfr:B", "mpfi:B", "auto".
  std::string name() const;
  bool interval() const { return kind == TierKind::mpfi; }
  bool automatic() const { return kind == TierKind::automatic; }
  /// The ensemble engine runs these (the IEEE types); the others are for single trajectories.
  bool ensemble() const {
    return kind == TierKind::float_ || kind == TierKind::double_ || kind == TierKind::long_double;
  }

  /// The tier a name denotes ("auto" included); nothing for an unknown name or bits outside [kMinBits, kMaxBits].
  static std::optional<Tier> parse(const std::string& name);
  static Tier mpfr(long bits) { return {TierKind::mpfr, bits}; }
  static Tier mpfi(long bits) { return {TierKind::mpfi, bits}; }
  static constexpr long kMinBits = 24, kMaxBits = 1L << 20;  ///< for mpfr:B and mpfi:B

  static const Tier float_, double_, long_double, auto_;
  friend bool operator==(const Tier& a, const Tier& b) { return a.kind == b.kind && a.bits == b.bits; }
};

inline const Tier Tier::float_{TierKind::float_, 24};
inline const Tier Tier::double_{TierKind::double_, 53};
inline const Tier Tier::long_double{TierKind::long_double, 64};
inline const Tier Tier::auto_{TierKind::automatic, 0};

inline std::string to_string(const Tier& t) { return t.name(); }

/// Significand bits of a tier name (0 for a name that is not one, and for "auto").
long tier_bits(const std::string& name);
/// "double,dd,mpfr:256" -> the names; throws std::invalid_argument(name) for the first bad one
/// ("auto" is not a tier to run here).
std::vector<std::string> parse_tier_list(const std::string& list, bool allow_intervals);
/// What a user may write for a tier, for error messages.
std::string tier_names_allowed(bool allow_intervals);

}  // namespace rotleak
