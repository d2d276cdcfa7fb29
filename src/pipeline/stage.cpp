#include "pipeline/stage.h"

#include <filesystem>

#include "util/hash.h"

namespace pluvia {

std::string clipIdentity(const ClipInfo& clip) {
  Hasher hasher;
  hasher.add(clip.path);
  std::error_code ec;
  for (const auto& file : clip.files) {
    hasher.add(file);
    hasher.add(static_cast<uint64_t>(std::filesystem::file_size(file, ec)));
    auto time = std::filesystem::last_write_time(file, ec);
    hasher.add(static_cast<uint64_t>(time.time_since_epoch().count()));
  }
  hasher.add(static_cast<uint64_t>(clip.frames.size()));
  return hasher.hex();
}

}  // namespace pluvia
