#pragma once
// A number that must be the whole of a text (a command-line value, a field of a file): what
// std::stoi, std::stoll and std::stod read, but nothing may follow it.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace pluvia {

// `text` as an int, int64_t or double; nullopt when it is not a number, is out of the type's
// range or has anything after the number ("12x", "1.5" for an int).
template <class T>
std::optional<T> parseWholeNumber(const std::string& text) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, int64_t> || std::is_same_v<T, double>);
  size_t used = 0;
  T value{};
  try {
    if constexpr (std::is_same_v<T, int>)
      value = std::stoi(text, &used);
    else if constexpr (std::is_same_v<T, int64_t>)
      value = std::stoll(text, &used);
    else
      value = std::stod(text, &used);
  } catch (const std::logic_error&) {  // std::invalid_argument, std::out_of_range
    return std::nullopt;
  }
  if (used != text.size()) return std::nullopt;
  return value;
}

}  // namespace pluvia
