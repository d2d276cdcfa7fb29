#pragma once
// Parsing preset JSON text safely: nesting is bounded before anything recursive sees the
// document (a preset nested 60,000 levels deep crashed the serialiser that builds error
// messages), and errors give a position, never the text itself (an `extends` naming another
// file, /etc/passwd say, must not print its contents).
#include <string>

#include <nlohmann/json.hpp>

namespace pluvia {

// Deeper nesting than any preset needs (the deepest shipped key is 5 levels down).
inline constexpr int kMaxJsonNesting = 64;

// Throws PresetError for `source` when arrays and objects in `text` nest deeper than
// kMaxJsonNesting, naming the line and column where they do. Scans without recursion.
void checkJsonNesting(const std::string& text, const std::string& source);

// True when `text` is valid UTF-8, as JSON strings must be (a --set value that is not JSON
// becomes a string, and serialising one with invalid bytes throws).
bool isValidUtf8(const std::string& text);

// Parses `text` after checkJsonNesting(). Throws PresetError for `source` naming the line and
// column of a syntax error, or a number too large for a double.
nlohmann::json parsePresetJson(const std::string& text, const std::string& source);

}  // namespace pluvia
