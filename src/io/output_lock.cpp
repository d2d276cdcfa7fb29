#include "io/output_lock.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <thread>

#include <fmt/format.h>

#include "util/error.h"
#include "util/fs.h"
#include "util/hash.h"

namespace pluvia {
namespace {

// Each frame's bytes in the lock file: a frame range locks [first, last + 1) x this, and its
// holder writes "pid host" in its first frame's bytes.
constexpr off_t kBytesPerFrame = 64;
// A render that finishes holds the whole file for the moment it takes to remove it: a render
// that meets that lock tries again for this long before it is refused.
constexpr auto kRetryFor = std::chrono::milliseconds(500);
constexpr auto kRetryStep = std::chrono::milliseconds(20);

bool locksWholeOutput(const OutputTarget& output, int64_t firstFrame) {
  return !output.isSequence() || firstFrame < 0;
}

FileRangeLock lockFrames(const OutputTarget& output, int64_t firstFrame, int64_t lastFrame) {
  const std::string path = outputLockPath(output);
  const bool whole = locksWholeOutput(output, firstFrame);
  const off_t start = whole ? 0 : static_cast<off_t>(firstFrame) * kBytesPerFrame;
  const off_t length = whole ? 0 : static_cast<off_t>(lastFrame - firstFrame + 1) * kBytesPerFrame;
  const auto giveUp = std::chrono::steady_clock::now() + kRetryFor;
  LockConflict conflict;
  try {
    while (true) {
      if (auto lock = FileRangeLock::tryLock(path, start, length, &conflict))
        return std::move(*lock);
      if (std::chrono::steady_clock::now() > giveUp) break;
      std::this_thread::sleep_for(kRetryStep);
    }
  } catch (const Error& e) {
    throw Error(e.what(), {"write", {}, output.path});
  }
  std::string what = output.path;
  if (conflict.length > 0 && !whole) {
    const int64_t first = conflict.start / kBytesPerFrame;
    const int64_t last = (conflict.start + conflict.length) / kBytesPerFrame - 1;
    what = first == last ? fmt::format("frame {} of {}", first, output.path)
                         : fmt::format("frames {}-{} of {}", first, last, output.path);
  }
  throw Error(fmt::format("another render (pid and host: {}) is writing {}; wait for it or write "
                          "elsewhere (lock file {})",
                          conflict.holder, what, path),
              {"write", {}, output.path});
}

// The frame number in a temporary's name ("o.0012.pluvia-tmp-7-0.exr" or, for an AOV written
// beside the beauty, "o.rain.0012.pluvia-tmp-7-0.png", with the prefix "o."), or -1.
int64_t frameOfTemporary(const std::string& name, const std::string& prefix) {
  const size_t marker = name.find(".pluvia-tmp-");
  if (marker == std::string::npos || marker <= prefix.size() || name.rfind(prefix, 0) != 0)
    return -1;
  std::string middle = name.substr(prefix.size(), marker - prefix.size());
  for (const char* aov : {"rain.", "matte.", "depth."})
    if (middle.rfind(aov, 0) == 0) middle = middle.substr(std::strlen(aov));
  if (middle.empty() || middle.size() > 12 ||
      middle.find_first_not_of("0123456789") != std::string::npos)
    return -1;
  return std::stoll(middle);
}

}  // namespace

std::string outputLockPath(const OutputTarget& output) {
  std::string path = output.path;
  if (output.pattern) {
    const SequencePattern& pattern = *output.pattern;
    const size_t digits = static_cast<size_t>(std::max(pattern.padding, 1));
    path = pattern.prefix + std::string(digits, '#') + pattern.suffix;
  }
  constexpr std::string_view kSuffix = ".pluvia-lock";
  const std::filesystem::path named(path);
  std::string name = named.filename().string();
  // A legal output name near the 255-byte limit still gets a lock: its name is cut and the
  // whole name's hash keeps two such outputs apart (every render of one output agrees on it).
  if (name.size() + kSuffix.size() > fs::kNameMaxBytes) {
    const std::string hash = fmt::format("-{}", Hasher().add(name).hex());
    name.resize(fs::kNameMaxBytes - kSuffix.size() - hash.size());
    name += hash;
  }
  return (named.parent_path() / (name + std::string(kSuffix))).string();
}

OutputLock::OutputLock(const OutputTarget& output, int64_t firstFrame, int64_t lastFrame)
    : output_(output),
      firstFrame_(firstFrame),
      lastFrame_(lastFrame),
      wholeOutput_(locksWholeOutput(output, firstFrame)),
      lock_(lockFrames(output, firstFrame, lastFrame)) {}

int OutputLock::removeStaleTemporaries() const {
  const std::filesystem::path folder = std::filesystem::path(output_.path).parent_path();
  if (wholeOutput_) {
    return fs::removeStaleTemporaries(folder,
                                      std::filesystem::path(output_.path).stem().string() + ".");
  }
  const SequencePattern& pattern = *output_.pattern;
  const std::string prefix = std::filesystem::path(pattern.prefix + "0").filename().string();
  const std::string namePrefix = prefix.substr(0, prefix.size() - 1);
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder.empty() ? "." : folder, ec)) {
    const std::string name = entry.path().filename().string();
    const int64_t frame = frameOfTemporary(name, namePrefix);
    if (frame < firstFrame_ || frame > lastFrame_ || !fs::isStaleTemporary(entry.path())) continue;
    std::error_code removeError;
    removed += std::filesystem::remove(entry.path(), removeError) ? 1 : 0;
  }
  return removed;
}

}  // namespace pluvia
