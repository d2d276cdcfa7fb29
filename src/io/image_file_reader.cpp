#include "io/image_file_reader.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <system_error>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "io/frame_size.h"
#include "io/metadata_names.h"
#include "io/oiio_message.h"
#include "io/timecode.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

ErrorContext readContext(const std::string& path, std::optional<int64_t> frame) {
  return ErrorContext{"read", frame, path};
}

// The frame pluvia works on, in the file's coordinates: the display window grown to hold the
// data window (overscan is kept, not cropped). In 64 bits, a size past 2^31 held as INT32_MAX:
// a hostile header may set the windows far apart, and openImage() refuses that size.
PixelWindow frameOf(const OIIO::ImageSpec& spec) {
  const int x0 = std::min(spec.x, spec.full_x), y0 = std::min(spec.y, spec.full_y);
  const int64_t x1 =
      std::max<int64_t>(int64_t(spec.x) + spec.width, int64_t(spec.full_x) + spec.full_width);
  const int64_t y1 =
      std::max<int64_t>(int64_t(spec.y) + spec.height, int64_t(spec.full_y) + spec.full_height);
  return {x0, y0, int(std::min<int64_t>(x1 - x0, INT32_MAX)),
          int(std::min<int64_t>(y1 - y0, INT32_MAX))};
}

// A multi-part EXR (or a multi-page TIFF): pluvia reads its first part. Said once, for the first
// such file: a sequence's every frame has the same parts.
void warnOfOtherParts(OIIO::ImageInput& input, const std::string& path) {
  static std::atomic<bool> said{false};
  if (said) return;
  const bool several = input.seek_subimage(1, 0);
  input.seek_subimage(0, 0);
  // A seek past the last part leaves an error behind (libtiff's "Out of memory"), which the
  // decode check would take for the frame's.
  input.geterror(/*clear=*/true);
  if (!several) return;
  std::vector<std::string> parts;
  for (int part = 0; input.seek_subimage(part, 0); ++part) {
    const std::string name = input.spec().get_string_attribute("name");
    parts.push_back(name.empty() ? fmt::format("part {}", part) : "'" + name + "'");
  }
  input.seek_subimage(0, 0);
  input.geterror(/*clear=*/true);
  if (said.exchange(true)) return;
  log::warning(fmt::format(
      "{} holds {} parts ({}): pluvia reads the first, {}, as the plate and leaves the others "
      "(said once for all such files)",
      path, parts.size(), fmt::join(parts, ", "), parts.front()));
}

// EXIF orientation (1 upright, 2-8 flipped and turned, 5-8 a quarter turn): 1 where the file
// states none. The frame is read turned upright, as every viewer shows it.
int orientationOf(const OIIO::ImageSpec& spec) {
  const int orientation = spec.get_int_attribute("Orientation", 1);
  return orientation >= 1 && orientation <= 8 ? orientation : 1;
}

// `image` as shown: turned and flipped by its EXIF orientation.
Image upright(const Image& image, int orientation) {
  OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
  spec.attribute("Orientation", orientation);
  const OIIO::ImageBuf stored(spec, const_cast<float*>(image.rgba.data()));
  const OIIO::ImageBuf turned = OIIO::ImageBufAlgo::reorient(stored);
  const OIIO::ROI roi = turned.roi();
  Image out(roi.width(), roi.height());
  turned.get_pixels(roi, OIIO::TypeDesc::FLOAT, out.rgba.data());
  return out;
}

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path, std::optional<int64_t> frame) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // A device or a pipe (/dev/zero) never ends: decoders would read it forever.
    throw Error("not a regular file (a device, pipe or folder is not an image): " + path,
                readContext(path, frame));
  }
  if (std::filesystem::is_regular_file(status) && std::filesystem::file_size(path, ec) == 0) {
    throw Error("image file is empty (0 bytes): " + path, readContext(path, frame));
  }
  // Keep PNG/TIFF alpha straight, as pluvia's frames are; OIIO would premultiply otherwise.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path, &config);
  if (!input) {
    throw Error("cannot read image " + path + ": " + oiioMessage(OIIO::geterror()),
                readContext(path, frame));
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.full_width <= 0 || spec.full_height <= 0 || spec.width <= 0 || spec.height <= 0 ||
      spec.nchannels <= 0) {
    throw Error("image has no pixels (zero size): " + path, readContext(path, frame));
  }
  if (spec.deep)
    throw Error("image " + path +
                    " is a deep image (several samples a pixel): pluvia reads flat images; "
                    "flatten it first (oiiotool IN --flatten -o OUT)",
                readContext(path, frame));
  warnOfOtherParts(*input, path);
  checkFrameSize(spec.full_width, spec.full_height, path, readContext(path, frame));
  checkFrameSize(spec.width, spec.height, path, readContext(path, frame));  // the data window
  // The two windows together (a hostile header may set them far apart).
  const PixelWindow frameWindow = frameOf(spec);
  checkFrameSize(frameWindow.width, frameWindow.height, path, readContext(path, frame));
  return input;
}

bool isFloatFormat(const OIIO::ImageSpec& spec) {
  OIIO::TypeDesc::BASETYPE base = static_cast<OIIO::TypeDesc::BASETYPE>(spec.format.basetype);
  return base == OIIO::TypeDesc::HALF || base == OIIO::TypeDesc::FLOAT ||
         base == OIIO::TypeDesc::DOUBLE;
}

// Turns what read_image() left in the RGBA slots (1 channel: gray in R; 2: gray in R, alpha in G)
// into RGBA.
void expandChannels(Image& image, int channelsRead) {
  if (channelsRead > 2) return;
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    float* p = image.rgba.data() + i * 4;
    if (channelsRead == 2) p[3] = p[1];
    p[1] = p[2] = p[0];
  }
}

}  // namespace

const std::vector<std::string>& carriedMetadataNames() {
  static const std::vector<std::string> kNames{"Make",
                                               "Model",
                                               "Exif:LensModel",
                                               "Exif:FocalLength",
                                               "Exif:FocalLengthIn35mmFilm",
                                               "FNumber",
                                               "ExposureTime",
                                               "Exif:ISOSpeedRatings",
                                               "Exif:BodySerialNumber",
                                               "cameraMake",
                                               "cameraModel",
                                               "cameraSerialNumber",
                                               "lensMake",
                                               "lensModel",
                                               "lensSerialNumber",
                                               "dpx:InputDevice",
                                               "dpx:InputDeviceSerialNumber",
                                               "smpte:TimeCode"};
  return kNames;
}

ImageFileHeader readImageHeader(const std::string& path, std::optional<int64_t> frame) {
  std::unique_ptr<OIIO::ImageInput> input = openImage(path, frame);
  const OIIO::ImageSpec& spec = input->spec();
  ImageFileHeader header;
  const PixelWindow frameWindow = frameOf(spec);
  header.width = frameWindow.width;
  header.height = frameWindow.height;
  if (orientationOf(spec) >= 5) std::swap(header.width, header.height);  // read upright
  header.channels = spec.nchannels;
  header.isFloat = isFloatFormat(spec);
  header.bitsPerSample =
      spec.get_int_attribute("oiio:BitsPerSample", static_cast<int>(spec.format.size() * 8));
  const PixelWindow display{spec.full_x - frameWindow.x, spec.full_y - frameWindow.y,
                            spec.full_width, spec.full_height};
  const PixelWindow data{spec.x - frameWindow.x, spec.y - frameWindow.y, spec.width, spec.height};
  const PixelWindow whole{0, 0, frameWindow.width, frameWindow.height};
  if (!(display == whole)) header.displayWindow = display;
  if (!(data == whole)) header.dataWindow = data;
  for (const std::string& name : carriedMetadataNames()) {
    const OIIO::ParamValue* value = spec.find_attribute(name);
    if (!value) continue;
    if (value->type() == OIIO::TypeTimeCode) {
      // Held as two SMPTE words; as text here, so every format and the log can carry it.
      header.metadata[name] =
          Timecode::textOfSmpteWord(static_cast<const uint32_t*>(value->data())[0]);
    } else {
      header.metadata[name] = value->get_string();
    }
  }
  // A shutter angle, where the camera or the facility wrote one (no standard name: ARRI's
  // "com.arri.camera.ShutterAngle", "shutterAngle", "ShutterAngle"), in degrees.
  for (const OIIO::ParamValue& attribute : spec.extra_attribs)
    if (metadataNameEndsWith(attribute.name().string(), "shutterangle"))
      header.metadata["ShutterAngle"] = attribute.get_string();
  return header;
}

Image readImageFile(const std::string& path, std::optional<int64_t> frame) {
  std::unique_ptr<OIIO::ImageInput> input = openImage(path, frame);
  const OIIO::ImageSpec& spec = input->spec();
  const int channelsRead = std::min(spec.nchannels, 4);
  const PixelWindow frameWindow = frameOf(spec);
  Image image(frameWindow.width, frameWindow.height);
  const OIIO::stride_t pixelBytes = 4 * sizeof(float);
  // The data window (EXR) may differ from the frame. Pixels outside it stay black, transparent
  // where the file has alpha.
  const bool windowIsFrame = spec.x == frameWindow.x && spec.y == frameWindow.y &&
                             spec.width == frameWindow.width && spec.height == frameWindow.height;
  if (!windowIsFrame && (channelsRead == 2 || channelsRead == 4)) {
    for (size_t i = 0; i < image.pixelCount(); ++i) image.rgba[i * 4 + 3] = 0.0f;
  }
  // Straight into the frame's RGBA slots: no intermediate buffer (a 1080p one costs more to
  // allocate than to fill).
  if (!input->read_image(0, 0, 0, channelsRead, OIIO::TypeDesc::FLOAT,
                         image.pixel(spec.x - frameWindow.x, spec.y - frameWindow.y), pixelBytes,
                         pixelBytes * image.width)) {
    throw Error("cannot decode image " + path +
                    " (corrupt or truncated?): " + oiioMessage(input->geterror()),
                readContext(path, frame));
  }
  // A decoder that filled what it could not read (a JPEG cut short: its lower part grey) still
  // returns true; it says so among its errors.
  if (input->has_error())
    throw Error("cannot decode image " + path +
                    " (corrupt or truncated?): " + oiioMessage(input->geterror()),
                readContext(path, frame));
  expandChannels(image, channelsRead);
  if (const int orientation = orientationOf(spec); orientation != 1)
    return upright(image, orientation);
  return image;
}

}  // namespace pluvia
