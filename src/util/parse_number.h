#pragma once
// A number that must be the whole of a text (a command-line value, a field of a file).
#include <charconv>
#include <cstdint>
#include <optional>
#include <string_view>
#include <type_traits>

namespace pluvia {

// `text` as an int, int64_t or double (std::from_chars: an optional '-', no leading space or
// '+'); nullopt when it is not a number, is out of the type's range or has anything after the
// number ("12x", "1.5" for an int).
template <class T>
std::optional<T> parseWholeNumber(std::string_view text) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, int64_t> || std::is_same_v<T, double>);
  T value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end) return std::nullopt;
  return value;
}

}  // namespace pluvia
