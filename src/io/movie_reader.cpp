#include "io/movie_reader.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "util/error.h"

namespace pluvia {
namespace {

// Up to this many frames ahead, decoding forward is cheaper than a seek (which decodes from
// the previous keyframe anyway).
constexpr int64_t kMaxForwardGrabFrames = 16;
// Containers that estimate their frame count from the duration may be off by a frame or 1 %.
constexpr double kFrameCountSlack = 0.01;

class MovieReader final : public ClipReader {
 public:
  explicit MovieReader(const std::string& path) {
    info_.path = path;
    info_.isMovie = true;
    info_.files = {path};
    open();
    double fps = capture_.get(cv::CAP_PROP_FPS);
    info_.fps = std::isfinite(fps) && fps > 0 ? fps : 24.0;
    int64_t frames = countFrames();
    if (frames == 0) throw Error("movie has no decodable frames: " + path, {"read", {}, path});
    for (int64_t i = 0; i < frames; ++i) info_.frames.push_back(i);
    // Decoding frame 0 gives the size as decoded (rotation applied); kept for the first read.
    pending_ = decodeAt(0);
    info_.width = pending_.cols;
    info_.height = pending_.rows;
    info_.channels = pending_.channels();
  }

  const ClipInfo& info() const override { return info_; }

  Image read(int64_t frame) override {
    std::lock_guard lock(mutex_);
    if (frame < 0 || frame >= static_cast<int64_t>(info_.frames.size())) {
      throw Error(fmt::format("frame {} is not in movie {} (frames 0..{})", frame, info_.path,
                              info_.frames.size() - 1),
                  {"read", frame, info_.path});
    }
    cv::Mat bgr;
    if (!pending_.empty() && frame == 0) {
      bgr = pending_;  // decoded while opening
    } else {
      bgr = decodeAt(frame);
    }
    pending_.release();
    if (bgr.cols != info_.width || bgr.rows != info_.height) {
      throw Error(fmt::format("frame {} of {} is {}x{}, the movie started at {}x{}", frame,
                              info_.path, bgr.cols, bgr.rows, info_.width, info_.height),
                  {"read", frame, info_.path});
    }
    return toImage(bgr);
  }

 private:
  void open() {
    capture_.release();
    if (!capture_.open(info_.path, cv::CAP_FFMPEG)) {
      throw Error(
          "cannot open movie " + info_.path + " (not a movie FFmpeg can decode, or truncated)",
          {"read", {}, info_.path});
    }
    next_ = 0;
  }

  // The container's frame count is a hint (estimated from the duration in some containers,
  // wrong for truncated files): check that its last frame decodes and that none follow, and
  // count by decoding everything only when that check fails. Decoding that stops short of the
  // count by more than an estimate's rounding is a truncated or corrupt file: an error naming
  // the first frame that does not decode, rather than a render of the frames before it.
  int64_t countFrames() {
    const double hint = capture_.get(cv::CAP_PROP_FRAME_COUNT);
    const bool hinted = std::isfinite(hint) && hint >= 1;
    int64_t frames = 0;
    if (hinted && seekTo(static_cast<int64_t>(hint) - 1) && capture_.grab()) {
      frames = static_cast<int64_t>(hint);
    } else {
      open();
    }
    while (capture_.grab()) ++frames;
    next_ = frames;
    if (hinted && static_cast<double>(frames) < hint - std::max(1.0, hint * kFrameCountSlack)) {
      throw Error(fmt::format("movie {} is truncated or corrupt: its container lists {} frames, "
                              "but frame {} and those after it do not decode",
                              info_.path, static_cast<int64_t>(hint), frames),
                  {"read", frames, info_.path});
    }
    return frames;
  }

  // Positions the capture so that the next grab() returns `frame`; false when it cannot.
  bool seekTo(int64_t frame) {
    bool landed = capture_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(frame)) &&
                  std::llround(capture_.get(cv::CAP_PROP_POS_FRAMES)) == frame;
    next_ = landed ? frame : -1;
    return landed;
  }

  cv::Mat decodeAt(int64_t frame) {
    if (frame != next_) {
      if (frame > next_ && frame - next_ <= kMaxForwardGrabFrames) {
        skipTo(frame);
      } else if (!seekTo(frame)) {
        // FFmpeg could not land exactly on the frame: decode from the start instead.
        open();
        skipTo(frame);
      }
    }
    cv::Mat bgr;
    if (!capture_.grab() || !capture_.retrieve(bgr) || bgr.empty()) {
      next_ = -1;  // the decoder's position is unknown now: seek next time
      throw Error(fmt::format("cannot decode frame {} of movie {} (truncated or corrupt file?)",
                              frame, info_.path),
                  {"read", frame, info_.path});
    }
    next_ = frame + 1;
    return bgr;
  }

  void skipTo(int64_t frame) {
    while (next_ < frame) {
      if (!capture_.grab()) {
        const int64_t failed = next_;
        next_ = -1;
        throw Error(fmt::format("cannot decode frame {} of movie {}: decoding stops at frame {} "
                                "(truncated or corrupt file?)",
                                frame, info_.path, failed),
                    {"read", frame, info_.path});
      }
      ++next_;
    }
  }

  Image toImage(const cv::Mat& decoded) const {
    if (decoded.depth() != CV_8U || (decoded.channels() != 3 && decoded.channels() != 1)) {
      throw Error("unexpected pixel layout decoded from movie " + info_.path,
                  {"read", {}, info_.path});
    }
    Image image(decoded.cols, decoded.rows);
    const int channels = decoded.channels();
    constexpr float kScale = 1.0f / 255.0f;
    for (int y = 0; y < decoded.rows; ++y) {
      const uint8_t* src = decoded.ptr<uint8_t>(y);
      float* dst = image.pixel(0, y);
      for (int x = 0; x < decoded.cols; ++x, src += channels, dst += 4) {
        // OpenCV hands out BGR.
        dst[0] = src[channels == 3 ? 2 : 0] * kScale;
        dst[1] = src[channels == 3 ? 1 : 0] * kScale;
        dst[2] = src[0] * kScale;
      }
    }
    return image;
  }

  ClipInfo info_;
  cv::VideoCapture capture_;
  int64_t next_ = 0;  // frame the next grab() returns; -1 when unknown
  cv::Mat pending_;   // frame 0, decoded while opening to learn the size
  std::mutex mutex_;
};

}  // namespace

std::unique_ptr<ClipReader> openMovie(const std::string& path) {
  return std::make_unique<MovieReader>(path);
}

}  // namespace pluvia
