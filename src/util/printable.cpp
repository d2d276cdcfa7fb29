#include "util/printable.h"

#include <fmt/format.h>

namespace pluvia {

std::string printable(std::string_view text, bool keepLines) {
  std::string shown;
  shown.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    const bool control = byte < 0x20 || byte == 0x7f;
    if (!control || (keepLines && (c == '\n' || c == '\t')))
      shown += c;
    else
      shown += fmt::format("\\x{:02x}", byte);
  }
  return shown;
}

}  // namespace pluvia
