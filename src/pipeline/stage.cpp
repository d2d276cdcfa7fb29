#include "pipeline/stage.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "util/fs.h"
#include "util/hash.h"

namespace pluvia {
namespace {

constexpr std::streamoff kSampleBytes = 1 << 20;

// The first and the last MiB of a file: a plate replaced in place by another of the same size
// and modification time (a copy with `touch -r`, a restore) differs there.
void addContentSample(Hasher& hasher, const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  std::string bytes;
  for (const std::streamoff start :
       {std::streamoff(0), std::max<std::streamoff>(0, size - kSampleBytes)}) {
    bytes.assign(static_cast<size_t>(std::min(kSampleBytes, size - start)), '\0');
    in.seekg(start);
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    hasher.add(std::string_view(bytes.data(), static_cast<size_t>(in.gcount())));
    if (size <= kSampleBytes) break;
  }
}

}  // namespace

const std::map<std::string, std::string>& artifactsMadeOutsideStages() {
  static const std::map<std::string, std::string> made{{"image", "the plate"},
                                                       {"camera", "camera.path"},
                                                       {"still", "the frames, on first use"},
                                                       {"plate_rain", "the frames, on first use"}};
  return made;
}

std::string clipIdentity(const ClipInfo& clip) {
  Hasher hasher;
  // Names absolute with links resolved: a relative and an absolute spelling of one plate (a
  // local resume over a farm's frames) are one plate.
  hasher.add(fs::canonicalSpelling(clip.path).string());
  std::error_code ec;
  for (const auto& file : clip.files) {
    hasher.add(fs::canonicalSpelling(file).string());
    hasher.add(static_cast<uint64_t>(std::filesystem::file_size(file, ec)));
    auto time = std::filesystem::last_write_time(file, ec);
    hasher.add(static_cast<uint64_t>(time.time_since_epoch().count()));
  }
  hasher.add(static_cast<uint64_t>(clip.frames.size()));
  if (!clip.files.empty()) {
    for (const size_t i : {size_t(0), clip.files.size() / 2, clip.files.size() - 1})
      addContentSample(hasher, clip.files[i]);
  }
  return hasher.hex();
}

}  // namespace pluvia
