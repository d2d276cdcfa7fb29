#include "pipeline/numbered_clip_reader.h"

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {
namespace {

class NumberedClipReader final : public ClipReader {
 public:
  NumberedClipReader(std::unique_ptr<ClipReader> movie, int64_t firstFrame)
      : movie_(std::move(movie)), info_(movie_->info()), offset_(firstFrame) {
    for (int64_t& frame : info_.frames) frame += offset_;
  }
  const ClipInfo& info() const override { return info_; }
  Image read(int64_t frame) override {
    return numbered(frame, [&] { return movie_->read(frame - offset_); });
  }
  int codeBits() const override { return movie_->codeBits(); }
  Image readCodesThrough(int64_t frame, const CodeValues& table) override {
    return numbered(frame, [&] { return movie_->readCodesThrough(frame - offset_, table); });
  }
  void prefetch(const std::vector<int64_t>& frames) override {
    std::vector<int64_t> positions;
    for (int64_t frame : frames) positions.push_back(frame - offset_);
    movie_->prefetch(positions);
  }

 private:
  // The movie's reader names the frame by its position; the number asked for is added.
  template <class Read>
  Image numbered(int64_t frame, const Read& read) {
    try {
      return read();
    } catch (const Error& e) {
      throw Error(fmt::format("frame {} (the movie's frame {} from 0): {}", frame, frame - offset_,
                              e.what()),
                  {"read", frame, info_.path});
    }
  }

  std::unique_ptr<ClipReader> movie_;
  ClipInfo info_;
  int64_t offset_;
};

}  // namespace

std::unique_ptr<ClipReader> openNumberedClip(const std::string& input,
                                             std::optional<int64_t> movieFirstFrame) {
  std::unique_ptr<ClipReader> reader = openClip(input);
  if (!movieFirstFrame) return reader;
  if (!reader->info().isMovie)
    throw UsageError(
        fmt::format("--start-frame {}: {} is not a movie; a sequence or image keeps "
                    "its own frame numbers",
                    *movieFirstFrame, input));
  if (*movieFirstFrame == 0) return reader;
  return std::make_unique<NumberedClipReader>(std::move(reader), *movieFirstFrame);
}

}  // namespace pluvia
