#include "farm/assemble.h"

#include <filesystem>

#include <fmt/format.h>

#include "io/clip_reader.h"
#include "io/output_lock.h"
#include "io/sequence_pattern.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/interrupt.h"

namespace pluvia::farm {

int assembleMovie(const std::string& frames, int64_t first, int64_t last, const OutputTarget& movie,
                  const WriterOptions& options) {
  const std::optional<SequencePattern> pattern = SequencePattern::parse(frames);
  if (!pattern)
    throw UsageError(fmt::format("{} is not a frame sequence pattern (frames.####.tif)", frames),
                     {"assemble", {}, frames});
  if (!movie.isMovie())
    throw UsageError(fmt::format("-o {}: not a movie (.mp4, .mov)", movie.path),
                     {"assemble", {}, movie.path});
  for (int64_t f = first; f <= last; ++f) {
    const std::string path = pattern->pathFor(f);
    if (!std::filesystem::exists(path))
      throw Error(fmt::format("frame {} of {} is missing ({}): has every render chunk finished?", f,
                              frames, path),
                  {"assemble", f, path});
    if (fs::samePath(path, movie.path))
      throw UsageError(
          fmt::format("-o {} is the frame file {}: refusing to overwrite it", movie.path, path),
          {"assemble", f, path});
  }
  const std::unique_ptr<ClipReader> reader = openClip(frames);
  const ClipInfo& clip = reader->info();
  OutputLock lock(movie, first, last);
  lock.removeStaleTemporaries();
  const std::unique_ptr<ClipWriter> writer =
      openClipWriter(movie, clip.width, clip.height, options);
  for (int64_t f = first; f <= last; ++f) {
    throwIfInterrupted();
    writer->write(f, reader->read(f));
  }
  writer->close();
  return static_cast<int>(last - first + 1);
}

}  // namespace pluvia::farm
