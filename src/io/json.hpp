// The JSON type of every document rotleak writes: keys keep the order they were written in.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>

namespace rotleak {

using json = nlohmann::ordered_json;

/// A value or null.
template <class T>
json nullable(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

}  // namespace rotleak
