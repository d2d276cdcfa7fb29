#include "io/movie_writer.h"

#include <sys/statvfs.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/movie_index.h"
#include "io/sequence_pattern.h"
#include "io/ycbcr_frame.h"
#include "util/log.h"

#include "util/error.h"
#include "util/fs.h"
#include "util/interrupt.h"
#include "util/subprocess.h"
#include "util/thread_limit.h"

namespace pluvia {
namespace stdfs = std::filesystem;
namespace {

// ffmpeg's log beside the movie's temporary: the temporary's name plus this.
constexpr const char* kLogSuffix = ".log";

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

// Less than this left on the output's file system reads as a full disk.
constexpr unsigned long long kFullDiskBytes = 1 << 20;

std::string lastLines(const stdfs::path& path, int count) {
  std::ifstream in(path);
  std::deque<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
    if (static_cast<int>(lines.size()) > count) lines.pop_front();
  }
  std::string text;
  for (const std::string& line : lines) text += "\n  " + line;
  if (!text.empty()) return text;
  // ffmpeg's log sits beside the movie: on a full disk it is empty too, so say what is left.
  struct statvfs disk {};
  if (::statvfs(path.parent_path().empty() ? "." : path.parent_path().c_str(), &disk) == 0 &&
      disk.f_bavail * disk.f_frsize < kFullDiskBytes)
    return fmt::format(
        " (the disk is full: the output's file system has {} bytes free, and ffmpeg's log "
        "beside it is empty)",
        disk.f_bavail * disk.f_frsize);
  return " (ffmpeg printed nothing)";
}

struct MovieCodec {
  std::string name;
  std::vector<std::string> arguments;  // -c:v ...
  std::vector<std::string> containers;
  // The Y'CbCr pluvia makes for it (io/ycbcr_frame.h) and ffmpeg's name for that layout.
  YcbcrLayout layout;
  std::string pixelFormat;
  // The layout with an alpha plane, for codecs that carry one (ProRes 4444); empty for others.
  std::string alphaPixelFormat;
  int minWidth = 1, minHeight = 1;  // DNxHR's smallest frame is 256x120
};

// The codecs, with what each needs: libx264 at 4:2:0 (every player), ProRes 4444 (12-bit
// 4:4:4) and 422 HQ (10-bit 4:2:2) through prores_ks, DNxHR HQ (8-bit 4:2:2), HQX (10-bit
// 4:2:2) and 444 (10-bit 4:4:4) through dnxhd.
std::vector<MovieCodec> makeCodecs() {
  const std::vector<std::string> movContainers{"mov", "mkv"};
  // DNxHR also goes in MXF (OP1a), the Avid and broadcast container.
  const std::vector<std::string> dnxhrContainers{"mov", "mkv", "mxf"};
  auto prores = [&](const char* name, const char* profile, YcbcrLayout layout,
                    const char* pixelFormat, const char* alphaPixelFormat) {
    return MovieCodec{.name = name,
                      .arguments = {"-c:v", "prores_ks", "-profile:v", profile, "-vendor", "apl0"},
                      .containers = movContainers,
                      .layout = layout,
                      .pixelFormat = pixelFormat,
                      .alphaPixelFormat = alphaPixelFormat};
  };
  auto dnxhr = [&](const std::string& profile, YcbcrLayout layout, const char* pixelFormat) {
    return MovieCodec{.name = "dnxhr_" + profile,
                      .arguments = {"-c:v", "dnxhd", "-profile:v", "dnxhr_" + profile},
                      .containers = dnxhrContainers,
                      .layout = layout,
                      .pixelFormat = pixelFormat,
                      .alphaPixelFormat = "",
                      .minWidth = 256,
                      .minHeight = 120};
  };
  const YcbcrLayout eightBit420{.bits = 8, .chromaColumns = 2, .chromaRows = 2},
      eightBit422{.bits = 8, .chromaColumns = 2, .chromaRows = 1},
      tenBit422{.bits = 10, .chromaColumns = 2, .chromaRows = 1},
      tenBit444{.bits = 10, .chromaColumns = 1, .chromaRows = 1},
      twelveBit444{.bits = 12, .chromaColumns = 1, .chromaRows = 1};
  return {
      {.name = "h264",
       .arguments = {"-c:v", "libx264", "-preset", "medium", "-crf", "16"},
       .containers = {"mp4", "mov", "mkv", "m4v"},
       .layout = eightBit420,
       .pixelFormat = "yuv420p",
       .alphaPixelFormat = ""},
      prores("prores_4444", "4444", twelveBit444, "yuv444p12le", "yuva444p12le"),
      prores("prores_422hq", "hq", tenBit422, "yuv422p10le", ""),
      dnxhr("hq", eightBit422, "yuv422p"),
      dnxhr("hqx", tenBit422, "yuv422p10le"),
      dnxhr("444", tenBit444, "yuv444p10le"),
  };
}

const std::vector<MovieCodec>& codecs() {
  static const std::vector<MovieCodec> kCodecs = makeCodecs();
  return kCodecs;
}

const MovieCodec& movieCodec(const std::string& name, const std::string& path) {
  const std::vector<MovieCodec>& all = codecs();
  auto found =
      std::find_if(all.begin(), all.end(), [&](const MovieCodec& c) { return c.name == name; });
  if (found == all.end()) {
    throw Error(fmt::format("unknown movie codec '{}' for {} (known: {})", name, path,
                            fmt::join(movieCodecs(), ", ")),
                {"write", {}, path});
  }
  const std::string extension = lowerExtension(path);
  if (std::find(found->containers.begin(), found->containers.end(), extension) ==
      found->containers.end()) {
    throw Error(fmt::format("the codec {} does not go into a .{} file ({}): use {}", name,
                            extension, path, fmt::join(found->containers, " or ")),
                {"write", {}, path});
  }
  return *found;
}

// The colour tags of the Y'CbCr we made (its range and matrix, the primaries and transfer), set
// on the frames so that the encoder and the container both carry them (ffmpeg 5.1 takes the
// stream's tags from the frames: its -color_* options alone leave ProRes untagged). A player
// decoding by the tags gets our RGB back.
std::vector<std::string> colorArguments(const ColorTags& tags) {
  const std::string matrix = tags.movieMatrix.empty() ? "bt709" : tags.movieMatrix;
  std::string filter = fmt::format("setparams=range=tv:colorspace={}", matrix);
  if (!tags.moviePrimaries.empty()) filter += ":color_primaries=" + tags.moviePrimaries;
  if (!tags.movieTransfer.empty()) filter += ":color_trc=" + tags.movieTransfer;
  // The encoder's own options too: MXF's descriptors take the tags from them, not the frames.
  std::vector<std::string> arguments{"-vf", filter, "-colorspace", matrix, "-color_range", "tv"};
  if (!tags.moviePrimaries.empty())
    arguments.insert(arguments.end(), {"-color_primaries", tags.moviePrimaries});
  if (!tags.movieTransfer.empty())
    arguments.insert(arguments.end(), {"-color_trc", tags.movieTransfer});
  return arguments;
}

class MovieWriter final : public ClipWriter {
 public:
  MovieWriter(const std::string& path, int width, int height, const WriterOptions& options,
              bool withAlpha)
      : path_(path),
        width_(width),
        height_(height),
        codec_(movieCodec(options.codec, path)),
        layout_(codec_.layout),
        pixelFormat_(withAlpha ? codec_.alphaPixelFormat : codec_.pixelFormat),
        encodedWidth_(codec_.layout.chromaColumns == 2 ? width + width % 2 : width),
        encodedHeight_(codec_.layout.chromaRows == 2 ? height + height % 2 : height),
        tmp_(fs::temporaryPathFor(path, std::string(kLogSuffix).size())),
        log_(tmp_.string() + kLogSuffix),
        tmpRemovedOnHardStop_(tmp_.string()),
        logRemovedOnHardStop_(log_.string()) {
    matrix_ = ycbcrMatrix(options.color.movieMatrix, path);
    if (withAlpha && pixelFormat_.empty()) {
      throw Error(fmt::format("the codec {} has no alpha channel, which {} needs: use {}",
                              codec_.name, path, fmt::join(codecsWithAlpha(), " or ")),
                  {"write", {}, path});
    }
    layout_.alpha = withAlpha;
    if (!(options.fps > 0) || !std::isfinite(options.fps)) {
      throw Error(
          fmt::format("cannot write the movie {} at {} frames per second", path, options.fps),
          {"write", {}, path});
    }
    if (width < codec_.minWidth || height < codec_.minHeight) {
      throw Error(fmt::format("the codec {} needs frames of at least {}x{}; {} would be {}x{}",
                              codec_.name, codec_.minWidth, codec_.minHeight, path, width, height),
                  {"write", {}, path});
    }
    if (!programAvailable("ffmpeg")) {
      throw Error("ffmpeg is needed to write the movie " + path + " but is not on PATH",
                  {"write", {}, path});
    }
    if (encodedWidth_ != width || encodedHeight_ != height)
      log::warning(fmt::format(
          "{}x{} frames are written as {}x{} into {}: {} shares chroma between pixel pairs, "
          "so its frames have even sizes (the last column or row repeated); a 4:4:4 codec or an "
          "image sequence keeps the plate's size",
          width, height, encodedWidth_, encodedHeight_, path, codec_.name));
    const MovieCodec& codec = codec_;
    std::vector<std::string> argv{"ffmpeg",   "-y",
                                  "-v",       "error",
                                  "-f",       "rawvideo",
                                  "-pix_fmt", pixelFormat_,
                                  "-s",       fmt::format("{}x{}", encodedWidth_, encodedHeight_),
                                  "-r",       frameRateArgument(options.fps),
                                  "-i",       "-"};
    argv.insert(argv.end(), codec.arguments.begin(), codec.arguments.end());
    argv.insert(argv.end(), {"-pix_fmt", pixelFormat_});  // encoded as piped
    argv.insert(argv.end(), {"-threads", std::to_string(threadLimit())});
    const std::vector<std::string> color = colorArguments(options.color);
    argv.insert(argv.end(), color.begin(), color.end());
    if (lowerExtension(path_) == "mxf" && options.color.movieTransfer == "iec61966-2-1")
      log::warning(fmt::format(
          "{}: MXF has no label for the sRGB transfer (ffmpeg's MXF writer leaves it unstated): "
          "the movie states its primaries and matrix only; --out-colorspace rec709 writes a "
          "BT.709 movie MXF readers take as such",
          path_));
    if (options.timecode) {
      argv.insert(argv.end(), {"-timecode", options.timecode->text()});
    }
    if (!options.metadata.empty())
      argv.insert(argv.end(), {"-metadata", "comment=" + metadataComment(options.metadata)});
    // "file:" keeps a name that starts with "-" from reading as an option, and one such as
    // "pipe:1.mp4" from reading as another protocol.
    argv.push_back("file:" + tmp_.string());
    if (!options.ycbcrCopy.empty()) {
      ycbcrCopy_.open(options.ycbcrCopy, std::ios::binary | std::ios::trunc);
      if (!ycbcrCopy_)
        throw Error("cannot write the Y'CbCr copy " + options.ycbcrCopy, {"write", {}, path});
    }
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
    const void* bytes = nullptr;
    size_t byteCount = 0;
    if (layout_.bits == 8) {
      packYcbcr(image, encodedWidth_, encodedHeight_, layout_, matrix_, packed8_);
      bytes = packed8_.data(), byteCount = packed8_.size();
    } else {
      packYcbcr(image, encodedWidth_, encodedHeight_, layout_, matrix_, packed16_);
      bytes = packed16_.data(), byteCount = packed16_.size() * sizeof(uint16_t);
    }
    if (ycbcrCopy_.is_open() &&
        !ycbcrCopy_.write(static_cast<const char*>(bytes), std::streamsize(byteCount)))
      throw Error(fmt::format("cannot write frame {} to the Y'CbCr copy of {}", frame, path_),
                  context);
    try {
      encoder_->write(bytes, byteCount);
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
    // ffmpeg may exit 0 with the index unwritten (a full disk): the file is checked itself.
    if (const std::string problem = movieIndexProblem(tmp_.string()); !problem.empty()) {
      removeTemporaries();
      throw Error(fmt::format("ffmpeg finished {} but the movie is not whole: {}", path_, problem),
                  context);
    }
    fs::commitTemporary(tmp_, path_);
    removeTemporaries();
    if (ycbcrCopy_.is_open()) {
      ycbcrCopy_.close();
      if (ycbcrCopy_.fail()) throw Error("cannot finish the Y'CbCr copy of " + path_, context);
    }
  }

  bool isMovie() const override { return true; }
  std::string pathFor(int64_t) const override { return path_; }

 private:
  void removeTemporaries() {
    std::error_code ec;
    stdfs::remove(tmp_, ec);
    stdfs::remove(log_, ec);
  }

  std::string path_;
  int width_;
  int height_;
  const MovieCodec& codec_;
  YcbcrLayout layout_;       // the codec's, with the alpha plane when asked for
  std::string pixelFormat_;  // ffmpeg's name of that layout
  int encodedWidth_;         // even for codecs that share chroma between columns
  int encodedHeight_;
  stdfs::path tmp_;  // encoded here, renamed to path_ by close()
  stdfs::path log_;  // ffmpeg's output, quoted in errors
  // Both removed if a second signal stops the process before close() or the destructor does.
  RemovedOnHardStop tmpRemovedOnHardStop_, logRemovedOnHardStop_;
  std::optional<PipeProcess> encoder_;
  std::optional<int64_t> lastFrame_;
  YcbcrMatrix matrix_;
  std::vector<uint8_t> packed8_;    // planar Y', Cb, Cr of 8-bit codecs
  std::vector<uint16_t> packed16_;  // and of 10- and 12-bit ones (ffmpeg's ...le formats)
  std::ofstream ycbcrCopy_;         // WriterOptions::ycbcrCopy, when asked for
  static_assert(std::endian::native == std::endian::little, "16-bit samples are piped as ...le");
  std::mutex mutex_;
};

}  // namespace

std::vector<std::string> movieCodecs() {
  std::vector<std::string> names;
  for (const MovieCodec& codec : codecs()) names.push_back(codec.name);
  return names;
}

const std::vector<std::string>& movieOutputExtensions() {
  static const std::vector<std::string> kExtensions{"mp4", "mov", "mkv", "m4v", "mxf"};
  return kExtensions;
}

std::vector<std::string> codecsWithAlpha() {
  std::vector<std::string> names;
  for (const MovieCodec& codec : codecs())
    if (!codec.alphaPixelFormat.empty()) names.push_back(codec.name);
  return names;
}

std::unique_ptr<ClipWriter> openMovieWriter(const std::string& path, int width, int height,
                                            const WriterOptions& options, bool withAlpha) {
  return std::make_unique<MovieWriter>(path, width, height, options, withAlpha);
}

}  // namespace pluvia
