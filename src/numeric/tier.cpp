#include "numeric/tier.hpp"

#include <stdexcept>

namespace rotleak {

namespace {

struct Named {
  const char* name;
  TierKind kind;
  long bits;
};
// long double's bits are the x86-64 extended format's; num_traits<long double> says the same (a test checks).
constexpr Named kFixed[] = {
    {"float", TierKind::float_, 24}, {"double", TierKind::double_, 53},     {"long_double", TierKind::long_double, 64},
    {"dd", TierKind::dd, 106},       {"float128", TierKind::float128, 113}, {"auto", TierKind::automatic, 0}};

}  // namespace

std::string Tier::name() const {
  if (kind == TierKind::mpfr) return "mpfr:" + std::to_string(bits);
  if (kind == TierKind::mpfi) return "mpfi:" + std::to_string(bits);
  for (const Named& n : kFixed)
    if (n.kind == kind) return n.name;
  return "?";
}

std::optional<Tier> Tier::parse(const std::string& n) {
  for (const Named& f : kFixed)
    if (n == f.name) return Tier{f.kind, f.bits};
  const bool mp = n.rfind("mpfr:", 0) == 0, mi = n.rfind("mpfi:", 0) == 0;
  if (!mp && !mi) return std::nullopt;
  const std::string digits = n.substr(5);
  if (digits.empty() || digits.size() > 8 || digits.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  const long b = std::stol(digits);
  if (b < kMinBits || b > kMaxBits) return std::nullopt;
  return Tier{mp ? TierKind::mpfr : TierKind::mpfi, b};
}

long tier_bits(const std::string& name) {
  const auto t = Tier::parse(name);
  return t ? t->bits : 0;
}

std::vector<std::string> parse_tier_list(const std::string& list, bool allow_intervals) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (;;) {
    const std::size_t comma = list.find(',', from);
    const std::string t = list.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    const auto tier = Tier::parse(t);
    if (!tier || tier->automatic() || (!allow_intervals && tier->interval())) throw std::invalid_argument(t);
    out.push_back(t);
    if (comma == std::string::npos) return out;
    from = comma + 1;
  }
}

std::string tier_names_allowed(bool allow_intervals) {
  return std::string("float, double, long_double, dd, float128, mpfr:BITS") + (allow_intervals ? ", mpfi:BITS" : "") +
         " (BITS " + std::to_string(Tier::kMinBits) + "..2^20)";
}

}  // namespace rotleak
