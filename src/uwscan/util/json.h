// Figures that may not have been measured, in and out of JSON: null, not a
// made-up 0 or 1.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>

namespace uwscan {

// `value` where it was measured, else null.
template <typename T>
nlohmann::json ValueOrNull(bool measured, const T& value) {
  return measured ? nlohmann::json(value) : nlohmann::json();
}

// The number at `key` of a JSON object; none if absent, null or not a number.
inline std::optional<double> NumberAt(const nlohmann::json& object, const char* key) {
  if (!object.is_object()) return std::nullopt;
  const auto found = object.find(key);
  if (found == object.end() || !found->is_number()) return std::nullopt;
  return found->get<double>();
}

}  // namespace uwscan
