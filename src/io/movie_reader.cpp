#include "io/movie_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>

#include "io/frame_size.h"
#include "io/movie_probe.h"
#include "util/error.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/parallel.h"
#include "util/read_pipe.h"
#include "util/thread_limit.h"

namespace pluvia {
namespace {

// Up to this many frames ahead, decoding forward is cheaper than a seek (which decodes from
// the previous keyframe anyway).
constexpr int64_t kMaxForwardSkipFrames = 16;
// Containers that estimate their frame count from the duration may be off by a frame or 1 %.
constexpr double kFrameCountSlack = 0.01;

// Whether `frames` falls short of the container's `listed` count by more than that: a truncated
// or corrupt file (or a count that is not this file's).
bool shortOfListed(int64_t frames, int64_t listed) {
  return listed >= 1 &&
         double(frames) < double(listed) - std::max(1.0, double(listed) * kFrameCountSlack);
}

// Frame counts this process has already checked, by movieFileIdentity. Commands open their
// input more than once (the bench plans, then renders; the derain stage, preview and derain open
// it again), and a count decodes up to a keyframe interval: 0.29 s of CPU for the 24-frame 1080p
// bench clip, whose one keyframe makes that the whole clip.
class CheckedFrameCounts {
 public:
  std::optional<int64_t> find(const std::string& path) {
    const std::optional<std::string> key = movieFileIdentity(path);
    std::lock_guard lock(mutex_);
    if (!key) return std::nullopt;
    auto found = counts_.find(*key);
    if (found == counts_.end()) return std::nullopt;
    return found->second;
  }
  void remember(const std::string& path, int64_t frames) {
    const std::optional<std::string> key = movieFileIdentity(path);
    std::lock_guard lock(mutex_);
    if (key) counts_[*key] = frames;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, int64_t> counts_;
};

CheckedFrameCounts& checkedFrameCounts() {
  static CheckedFrameCounts counts;
  return counts;
}

// A Y'CbCr movie's matrix and range. ffmpeg's swscale to RGB, which the reader used before,
// clipped super-whites and sub-blacks (8-bit Y' 1-15 and 236-254), and read a 10-bit ProRes Y' of
// 513 as 0.51058 where BT.709 says 0.51256 (0.39 % dark). Its yuv444p (8-bit) and yuv444p16le
// outputs are the codes themselves (a 10-bit code << 6), and the conversion to R'G'B' is done
// here, keeping values beyond [0, 1].
struct Ycbcr {
  float kr = 0.2126f, kb = 0.0722f;
  bool fullRange = false;
};

// An untagged movie is taken as players take it: BT.601 up to standard definition (576 lines),
// BT.709 above. swscale takes every untagged movie as BT.601, which for an HD phone clip is
// wrong.
constexpr int kLargestStandardDefinitionLines = 576;

Ycbcr ycbcrOf(const MovieProbe& probe) {
  Ycbcr ycbcr;
  const auto tag = [&](const char* name) {
    const auto found = probe.metadata.find(name);
    return found == probe.metadata.end() ? std::string() : found->second;
  };
  const std::string matrix = tag("ffmpeg:color_space");
  const bool bt601 = matrix == "smpte170m" || matrix == "bt470bg";
  const bool tagged = bt601 || matrix == "bt709" || matrix == "bt2020nc" || matrix == "bt2020c" ||
                      matrix == "smpte240m";
  if (matrix == "bt2020nc" || matrix == "bt2020c") {
    ycbcr.kr = 0.2627f, ycbcr.kb = 0.0593f;
  } else if (matrix == "smpte240m") {
    ycbcr.kr = 0.212f, ycbcr.kb = 0.087f;
  } else if (bt601 || (!tagged && probe.height <= kLargestStandardDefinitionLines)) {
    ycbcr.kr = 0.299f, ycbcr.kb = 0.114f;
  }  // else BT.709: tagged so, or untagged HD
  ycbcr.fullRange = tag("ffmpeg:color_range") == "pc" || probe.pixelFormat.starts_with("yuvj");
  return ycbcr;
}

// Planar Y', Cb, Cr of `sampleBytes` (1, or 2 little-endian) to R'G'B' by the matrix's inverse:
// video range E'y = (Y' / s - 16) / 219, E'c = (C / s - 128) / 224 with s = 1 or 256; full
// range over 2^n - 1 about 2^(n-1). Values beyond [0, 1] are kept. Rows in parallel.
Image ycbcrToImage(const uint8_t* planes, int width, int height, int sampleBytes,
                   const Ycbcr& ycbcr) {
  Image image(width, height);
  const size_t plane = static_cast<size_t>(width) * height;
  const float largest = sampleBytes == 2 ? 65535.0f : 255.0f;
  const float step = sampleBytes == 2 ? 256.0f : 1.0f;  // one 8-bit code in the samples
  const float lumaScale = ycbcr.fullRange ? 1.0f / largest : 1.0f / (step * 219.0f);
  const float lumaOffset = ycbcr.fullRange ? 0.0f : 16.0f / 219.0f;
  const float chromaScale = ycbcr.fullRange ? 1.0f / largest : 1.0f / (step * 224.0f);
  const float chromaOffset = ycbcr.fullRange ? 128.0f * step / largest : 128.0f / 224.0f;
  const float kg = 1.0f - ycbcr.kr - ycbcr.kb;
  forEachBlock(size_t(height), 1, [&](size_t firstRow, size_t endRow) {
    for (size_t y = firstRow; y < endRow; ++y) {
      float* dst = image.pixel(0, int(y));
      for (size_t x = 0; x < size_t(width); ++x, dst += 4) {
        const size_t i = y * size_t(width) + x;
        const auto sample = [&](size_t p) {
          const uint8_t* at = planes + size_t(sampleBytes) * (p * plane + i);
          return static_cast<float>(sampleBytes == 2 ? at[0] | (at[1] << 8) : at[0]);
        };
        const float ey = sample(0) * lumaScale - lumaOffset;
        const float cb = sample(1) * chromaScale - chromaOffset;
        const float cr = sample(2) * chromaScale - chromaOffset;
        const float r = ey + 2.0f * (1.0f - ycbcr.kr) * cr;
        const float b = ey + 2.0f * (1.0f - ycbcr.kb) * cb;
        dst[0] = r;
        dst[1] = (ey - ycbcr.kr * r - ycbcr.kb * b) / kg;
        dst[2] = b;
      }
    }
  });
  return image;
}

// Frames come from an ffmpeg process writing raw samples to a pipe: a Y'CbCr movie's own codes
// (yuv444p at 8 bits, yuv444p16le deeper: 10-bit DNxHR, 12-bit ProRes 4444), converted here;
// an RGB one's as rgb24 or rgb48le, so that every bit the file holds reaches the float frame. A
// variable-rate movie is conformed to its nominal rate by ffmpeg's fps filter: a frame held on
// screen repeats, as an editor shows it.
class MovieReader final : public ClipReader {
 public:
  explicit MovieReader(const std::string& path) : probe_(probeMovie(path)) {
    info_.path = path;
    info_.isMovie = true;
    info_.files = {path};
    info_.fps = probe_.fps;
    info_.width = probe_.width;
    info_.height = probe_.height;
    info_.channels = 3;
    info_.bitsPerSample = probe_.bitsPerSample;
    info_.metadata = probe_.metadata;
    sampleBytes_ = probe_.bitsPerSample > 8 ? 2 : 1;
    if (probe_.pixelFormat.starts_with("yuv")) ycbcr_ = ycbcrOf(probe_);
    if (info_.width <= 0 || info_.height <= 0)
      throw Error("movie has no picture (zero size): " + path, {"read", {}, path});
    checkFrameSize(info_.width, info_.height, path, {"read", {}, path});
    if (probe_.variableRate) {
      log::warning(fmt::format(
          "movie {} has a variable frame rate ({} coded frames): conformed to its nominal {} fps "
          "as {} frames, a held frame repeating",
          path, probe_.packets, fmt::format("{:g}", probe_.fps), probe_.frames));
    }
    std::optional<int64_t> frames = checkedFrameCounts().find(path);
    // A count remembered from elsewhere (a cache) that the check would have refused as
    // truncated is not this file's: checked again.
    if (frames && shortOfListed(*frames, probe_.frames)) frames.reset();
    if (!frames) {
      frames = countFrames();
      checkedFrameCounts().remember(path, *frames);
    }
    if (*frames == 0) throw Error("movie has no decodable frames: " + path, {"read", {}, path});
    for (int64_t i = 0; i < *frames; ++i) info_.frames.push_back(i);
  }

  const ClipInfo& info() const override { return info_; }

  Image read(int64_t frame) override { return readWith(frame, nullptr); }

  // The frame, its codes normalised or (`table`) looked up.
  Image readWith(int64_t frame, const CodeValues* table) {
    throwIfInterrupted();  // an analysis stops at its next frame (util/interrupt.h)
    std::lock_guard lock(mutex_);
    if (frame < 0 || frame >= static_cast<int64_t>(info_.frames.size())) {
      throw Error(fmt::format("frame {} is not in movie {} (frames 0..{})", frame, info_.path,
                              info_.frames.size() - 1),
                  {"read", frame, info_.path});
    }
    if (auto held = prefetched_.find(frame); held != prefetched_.end()) {
      raw_.swap(held->second);
      prefetched_.erase(held);
      return toImage(table);
    }
    if (!decoder_ || frame < next_ || frame - next_ > kMaxForwardSkipFrames) startAt(frame);
    if (!decoder_->skip((frame - next_) * frameBytes()) ||
        !decoder_->readExactly(raw_.data(), raw_.size())) {
      const std::string why = decoder_->errorText();
      decoder_.reset();
      throw Error(fmt::format("cannot decode frame {} of movie {} (truncated or corrupt file?){}",
                              frame, info_.path, why),
                  {"read", frame, info_.path});
    }
    next_ = frame + 1;
    return toImage(table);
  }

  // Y'CbCr is converted here, to values beyond [0, 1] where the file holds them: no code table
  // can stand for it.
  int codeBits() const override { return ycbcr_ ? 0 : sampleBytes_ == 2 ? 16 : 8; }

  Image readCodesThrough(int64_t frame, const CodeValues& table) override {
    return readWith(frame, &table);
  }

  // One decoder of its own whose select filter passes only the frames asked for: those between
  // are decoded (as a seek would) but never converted to RGB or sent down the pipe. A conformed
  // variable-rate movie, whose frame numbers exist only after its fps filter, reads as it does.
  void prefetch(const std::vector<int64_t>& frames) override {
    std::lock_guard lock(mutex_);
    prefetched_.clear();
    if (probe_.variableRate || frames.size() < 2 || !std::is_sorted(frames.begin(), frames.end()) ||
        std::adjacent_find(frames.begin(), frames.end()) != frames.end() || frames.front() < 0 ||
        frames.back() >= static_cast<int64_t>(info_.frames.size()))
      return;
    std::string select;
    for (int64_t frame : frames)
      select += fmt::format("{}eq(n,{})", select.empty() ? "" : "+", frame);
    std::vector<std::string> argv = decoderArguments();
    argv.insert(argv.end(), {"-i", "file:" + info_.path, "-map", "0:v:0", "-vf",
                             "select='" + select + "'", "-fps_mode", "passthrough"});
    appendRawOutput(argv);
    ReadPipe pass(argv);
    for (int64_t frame : frames) {
      std::vector<uint8_t> raw(frameBytes());
      if (!pass.readExactly(raw.data(), raw.size())) {
        prefetched_.clear();  // read() decodes them again, and names what fails
        return;
      }
      prefetched_.emplace(frame, std::move(raw));
    }
  }

 private:
  size_t frameBytes() const {
    return static_cast<size_t>(info_.width) * info_.height * 3 * sampleBytes_;
  }

  // Starts ffmpeg so that the next frame it writes is `frame`. A constant-rate movie seeks
  // (ffmpeg decodes from the keyframe before and drops what comes before the time asked for,
  // half a frame early so rounding cannot drop the frame itself); a conformed variable-rate one
  // decodes from the start, since its frame numbers exist only after the fps filter.
  std::vector<std::string> decoderArguments() const {
    return {"ffmpeg", "-v", "error", "-nostdin", "-threads", std::to_string(threadLimit())};
  }

  void appendRawOutput(std::vector<std::string>& argv) const {
    const char* format = ycbcr_              ? (sampleBytes_ == 2 ? "yuv444p16le" : "yuv444p")
                         : sampleBytes_ == 2 ? "rgb48le"
                                             : "rgb24";
    argv.insert(argv.end(), {"-sws_flags", "accurate_rnd+full_chroma_int", "-f", "rawvideo",
                             "-pix_fmt", format, "pipe:1"});
  }

  void startAt(int64_t frame) {
    decoder_.reset();
    std::vector<std::string> argv = decoderArguments();
    int64_t first = 0;
    if (frame > 0 && !probe_.variableRate) {
      argv.insert(argv.end(), {"-ss", fmt::format("{:.6f}", (frame - 0.5) / probe_.fps)});
      first = frame;
    }
    argv.insert(argv.end(), {"-i", "file:" + info_.path, "-map", "0:v:0"});
    if (probe_.variableRate) {
      argv.insert(argv.end(), {"-vf", "fps=" + probe_.rate, "-fps_mode", "cfr"});
    } else {
      argv.insert(argv.end(), {"-fps_mode", "passthrough"});
    }
    appendRawOutput(argv);
    std::string command;
    for (const std::string& arg : argv) command += (command.empty() ? "" : " ") + arg;
    log::debug("decoding: " + command);
    decoder_.emplace(argv);
    next_ = first;
    raw_.resize(frameBytes());
  }

  // The count from the probe is checked by decoding from the last frame it promises: that frame
  // must decode, and those after it are counted too. When it does not decode, every frame is
  // decoded and counted; a movie that stops short of its count by more than an estimate's
  // rounding is truncated or corrupt: an error naming the first frame that does not decode,
  // rather than a render of the frames before it.
  int64_t countFrames() {
    const int64_t promised = probe_.frames;
    int64_t frames = 0;
    if (promised >= 1 && !probe_.variableRate) {
      startAt(promised - 1);
      frames = promised - 1;
      while (decoder_->skip(frameBytes())) ++frames;
    }
    if (frames < promised || promised < 1 || probe_.variableRate) {
      startAt(0);
      frames = 0;
      while (decoder_->skip(frameBytes())) ++frames;
    }
    decoder_.reset();
    if (shortOfListed(frames, promised)) {
      throw Error(fmt::format("movie {} is truncated or corrupt: its container lists {} frames, "
                              "but frame {} and those after it do not decode",
                              info_.path, promised, frames),
                  {"read", frames, info_.path});
    }
    return frames;
  }

  // Samples to floats in [0, 1], rows in parallel (OpenCV's TBB backend): a 1080p frame is 6
  // million samples, and this runs on the reader's thread beside the render.
  Image toImage(const CodeValues* table) const {
    if (ycbcr_) return ycbcrToImage(raw_.data(), info_.width, info_.height, sampleBytes_, *ycbcr_);
    Image image(info_.width, info_.height);
    const size_t rowSamples = static_cast<size_t>(info_.width) * 3;
    forEachBlock(size_t(info_.height), 1, [&](size_t firstRow, size_t endRow) {
      for (int y = int(firstRow); y < int(endRow); ++y) {
        float* dst = image.pixel(0, y);
        const uint8_t* src = raw_.data() + static_cast<size_t>(y) * rowSamples * sampleBytes_;
        if (table) {
          const float* r = (*table)[0].data();
          const float* g = (*table)[1].data();
          const float* b = (*table)[2].data();
          if (sampleBytes_ == 1) {
            for (size_t i = 0; i < rowSamples; i += 3, dst += 4)
              dst[0] = r[src[i]], dst[1] = g[src[i + 1]], dst[2] = b[src[i + 2]];
          } else {
            auto code = [&](size_t i) { return size_t(src[2 * i] | (src[2 * i + 1] << 8)); };
            for (size_t i = 0; i < rowSamples; i += 3, dst += 4)
              dst[0] = r[code(i)], dst[1] = g[code(i + 1)], dst[2] = b[code(i + 2)];
          }
        } else if (sampleBytes_ == 1) {
          constexpr float kScale = codeScale(8);
          for (size_t i = 0; i < rowSamples; i += 3, dst += 4) {
            dst[0] = src[i] * kScale;
            dst[1] = src[i + 1] * kScale;
            dst[2] = src[i + 2] * kScale;
          }
        } else {
          constexpr float kScale = codeScale(16);
          // Little-endian 16-bit samples, assembled byte by byte: no alignment or host-order trap.
          auto sample = [&](size_t i) {
            return static_cast<float>(src[2 * i] | (src[2 * i + 1] << 8));
          };
          for (size_t i = 0; i < rowSamples; i += 3, dst += 4) {
            dst[0] = sample(i) * kScale;
            dst[1] = sample(i + 1) * kScale;
            dst[2] = sample(i + 2) * kScale;
          }
        }
      }
    });
    return image;
  }

  MovieProbe probe_;
  ClipInfo info_;
  int sampleBytes_ = 1;
  std::optional<Ycbcr> ycbcr_;  // a Y'CbCr movie, decoded as yuv444p or yuv444p16le
  std::optional<ReadPipe> decoder_;
  int64_t next_ = 0;  // the frame the decoder writes next
  std::vector<uint8_t> raw_;
  std::map<int64_t, std::vector<uint8_t>> prefetched_;  // frames prefetch() decoded, until read
  std::mutex mutex_;
};

}  // namespace

std::optional<std::string> movieFileIdentity(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return std::nullopt;
  const auto written = std::filesystem::last_write_time(path, ec);
  if (ec) return std::nullopt;
  return fmt::format("{}\n{}\n{}", std::filesystem::absolute(path, ec).string(), size,
                     written.time_since_epoch().count());
}

std::optional<int64_t> checkedMovieFrames(const std::string& path) {
  return checkedFrameCounts().find(path);
}

void rememberCheckedMovieFrames(const std::string& path, int64_t frames) {
  checkedFrameCounts().remember(path, frames);
}

std::unique_ptr<ClipReader> openMovie(const std::string& path) {
  return std::make_unique<MovieReader>(path);
}

}  // namespace pluvia
