// Stable, readable names for parameterised tests: "<index>_<what the parameter says>", so ctest
// names do not change from build to build (GoogleTest's default prints bytes or pointers).
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <type_traits>
#include <utility>

namespace rotleak::test {

/// Text reduced to [A-Za-z0-9_]: a decimal point as 'p', '/' as "_over_", every other run of
/// symbols one '_', at most 48 characters.
inline std::string name_part(const std::string& text) {
  std::string out;
  auto digit = [&](std::size_t i) { return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (std::isalnum(static_cast<unsigned char>(c)))
      out += c;
    else if (c == '.' && digit(i + 1) && (i == 0 || digit(i - 1)))
      out += 'p';
    else if (c == '/')
      out += "_over_";
    else if (!out.empty() && out.back() != '_')
      out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  if (out.size() > 48) out.resize(48);
  return out.empty() ? "x" : out;
}

template <class P>
std::string describe(const P& p) {
  if constexpr (std::is_convertible_v<P, std::string>)
    return name_part(std::string(p));
  else if constexpr (requires {
                       p.first;
                       p.second;
                     })
    return describe(p.first) + "_" + describe(p.second);
  else
    return name_part(p.key);  // a case struct names itself by the key it is about
}

/// name_generator for INSTANTIATE_TEST_SUITE_P.
struct IndexedName {
  template <class P>
  std::string operator()(const ::testing::TestParamInfo<P>& info) const {
    return std::to_string(info.index) + "_" + describe(info.param);
  }
};

}  // namespace rotleak::test
