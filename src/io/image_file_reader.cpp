#include "io/image_file_reader.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <system_error>

#include <OpenImageIO/imageio.h>

#include "util/error.h"

namespace pluvia {
namespace {

ErrorContext readContext(const std::string& path, std::optional<int64_t> frame) {
  return ErrorContext{"read", frame, path};
}

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path, std::optional<int64_t> frame) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) == 0) {
    throw Error("image file is empty (0 bytes): " + path, readContext(path, frame));
  }
  // Keep PNG/TIFF alpha straight, as pluvia's frames are; OIIO would premultiply otherwise.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path, &config);
  if (!input) {
    throw Error("cannot read image " + path + ": " + OIIO::geterror(), readContext(path, frame));
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.full_width <= 0 || spec.full_height <= 0 || spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    throw Error("image has no pixels (zero size): " + path, readContext(path, frame));
  }
  return input;
}

bool isFloatFormat(const OIIO::ImageSpec& spec) {
  OIIO::TypeDesc::BASETYPE base = static_cast<OIIO::TypeDesc::BASETYPE>(spec.format.basetype);
  return base == OIIO::TypeDesc::HALF || base == OIIO::TypeDesc::FLOAT || base == OIIO::TypeDesc::DOUBLE;
}

// Where each of R, G, B, A comes from among the channels read; -1: alpha absent (1).
std::array<int, 4> channelSources(int channelsRead) {
  switch (channelsRead) {
    case 1: return {0, 0, 0, -1};
    case 2: return {0, 0, 0, 1};
    case 3: return {0, 1, 2, -1};
    default: return {0, 1, 2, 3};
  }
}

}  // namespace

ImageFileHeader readImageHeader(const std::string& path, std::optional<int64_t> frame) {
  std::unique_ptr<OIIO::ImageInput> input = openImage(path, frame);
  const OIIO::ImageSpec& spec = input->spec();
  return {spec.full_width, spec.full_height, spec.nchannels, isFloatFormat(spec)};
}

Image readImageFile(const std::string& path, std::optional<int64_t> frame) {
  std::unique_ptr<OIIO::ImageInput> input = openImage(path, frame);
  const OIIO::ImageSpec& spec = input->spec();
  const int channelsRead = std::min(spec.nchannels, 4);
  std::vector<float> data(spec.image_pixels() * channelsRead);
  if (!input->read_image(0, 0, 0, channelsRead, OIIO::TypeDesc::FLOAT, data.data())) {
    throw Error("cannot decode image " + path + " (corrupt or truncated?): " + input->geterror(),
                readContext(path, frame));
  }
  const std::array<int, 4> source = channelSources(channelsRead);
  // The data window (EXR) may be smaller or larger than the display window, which is the
  // frame: pixels outside the data window are black, transparent only if the file has alpha.
  Image image(spec.full_width, spec.full_height);
  if (spec.x != spec.full_x || spec.y != spec.full_y || spec.width != spec.full_width ||
      spec.height != spec.full_height) {
    const float outsideAlpha = source[3] >= 0 ? 0.0f : 1.0f;
    for (size_t i = 0; i < image.pixelCount(); ++i) image.rgba[i * 4 + 3] = outsideAlpha;
  }
  const int x0 = std::max(spec.x, spec.full_x), x1 = std::min(spec.x + spec.width, spec.full_x + spec.full_width);
  const int y0 = std::max(spec.y, spec.full_y), y1 = std::min(spec.y + spec.height, spec.full_y + spec.full_height);
  for (int y = y0; y < y1; ++y) {
    const float* src = data.data() + (static_cast<size_t>(y - spec.y) * spec.width + (x0 - spec.x)) * channelsRead;
    float* dst = image.pixel(x0 - spec.full_x, y - spec.full_y);
    for (int x = x0; x < x1; ++x, src += channelsRead, dst += 4) {
      for (int c = 0; c < 4; ++c) dst[c] = source[c] >= 0 ? src[source[c]] : 1.0f;
    }
  }
  return image;
}

}  // namespace pluvia
