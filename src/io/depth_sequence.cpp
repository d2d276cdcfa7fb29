#include "io/depth_sequence.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <system_error>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "image/image.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/input_guard.h"

namespace pluvia {
namespace {

constexpr float kSky = std::numeric_limits<float>::infinity();

ErrorContext depthContext(const std::string& path, std::optional<int64_t> frame) {
  return ErrorContext{"depth", frame, path};
}

// The channel holding depth: the first of Z, depth.Z, Y, R the file has, or its only channel.
int depthChannel(const OIIO::ImageSpec& spec, const std::string& path,
                 std::optional<int64_t> frame) {
  static const std::array<std::string, 4> kPreferred{"Z", "depth.Z", "Y", "R"};
  for (const std::string& name : kPreferred) {
    auto found = std::find(spec.channelnames.begin(), spec.channelnames.end(), name);
    if (found != spec.channelnames.end())
      return static_cast<int>(found - spec.channelnames.begin());
  }
  if (spec.nchannels == 1) return 0;
  throw Error(fmt::format("depth file {} has channels {} but none of Z, depth.Z, Y, R to take "
                          "depth from (or give a single-channel file)",
                          path, fmt::join(spec.channelnames, ", ")),
              depthContext(path, frame));
}

double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}

}  // namespace

DepthEncoding depthEncodingFromName(const std::string& name) {
  if (name == "z_m") return DepthEncoding::ZMeters;
  if (name == "inverse") return DepthEncoding::Inverse;
  if (name == "normalized") return DepthEncoding::Normalized;
  throw Error(fmt::format("unknown depth encoding '{}' (z_m, inverse or normalized)", name),
              {"depth", {}, {}});
}

float decodeDepthValue(float value, const DepthDecoding& decoding) {
  double meters = 0.0;
  switch (decoding.encoding) {
    case DepthEncoding::ZMeters:
      meters = decoding.scale * value;
      break;
    case DepthEncoding::Inverse:
      meters = decoding.scale / value;  // v == 0: +inf (or -inf for -0, sky below too)
      break;
    case DepthEncoding::Normalized:
      meters = lerp(decoding.nearMeters, decoding.farMeters, value);
      break;
  }
  // The render's depth AOV writes its sky as kSkyDepthInAovMeters: read back, it is sky again.
  const bool aovSky = decoding.encoding == DepthEncoding::ZMeters && value == kSkyDepthInAovMeters;
  if (!std::isfinite(meters) || meters <= 0.0 || aovSky) return kSky;
  return static_cast<float>(meters);
}

DepthPlane readDepthFile(const std::string& path, const DepthDecoding& decoding,
                         std::optional<int64_t> frame) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) == 0)
    throw Error("depth file is empty (0 bytes): " + path, depthContext(path, frame));
  fs::requireRegularFile(path, "the depth file");
  fs::protectInputs({path});
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
  if (!input)
    throw Error(fmt::format("cannot read depth file {}: {}", path, OIIO::geterror()),
                depthContext(path, frame));
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.full_width <= 0 || spec.full_height <= 0 || spec.width <= 0 || spec.height <= 0)
    throw Error("depth file has no pixels (zero size): " + path, depthContext(path, frame));
  const int channel = depthChannel(spec, path, frame);

  // The data window, as stored; integer samples come back as code / max code, in [0, 1].
  std::vector<float> stored(static_cast<size_t>(spec.width) * spec.height);
  if (!input->read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, stored.data()))
    throw Error(fmt::format("cannot decode depth file {} (corrupt or truncated?): {}", path,
                            input->geterror()),
                depthContext(path, frame));

  // Into the display window, which is the frame; what the data window leaves out is sky.
  DepthPlane plane;
  plane.width = spec.full_width;
  plane.height = spec.full_height;
  plane.meters.assign(static_cast<size_t>(plane.width) * plane.height, kSky);
  for (int y = 0; y < spec.height; ++y) {
    const int frameY = spec.y + y - spec.full_y;
    if (frameY < 0 || frameY >= plane.height) continue;
    for (int x = 0; x < spec.width; ++x) {
      const int frameX = spec.x + x - spec.full_x;
      if (frameX < 0 || frameX >= plane.width) continue;
      plane.meters[static_cast<size_t>(frameY) * plane.width + frameX] =
          decodeDepthValue(stored[static_cast<size_t>(y) * spec.width + x], decoding);
    }
  }
  return plane;
}

std::vector<float> resampleDepth(const DepthPlane& depth, int width, int height) {
  if (depth.width == width && depth.height == height) return depth.meters;
  // Inverse depth: sky (+inf) is 0 and interpolates like any other value.
  auto inverseAt = [&depth](int x, int y) {
    return 1.0 / depth.meters[static_cast<size_t>(y) * depth.width + x];
  };
  std::vector<float> meters(static_cast<size_t>(width) * height);
  const double scaleX = static_cast<double>(depth.width) / width;
  const double scaleY = static_cast<double>(depth.height) / height;
  for (int y = 0; y < height; ++y) {
    // Pixel centres line up: output centre y + 0.5 falls at (y + 0.5) * scale in the source.
    const double sourceY = std::clamp((y + 0.5) * scaleY - 0.5, 0.0, depth.height - 1.0);
    const int y0 = static_cast<int>(sourceY);
    const int y1 = std::min(y0 + 1, depth.height - 1);
    const double ty = sourceY - y0;
    for (int x = 0; x < width; ++x) {
      const double sourceX = std::clamp((x + 0.5) * scaleX - 0.5, 0.0, depth.width - 1.0);
      const int x0 = static_cast<int>(sourceX);
      const int x1 = std::min(x0 + 1, depth.width - 1);
      const double tx = sourceX - x0;
      const double inverse = lerp(lerp(inverseAt(x0, y0), inverseAt(x1, y0), tx),
                                  lerp(inverseAt(x0, y1), inverseAt(x1, y1), tx), ty);
      meters[static_cast<size_t>(y) * width + x] =
          inverse > 0.0 ? static_cast<float>(1.0 / inverse) : kSky;
    }
  }
  return meters;
}

DepthSequence::DepthSequence(const std::string& fileOrPattern, const DepthDecoding& decoding)
    : given_(fileOrPattern), decoding_(decoding) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(given_, ec);
  if (std::filesystem::is_directory(status))
    throw Error(fmt::format("{} is a folder; give a depth file or a sequence pattern such as {}",
                            given_, (std::filesystem::path(given_) / "depth.####.exr").string()),
                depthContext(given_, {}));
  // A file that exists is taken literally, as the plate is (io/clip_reader.cpp).
  if (std::filesystem::exists(status)) return;
  pattern_ = SequencePattern::parse(given_);
  if (!pattern_)
    throw Error(fmt::format("depth file {} not found (nor is it a sequence pattern such as "
                            "depth.####.exr)",
                            given_),
                depthContext(given_, {}));
}

std::string DepthSequence::pathFor(int64_t frame) const {
  return pattern_ ? pattern_->pathFor(frame) : given_;
}

void DepthSequence::requireFrames(const std::vector<int64_t>& frames) const {
  for (int64_t frame : frames) {
    const std::string path = pathFor(frame);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw Error(fmt::format("no depth file for frame {}: {} does not exist", frame, path),
                  depthContext(path, frame));
  }
}

std::vector<float> DepthSequence::read(int64_t frame, int width, int height) const {
  return resampleDepth(readDepthFile(pathFor(frame), decoding_, frame), width, height);
}

}  // namespace pluvia
