#include "pipeline/skip_existing.h"

#include <filesystem>

#include <fmt/format.h>

#include "io/clip_writer.h"
#include "io/sequence_pattern.h"
#include "io/written_frame.h"
#include "util/log.h"

namespace pluvia {

FramesToRender framesStillToRender(const std::string& output, const std::vector<int64_t>& frames,
                                   const std::map<std::string, std::string>& metadata) {
  FramesToRender result;
  result.frames = frames;
  if (isMovieExtension(output) && std::filesystem::exists(output)) {
    const std::string reason = reasonToRenderMovieAgain(output, frames.size());
    if (reason.empty()) {
      log::info("--skip-existing: " + output + " exists, nothing to do");
      result.kept = int(frames.size());
      result.frames.clear();
      return result;
    }
    log::warning(fmt::format("--skip-existing: rendering {} again: {}", output, reason));
    result.redone = int(frames.size());
  }
  if (auto pattern = SequencePattern::parse(output)) {
    result.frames.clear();
    for (int64_t f : frames) {
      const std::string path = pattern->pathFor(f);
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
