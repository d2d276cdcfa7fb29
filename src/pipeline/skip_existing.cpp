#include "pipeline/skip_existing.h"

#include <filesystem>

#include <fmt/format.h>

#include "io/clip_writer.h"
#include "io/written_frame.h"
#include "util/log.h"

namespace pluvia {

namespace {

// Why a movie and its AOV movies must be rendered again, empty when each is whole.
std::string reasonToRenderMoviesAgain(const OutputTarget& output,
                                      const std::vector<std::string>& aovs, size_t frames,
                                      const std::string& size) {
  for (const std::string& path : framePaths(output, aovs, 0)) {
    if (!std::filesystem::exists(path)) return path + " is missing";
    const std::string reason = reasonToRenderMovieAgain(path, frames, size);
    if (!reason.empty()) return path == output.path ? reason : path + ": " + reason;
  }
  return "";
}

}  // namespace

FramesToRender framesStillToRender(const OutputTarget& output, const std::vector<int64_t>& frames,
                                   const std::map<std::string, std::string>& metadata,
                                   const std::vector<std::string>& aovs, const std::string& size) {
  FramesToRender result;
  result.frames = frames;
  if (output.isMovie() && std::filesystem::exists(output.path)) {
    const std::string reason = reasonToRenderMoviesAgain(output, aovs, frames.size(), size);
    if (reason.empty()) {
      log::info("--skip-existing: " + output.path + " exists, nothing to do");
      result.kept = int(frames.size());
      result.frames.clear();
      return result;
    }
    log::warning(fmt::format("--skip-existing: rendering {} again: {}", output.path, reason));
    result.redone = int(frames.size());
  }
  if (output.isSequence()) {
    result.frames.clear();
    for (int64_t f : frames) {
      const std::string path = output.pathFor(f);
      if (!std::filesystem::exists(path)) {
        result.frames.push_back(f);
        continue;
      }
      const std::string reason = reasonToRenderAgain(path, metadata);
      if (reason.empty()) {
        ++result.kept;
      } else {
        log::warning(fmt::format("--skip-existing: rendering {} again: {}", path, reason));
        ++result.redone;
        result.frames.push_back(f);
      }
    }
    if (result.frames.empty()) log::info("--skip-existing: every frame exists, nothing to do");
  }
  return result;
}

}  // namespace pluvia
