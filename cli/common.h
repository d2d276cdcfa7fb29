#pragma once
// Helpers shared by the subcommands.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "preset/preset.h"

namespace pluvia::cli {

// "1001-1048" or "12" -> (first, last). Throws UsageError naming the text.
std::pair<int64_t, int64_t> parseFrameRange(const std::string& text);
// Resolves a preset against the full schema (every stage's table).
Preset loadPreset(const std::string& nameOrPath, const std::vector<std::string>& overrides);
// The command line as one shell-quoted string, for logs and metadata.
std::string joinCommandLine(int argc, char** argv);

}  // namespace pluvia::cli
