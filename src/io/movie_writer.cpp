#include "io/movie_writer.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>

#include "util/error.h"
#include "util/fs.h"
#include "util/subprocess.h"

namespace pluvia {
namespace stdfs = std::filesystem;
namespace {

constexpr int kLogLinesInErrors = 8;

// "24", or "24000/1001" for the NTSC rates (23.976, 29.97, 59.94), which are not decimals.
std::string frameRateArgument(double fps) {
  const double ntscBase = std::round(fps * 1.001);
  if (std::abs(fps - ntscBase / 1.001) < 1e-3 && std::abs(fps - ntscBase) > 1e-3) {
    return fmt::format("{}/1001", static_cast<int64_t>(ntscBase) * 1000);
  }
  return fmt::format("{}", fps);
}

std::string metadataComment(const std::map<std::string, std::string>& metadata) {
  std::string comment;
  for (const auto& [key, value] : metadata)
    comment += (comment.empty() ? "" : "; ") + key + "=" + value;
  return comment;
}

std::string lastLines(const stdfs::path& path, int count) {
  std::ifstream in(path);
  std::deque<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
    if (static_cast<int>(lines.size()) > count) lines.pop_front();
  }
  std::string text;
  for (const std::string& line : lines) text += "\n  " + line;
  return text.empty() ? " (ffmpeg printed nothing)" : text;
}

class MovieWriter final : public ClipWriter {
 public:
  MovieWriter(const std::string& path, int width, int height, const WriterOptions& options)
      : path_(path),
        width_(width),
        height_(height),
        encodedWidth_(width + width % 2),
        encodedHeight_(height + height % 2),
        tmp_(fs::temporaryPathFor(path)),
        log_(tmp_.string() + ".log") {
    if (!(options.fps > 0) || !std::isfinite(options.fps)) {
      throw Error(
          fmt::format("cannot write the movie {} at {} frames per second", path, options.fps),
          {"write", {}, path});
    }
    if (!programAvailable("ffmpeg")) {
      throw Error("ffmpeg is needed to write the movie " + path + " but is not on PATH",
                  {"write", {}, path});
    }
    std::vector<std::string> argv{"ffmpeg",   "-y",
                                  "-v",       "error",
                                  "-f",       "rawvideo",
                                  "-pix_fmt", "rgb48le",
                                  "-s",       fmt::format("{}x{}", encodedWidth_, encodedHeight_),
                                  "-r",       frameRateArgument(options.fps),
                                  "-i",       "-"};
    argv.insert(argv.end(),
                {"-c:v", "libx264", "-preset", "medium", "-crf", "16", "-pix_fmt", "yuv420p"});
    if (!options.metadata.empty())
      argv.insert(argv.end(), {"-metadata", "comment=" + metadataComment(options.metadata)});
    // "file:" keeps a name that starts with "-" from reading as an option, and one such as
    // "pipe:1.mp4" from reading as another protocol.
    argv.push_back("file:" + tmp_.string());
    encoder_.emplace(argv, log_.string());
  }

  ~MovieWriter() override {
    if (encoder_) encoder_.reset();  // stops ffmpeg; what it wrote is incomplete
    removeTemporaries();
  }

  void write(int64_t frame, const Image& image) override {
    std::lock_guard lock(mutex_);
    const ErrorContext context{"write", frame, path_};
    if (!encoder_) throw Error("movie " + path_ + " is already closed or failed", context);
    if (lastFrame_ && frame <= *lastFrame_) {
      throw Error(fmt::format("movie frames must come in order: frame {} after frame {} ({})",
                              frame, *lastFrame_, path_),
                  context);
    }
    if (image.width != width_ || image.height != height_) {
      throw Error(fmt::format("frame {} is {}x{} but the movie {} is {}x{}", frame, image.width,
                              image.height, path_, width_, height_),
                  context);
    }
    pack(image);
    try {
      encoder_->write(packed_.data(), packed_.size() * sizeof(uint16_t));
    } catch (const Error&) {
      int code = encoder_->close();
      encoder_.reset();
      throw Error(fmt::format("ffmpeg stopped (exit code {}) while writing frame {} of {}:{}", code,
                              frame, path_, lastLines(log_, kLogLinesInErrors)),
                  context);
    }
    lastFrame_ = frame;
  }

  void close() override {
    std::lock_guard lock(mutex_);
    if (!encoder_) return;
    const ErrorContext context{"write", lastFrame_, path_};
    if (!lastFrame_) {
      encoder_.reset();
      throw Error("no frames were written to the movie " + path_, context);
    }
    const int code = encoder_->close();
    encoder_.reset();
    if (code != 0) {
      throw Error(fmt::format("ffmpeg failed (exit code {}) encoding {}:{}", code, path_,
                              lastLines(log_, kLogLinesInErrors)),
                  context);
    }
    fs::commitTemporary(tmp_, path_);
    removeTemporaries();
  }

  bool isMovie() const override { return true; }
  std::string pathFor(int64_t) const override { return path_; }

 private:
  // To rgb48le (on a little-endian host), clamped and rounded. libx264 cannot encode 4:2:0 at
  // odd sizes, so odd frames get their last column/row repeated to reach an even size (rather
  // than ffmpeg's pad filter: black there would bleed into the edge through the shared chroma).
  // Rows in parallel (OpenCV's TBB backend): a 1080p frame is 6 million values.
  void pack(const Image& image) {
    packed_.resize(static_cast<size_t>(encodedWidth_) * encodedHeight_ * 3);
    cv::parallel_for_(cv::Range(0, encodedHeight_), [&](const cv::Range& rows) {
      for (int y = rows.start; y < rows.end; ++y) {
        const float* row = image.pixel(0, std::min(y, height_ - 1));
        uint16_t* dst = packed_.data() + static_cast<size_t>(y) * encodedWidth_ * 3;
        for (int x = 0; x < encodedWidth_; ++x) {
          const float* src = row + std::min(x, width_ - 1) * 4;
          for (int c = 0; c < 3; ++c) {
            const float clamped =
                src[c] > 0.0f ? (src[c] < 1.0f ? src[c] : 1.0f) : 0.0f;  // NaN -> 0
            *dst++ = static_cast<uint16_t>(clamped * 65535.0f + 0.5f);
          }
        }
      }
    });
  }

  void removeTemporaries() {
    std::error_code ec;
    stdfs::remove(tmp_, ec);
    stdfs::remove(log_, ec);
  }

  std::string path_;
  int width_;
  int height_;
  int encodedWidth_;  // even: what libx264 gets
  int encodedHeight_;
  stdfs::path tmp_;  // encoded here, renamed to path_ by close()
  stdfs::path log_;  // ffmpeg's output, quoted in errors
  std::optional<PipeProcess> encoder_;
  std::optional<int64_t> lastFrame_;
  std::vector<uint16_t> packed_;
  std::mutex mutex_;
};

}  // namespace

const std::vector<std::string>& movieOutputExtensions() {
  static const std::vector<std::string> kExtensions{"mp4", "mov", "mkv", "m4v"};
  return kExtensions;
}

std::unique_ptr<ClipWriter> openMovieWriter(const std::string& path, int width, int height,
                                            const WriterOptions& options) {
  return std::make_unique<MovieWriter>(path, width, height, options);
}

}  // namespace pluvia
