#include "io/clip_reader.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <system_error>

#include <fmt/format.h>

#include "io/image_file_reader.h"
#include "io/movie_reader.h"
#include "io/sequence_pattern.h"
#include "util/error.h"
#include "util/input_guard.h"
#include "util/interrupt.h"
#include "util/log.h"

namespace pluvia {
namespace stdfs = std::filesystem;
namespace {

// Frames read one file each (a sequence, or a still as a one-frame sequence numbered 0).
class ImageFilesReader final : public ClipReader {
 public:
  ImageFilesReader(ClipInfo info, std::function<std::string(int64_t)> pathFor)
      : info_(std::move(info)), pathFor_(std::move(pathFor)) {}

  const ClipInfo& info() const override { return info_; }

  Image read(int64_t frame) override {
    throwIfInterrupted();  // an analysis stops at its next frame (util/interrupt.h)
    const std::string path = pathFor_(frame);
    if (!std::binary_search(info_.frames.begin(), info_.frames.end(), frame)) {
      const bool inGap = frame > info_.frames.front() && frame < info_.frames.back();
      throw Error(fmt::format("frame {} {} {}: expected file {}", frame,
                              inGap ? "is missing from" : "is not in", info_.path, path),
                  {"read", frame, path});
    }
    fs::protectInputs({path});  // a frame read here is never written by this run
    Image image = readImageFile(path, frame);
    if (image.width != info_.width || image.height != info_.height) {
      throw Error(fmt::format("frame {} is {}x{} but the clip is {}x{} (from its first frame): {}",
                              frame, image.width, image.height, info_.width, info_.height, path),
                  {"read", frame, path});
    }
    return image;
  }

 private:
  ClipInfo info_;
  std::function<std::string(int64_t)> pathFor_;
};

void describeFirstFrame(ClipInfo& info, const std::string& path, int64_t frame) {
  ImageFileHeader header = readImageHeader(path, frame);
  info.width = header.width;
  info.height = header.height;
  info.channels = header.channels;
  info.isFloat = header.isFloat;
  info.bitsPerSample = header.bitsPerSample;
  info.displayWindow = header.displayWindow;
  info.dataWindow = header.dataWindow;
  info.metadata = header.metadata;
}

// Gaps are not an error here (a render may cover only the frames that exist), but reading a
// missing frame is; say early that there are some.
void warnAboutGaps(const ClipInfo& info) {
  const int64_t span = info.frames.back() - info.frames.front() + 1;
  const int64_t missing = span - static_cast<int64_t>(info.frames.size());
  if (missing == 0) return;
  auto gap = std::adjacent_find(info.frames.begin(), info.frames.end(),
                                [](int64_t a, int64_t b) { return b != a + 1; });
  log::warning(
      fmt::format("sequence {} has {} missing frame(s) between {} and {}; the first is frame {}",
                  info.path, missing, info.frames.front(), info.frames.back(), *gap + 1));
}

std::unique_ptr<ClipReader> openSequence(const std::string& input, const SequencePattern& pattern) {
  ClipInfo info;
  info.path = input;
  info.frames = pattern.existingFrames();
  if (info.frames.empty()) {
    throw Error("input not found: no files match the sequence pattern " + input,
                {"read", {}, input});
  }
  for (int64_t frame : info.frames) info.files.push_back(pattern.pathFor(frame));
  describeFirstFrame(info, info.files.front(), info.frames.front());
  warnAboutGaps(info);
  return std::make_unique<ImageFilesReader>(
      std::move(info), [pattern](int64_t frame) { return pattern.pathFor(frame); });
}

std::unique_ptr<ClipReader> openStill(const std::string& input) {
  ClipInfo info;
  info.path = input;
  info.frames = {0};
  info.files = {input};
  describeFirstFrame(info, input, 0);
  return std::make_unique<ImageFilesReader>(std::move(info), [input](int64_t) { return input; });
}

}  // namespace

std::unique_ptr<ClipReader> openClip(const std::string& input) {
  std::error_code ec;
  stdfs::file_status status = stdfs::status(input, ec);
  if (stdfs::is_directory(status)) {
    throw Error("input is a folder, not a clip: " + input +
                    " (give a movie, an image, or a sequence pattern such as " +
                    (stdfs::path(input) / "frame.####.exr").string() + ")",
                {"read", {}, input});
  }
  if (stdfs::exists(status) && !stdfs::is_regular_file(status)) {
    // A device or a pipe (/dev/zero) never ends: decoders would read it forever.
    throw Error("input is not a regular file (a device or a pipe): " + input, {"read", {}, input});
  }
  // A file that exists is taken literally, even if its name happens to contain '#' or '%d'.
  if (stdfs::exists(status)) return isMovieExtension(input) ? openMovie(input) : openStill(input);
  if (std::optional<SequencePattern> pattern = SequencePattern::parse(input))
    return openSequence(input, *pattern);
  // Not there, or not reachable: the system says which (a name too long, a folder not readable).
  throw Error(ec && ec != std::errc::no_such_file_or_directory
                  ? "cannot read the input " + input + ": " + ec.message()
                  : "input not found: " + input,
              {"read", {}, input});
}

}  // namespace pluvia
