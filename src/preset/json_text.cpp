#include "preset/json_text.h"

#include <fmt/format.h>

#include "preset/preset.h"

namespace pluvia {
namespace {

// "line 3, column 14" of the 0-based byte offset.
std::string positionOf(const std::string& text, size_t offset) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return fmt::format("line {}, column {}", line, column);
}

}  // namespace

void checkJsonNesting(const std::string& text, const std::string& source) {
  int depth = 0;
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') {
        ++i;  // the escaped character cannot end the string
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonNesting) {
        throw PresetError(source,
                          {fmt::format("arrays and objects nest deeper than {} levels at {}",
                                       kMaxJsonNesting, positionOf(text, i))});
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

nlohmann::json parsePresetJson(const std::string& text, const std::string& source) {
  checkJsonNesting(text, source);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based, just past what was read.
    const size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    throw PresetError(source, {fmt::format("not valid JSON at {}", positionOf(text, offset))});
  } catch (const nlohmann::json::exception&) {
    throw PresetError(source, {"not valid JSON: a number is too large for a double"});
  }
}

}  // namespace pluvia
