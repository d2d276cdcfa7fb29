#include "preset/json_text.h"

#include <cstdint>
#include <set>
#include <vector>

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

bool isValidUtf8(const std::string& text) {
  for (size_t i = 0; i < text.size();) {
    const auto lead = static_cast<unsigned char>(text[i]);
    // Continuation bytes that follow the lead byte, and the smallest code point that needs them
    // (smaller ones are overlong encodings).
    size_t continuation = 0;
    uint32_t codePoint = 0, smallest = 0;
    if (lead < 0x80) {
      ++i;
      continue;
    } else if ((lead & 0xE0) == 0xC0) {
      continuation = 1, codePoint = lead & 0x1F, smallest = 0x80;
    } else if ((lead & 0xF0) == 0xE0) {
      continuation = 2, codePoint = lead & 0x0F, smallest = 0x800;
    } else if ((lead & 0xF8) == 0xF0) {
      continuation = 3, codePoint = lead & 0x07, smallest = 0x10000;
    } else {
      return false;
    }
    if (i + continuation >= text.size()) return false;  // cut short
    for (size_t k = 1; k <= continuation; ++k) {
      const auto byte = static_cast<unsigned char>(text[i + k]);
      if ((byte & 0xC0) != 0x80) return false;
      codePoint = (codePoint << 6) | (byte & 0x3F);
    }
    if (codePoint < smallest || codePoint > 0x10FFFF ||
        (codePoint >= 0xD800 && codePoint <= 0xDFFF))
      return false;
    i += continuation + 1;
  }
  return true;
}

nlohmann::json parsePresetJson(const std::string& text, const std::string& source) {
  checkJsonNesting(text, source);
  // The parser stops at a NUL byte: what follows would be ignored unseen.
  if (const size_t nul = text.find('\0'); nul != std::string::npos)
    throw PresetError(
        source, {fmt::format("a NUL byte at {}: not a JSON text file", positionOf(text, nul))});
  // A key given twice in one object: JSON takes the last silently, so a preset edited by hand
  // could hold a value nobody sees. Each object's keys so far, innermost last.
  std::vector<std::set<std::string>> keys;
  std::vector<std::string> duplicates;
  const nlohmann::json::parser_callback_t noteDuplicates =
      [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start) keys.emplace_back();
        if (event == Event::object_end && !keys.empty()) keys.pop_back();
        if (event == Event::key && !keys.empty() &&
            !keys.back().insert(parsed.get<std::string>()).second)
          duplicates.push_back(parsed.get<std::string>());
        return true;
      };
  try {
    nlohmann::json value = nlohmann::json::parse(text, noteDuplicates);
    if (!duplicates.empty())
      throw PresetError(source,
                        {fmt::format("the key \"{}\" is given twice in one object (JSON would "
                                     "take the last silently): keep one",
                                     duplicates.front())});
    return value;
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based, just past what was read.
    const size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    throw PresetError(source, {fmt::format("not valid JSON at {}", positionOf(text, offset))});
  } catch (const nlohmann::json::exception&) {
    throw PresetError(source, {"not valid JSON: a number is too large for a double"});
  }
}

}  // namespace pluvia
