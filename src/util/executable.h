#pragma once
// The running binary's own path, read once from /proc/self/exe: presets, assets and the
// bundled example are searched beside it, and the farm and the benches run it again.
#include <filesystem>

namespace pluvia {

// The binary's absolute path; empty when /proc/self/exe cannot be read.
const std::filesystem::path& executablePath();

}  // namespace pluvia
