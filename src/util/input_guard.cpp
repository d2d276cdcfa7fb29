#include "util/input_guard.h"

#include <sys/stat.h>

#include <map>
#include <mutex>
#include <utility>

#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::fs {
namespace {

using FileId = std::pair<dev_t, ino_t>;

std::mutex gMutex;
std::map<FileId, std::string> gInputs;        // file id -> the path it was read by
std::map<std::string, std::string> gOutputs;  // canonical path -> the option that writes it

}  // namespace

void protectInputs(const std::vector<std::string>& files) {
  {
    std::lock_guard lock(gMutex);
    for (const std::string& file : files) {
      struct stat info {};
      if (::stat(file.c_str(), &info) == 0) gInputs.emplace(FileId{info.st_dev, info.st_ino}, file);
    }
  }
  // The log was opened before the command knew its inputs.
  const std::string logFile = log::filePath();
  if (logFile.empty() || protectedInputAt(logFile).empty()) return;
  log::setFile("");  // closed first, so that the error itself is not appended to the input
  refuseWritingInput(logFile);
}

std::string protectedInputAt(const std::filesystem::path& target) {
  struct stat info {};
  if (::stat(target.c_str(), &info) != 0) return "";
  std::lock_guard lock(gMutex);
  auto found = gInputs.find({info.st_dev, info.st_ino});
  return found == gInputs.end() ? "" : found->second;
}

void claimOutput(const std::filesystem::path& target, const std::string& option) {
  const std::string canonical = canonicalSpelling(target).string();
  std::lock_guard lock(gMutex);
  const auto [at, added] = gOutputs.emplace(canonical, option);
  if (added || at->second == option) return;
  throw UsageError(target.string() + " would be written twice by this run, as " + at->second +
                       " and as " + option + ": one would be lost; give them different names",
                   {"write", {}, target.string()});
}

void refuseWritingInput(const std::filesystem::path& target) {
  const std::string input = protectedInputAt(target);
  if (input.empty()) return;
  const std::string same = input == target.string() ? "" : " (the same file as " + input + ")";
  throw UsageError(
      target.string() + " is an input file of this run" + same + ": refusing to write over it",
      {"write", {}, target.string()});
}

}  // namespace pluvia::fs
