// The one place a tier becomes a number type: with_tier(tier, f) calls f(std::type_identity<R>{})
// with R the tier's type (MPFR and MPFI at the tier's bits on this thread, for the call's duration).
#pragma once

#include <stdexcept>
#include <type_traits>

#include "numeric/tier.hpp"
#include "numeric/tiers.hpp"

namespace rotleak {

template <class F>
decltype(auto) with_tier(const Tier& tier, F&& f) {
  switch (tier.kind) {
    case TierKind::float_:
      return f(std::type_identity<float>{});
    case TierKind::double_:
      return f(std::type_identity<double>{});
    case TierKind::long_double:
      return f(std::type_identity<long double>{});
    case TierKind::dd:
      return f(std::type_identity<dd_real>{});
    case TierKind::float128:
      return f(std::type_identity<float128>{});
    case TierKind::mpfr: {
      MpfrPrecision working(tier.bits);
      return f(std::type_identity<Mpfr>{});
    }
    case TierKind::mpfi: {
      MpfrPrecision working(tier.bits);
      return f(std::type_identity<Mpfi>{});
    }
    case TierKind::automatic:
      break;
  }
  throw std::logic_error("tier \"auto\" must be resolved (verify/auto_tier) before it runs");
}

/// The same from a name; std::invalid_argument(name) when it names no tier.
template <class F>
decltype(auto) with_tier(const std::string& name, F&& f) {
  const auto tier = Tier::parse(name);
  if (!tier) throw std::invalid_argument(name);
  return with_tier(*tier, std::forward<F>(f));
}

}  // namespace rotleak
