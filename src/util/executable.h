#pragma once
// The running binary's own path, read once from /proc/self/exe: presets, assets and the
// bundled example are searched beside it, and the farm and the benches run it again.
#include <filesystem>
#include <string>
#include <vector>

namespace pluvia {

// The binary's absolute path; empty when /proc/self/exe cannot be read.
const std::filesystem::path& executablePath();

// Where pluvia's shipped data of one kind ("presets", "assets") is looked for, in order: `first`
// (a folder the user set; skipped when empty), KIND beside the binary's parent (the source tree
// for build/pluvia), an installed share/pluvia/KIND, and `sourceFolder` (the configured source
// tree's).
std::vector<std::filesystem::path> shippedDataFolders(const std::filesystem::path& first,
                                                      const std::string& kind,
                                                      const std::filesystem::path& sourceFolder);

}  // namespace pluvia
