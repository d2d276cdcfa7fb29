#include "io/image_file_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>

#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/oiio_message.h"
#include "io/sequence_pattern.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/thread_limit.h"

namespace pluvia {
namespace {

// Compression, measured on a 1920x1080 RGBA street frame with grain, 2 loaded cores:
//  EXR half: none 47 ms / 16.6 MB, PIZ 52 ms / 6.9 MB, ZIP 131 ms / 6.8 MB: PIZ (the default
//    of ImageFileOptions), the faster of
//    the lossless two (and quick for compositors to read);
//  PNG 8-bit: zlib level 1 170 ms / 3.6 MB against the default (6) 704 ms / 3.1 MB;
//  TIFF 16-bit: zip level 1 318 ms / 11.1 MB against the default (zip 6) 954 ms / 10.6 MB.
constexpr int kPngZlibLevel = 1;
constexpr const char* kTiffCompression = "zip:1";
constexpr int kJpegQuality = 95;

enum class Encoding { Uint8, Uint16, Dpx10, Half, Float };

Encoding encodingFor(const std::string& extension, const ImageFileOptions& options) {
  if (extension == "exr") return options.exrFullFloat ? Encoding::Float : Encoding::Half;
  if (extension == "hdr") return Encoding::Float;
  if (extension == "tif" || extension == "tiff")
    return options.tiffFloat ? Encoding::Float : Encoding::Uint16;
  if (extension == "dpx") return Encoding::Dpx10;
  return Encoding::Uint8;  // png, jpg, jpeg
}

float clamp01(float value) {
  // NaN fails both comparisons and becomes 0.
  return value > 0.0f ? (value < 1.0f ? value : 1.0f) : 0.0f;
}

// Writes one channel's samples, each through `encode` to a T, into an interleaved buffer.
template <typename T, typename Encode>
void interleaveChannel(const OutputChannel& channel, size_t pixels, unsigned char* first,
                       size_t pixelBytes, Encode encode) {
  const float* src = channel.samples;
  unsigned char* dst = first;
  for (size_t i = 0; i < pixels; ++i, src += channel.strideFloats, dst += pixelBytes) {
    const T value = encode(*src);
    std::memcpy(dst, &value, sizeof(T));
  }
}

uint8_t toUint8(float v) {
  return static_cast<uint8_t>(clamp01(v) * 255.0f + 0.5f);
}
uint16_t toUint16(float v) {
  return static_cast<uint16_t>(clamp01(v) * 65535.0f + 0.5f);
}
// Rounded to the nearest 10-bit code first, then handed over as that code's exact 16-bit
// equivalent, so the 16 -> 10 bit step of the DPX writer cannot round a second time.
uint16_t toDpx10(float v) {
  const uint32_t code = static_cast<uint32_t>(clamp01(v) * 1023.0f + 0.5f);
  return static_cast<uint16_t>((code * 65535u + 511u) / 1023u);
}
// Round to nearest; NaN and Inf stay NaN and Inf, and a finite value beyond the half range
// becomes the largest half of its sign rather than Inf (a bright colour must not turn into Inf).
Imath::half toHalf(float v) {
  constexpr float kHalfMax = 65504.0f;
  if (std::isfinite(v)) v = std::clamp(v, -kHalfMax, kHalfMax);
  return Imath::half(v);
}
float asIs(float v) {
  return v;
}

OIIO::TypeDesc sampleType(Encoding encoding, const OutputChannel& channel) {
  switch (encoding) {
    case Encoding::Uint8:
      return OIIO::TypeDesc::UINT8;
    case Encoding::Uint16:
    case Encoding::Dpx10:
      return OIIO::TypeDesc::UINT16;
    case Encoding::Half:
      return channel.fullFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF;
    case Encoding::Float:
      return OIIO::TypeDesc::FLOAT;
  }
  return OIIO::TypeDesc::FLOAT;
}

// The samples in the file's own layout, each channel in its own type, so that OIIO writes them
// as they are: its own float -> half conversion on write costs ~130 ms a 1080p frame, ours ~10.
std::vector<unsigned char> encode(Encoding encoding, size_t pixels,
                                  const std::vector<OutputChannel>& channels) {
  size_t pixelBytes = 0;
  for (const OutputChannel& channel : channels) pixelBytes += sampleType(encoding, channel).size();
  std::vector<unsigned char> bytes(pixels * pixelBytes);
  unsigned char* first = bytes.data();
  for (const OutputChannel& channel : channels) {
    const OIIO::TypeDesc type = sampleType(encoding, channel);
    if (encoding == Encoding::Uint8) {
      interleaveChannel<uint8_t>(channel, pixels, first, pixelBytes, toUint8);
    } else if (encoding == Encoding::Uint16) {
      interleaveChannel<uint16_t>(channel, pixels, first, pixelBytes, toUint16);
    } else if (encoding == Encoding::Dpx10) {
      interleaveChannel<uint16_t>(channel, pixels, first, pixelBytes, toDpx10);
    } else if (type == OIIO::TypeDesc::HALF) {
      interleaveChannel<Imath::half>(channel, pixels, first, pixelBytes, toHalf);
    } else {
      interleaveChannel<float>(channel, pixels, first, pixelBytes, asIs);
    }
    first += type.size();
  }
  return bytes;
}

// What the file says about its colour and its time (see io/color_tags.h, io/timecode.h).
void describe(OIIO::ImageSpec& spec, const std::string& extension,
              const ImageFileOptions& options) {
  if (const ColorTags* color = options.color) {
    // Not in a TIFF: for "sRGB" OpenImageIO adds an EXIF directory that, written through the
    // in-memory proxy below, leaves a file libtiff cannot read ("missing ImageLength").
    if (!color->name.empty() && extension != "tif" && extension != "tiff") {
      spec.attribute("oiio:ColorSpace", color->name);
      // OpenImageIO keeps no "oiio:" attribute in an EXR header: there the name goes into a
      // string attribute of its own.
      if (extension == "exr") spec.attribute("colorspace", color->name);
    }
    if (extension == "exr" && color->chromaticities) {
      spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8),
                     color->chromaticities->data());
    }
    if (extension == "dpx") {
      if (!color->dpxTransfer.empty()) spec.attribute("dpx:Transfer", color->dpxTransfer);
      if (!color->dpxColorimetric.empty())
        spec.attribute("dpx:Colorimetric", color->dpxColorimetric);
    }
  }
  if (options.timecode && (extension == "exr" || extension == "dpx")) {
    const std::array<uint32_t, 2> words = options.timecode->smpteWords();
    spec.attribute("smpte:TimeCode", OIIO::TypeTimeCode, words.data());
  }
}

// A metadata value as its field's type: the exposure fields a plate carries are numbers in
// EXIF and EXR (written as text, OpenEXR's writer drops them with a debug line), the rest text.
void setAttribute(OIIO::ImageSpec& spec, const std::string& key, const std::string& value) {
  static const std::set<std::string> kReals{"ExposureTime", "ShutterAngle", "FNumber",
                                            "Exif:FocalLength"};
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  const bool isNumber = !value.empty() && end == value.c_str() + value.size();
  if (isNumber && kReals.count(key)) {
    spec.attribute(key, float(number));
  } else if (isNumber && (key == "Exif:ISOSpeedRatings" || key == "Exif:FocalLengthIn35mmFilm") &&
             number == std::floor(number)) {
    spec.attribute(key, int(number));
  } else {
    spec.attribute(key, value);
  }
}

OIIO::ImageSpec makeSpec(const std::string& extension, Encoding encoding, int width, int height,
                         const std::vector<OutputChannel>& channels,
                         const std::map<std::string, std::string>& metadata,
                         const ImageFileOptions& options) {
  const OIIO::TypeDesc fileType = encoding == Encoding::Half    ? OIIO::TypeDesc::HALF
                                  : encoding == Encoding::Float ? OIIO::TypeDesc::FLOAT
                                  : encoding == Encoding::Uint8 ? OIIO::TypeDesc::UINT8
                                                                : OIIO::TypeDesc::UINT16;
  OIIO::ImageSpec spec(width, height, static_cast<int>(channels.size()), fileType);
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  for (size_t c = 0; c < channels.size(); ++c) {
    spec.channelnames[c] = channels[c].name;
    if (channels[c].name == "A") spec.alpha_channel = static_cast<int>(c);
  }
  if (encoding == Encoding::Half &&
      std::any_of(channels.begin(), channels.end(),
                  [](const OutputChannel& c) { return c.fullFloat; })) {
    for (const OutputChannel& channel : channels)
      spec.channelformats.push_back(sampleType(encoding, channel));
  }
  if (encoding == Encoding::Dpx10) spec.attribute("oiio:BitsPerSample", 10);
  if (extension == "exr") spec.attribute("compression", options.exrCompression);
  if (extension == "png") spec.attribute("png:compressionLevel", kPngZlibLevel);
  if (extension == "tif" || extension == "tiff") spec.attribute("compression", kTiffCompression);
  if (extension == "jpg" || extension == "jpeg")
    spec.attribute("Compression", "jpeg:" + std::to_string(kJpegQuality));
  // No date: OIIO stamps EXR, TIFF and DPX headers with the time of writing unless DateTime is
  // given, and an empty one leaves it out, so that a frame's file is byte-identical whenever and
  // in whichever chunk it is rendered.
  spec.attribute("DateTime", "");
  // Our alpha is straight: stop OIIO from un-premultiplying it into PNG/TIFF.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  // EXR and PNG keep any named string. TIFF and JPEG keep only standard fields, so there the
  // metadata goes into the description, one "key=value" after another. (DPX's description holds
  // 32 characters and HDR none: they go without.)
  std::string description;
  for (const auto& [key, value] : metadata) {
    setAttribute(spec, key, value);
    description += (description.empty() ? "" : "; ") + key + "=" + value;
  }
  const bool describes =
      extension == "tif" || extension == "tiff" || extension == "jpg" || extension == "jpeg";
  if (describes && !description.empty()) spec.attribute("ImageDescription", description);
  describe(spec, extension, options);
  if (extension == "exr") {
    // File coordinates have the display window at the origin.
    const PixelWindow display = options.displayWindow.value_or(PixelWindow{0, 0, width, height});
    const PixelWindow data = options.dataWindow.value_or(PixelWindow{0, 0, width, height});
    spec.full_x = spec.full_y = 0;
    spec.full_width = display.width;
    spec.full_height = display.height;
    spec.x = data.x - display.x;
    spec.y = data.y - display.y;
    spec.width = data.width;
    spec.height = data.height;
  }
  return spec;
}

// OpenImageIO's and OpenEXR's pools keep to --threads too (util/thread_limit.h). Set only when
// the limit changes: setting "threads" resizes OpenImageIO's pool, and a resize while another
// thread's write uses the pool trips its assertion (a render writing frames in parallel aborted
// with "thread.cpp: size: Assertion 'm_size == ...threads.size()' failed").
void applyThreadLimitToOiio() {
  static std::mutex mutex;
  static int applied = -1;
  const std::lock_guard<std::mutex> lock(mutex);
  const int limit = threadLimit();
  if (limit == applied) return;
  OIIO::attribute("threads", limit);
  OIIO::attribute("exr_threads", limit);
  applied = limit;
}

}  // namespace

const std::vector<std::string>& exrCompressions() {
  static const std::vector<std::string> kCompressions{"none",  "rle", "zips", "zip",  "piz",
                                                      "pxr24", "b44", "b44a", "dwaa", "dwab"};
  return kCompressions;
}

const std::vector<std::string>& imageOutputExtensions() {
  static const std::vector<std::string> kExtensions{"exr",  "hdr", "png", "tif",
                                                    "tiff", "dpx", "jpg", "jpeg"};
  return kExtensions;
}

void writeImageFile(const std::string& path, int width, int height,
                    const std::vector<OutputChannel>& channels,
                    const std::map<std::string, std::string>& metadata,
                    std::optional<int64_t> frame, const ImageFileOptions& options) {
  const ErrorContext context{"write", frame, path};
  const std::string extension = lowerExtension(path);
  const std::vector<std::string>& compressions = exrCompressions();
  if (extension == "exr" && std::find(compressions.begin(), compressions.end(),
                                      options.exrCompression) == compressions.end()) {
    throw Error(fmt::format("unknown EXR compression '{}' for {} (known: {})",
                            options.exrCompression, path, fmt::join(compressions, ", ")),
                context);
  }
  for (const auto& [name, window] :
       {std::pair{"data", options.dataWindow}, std::pair{"display", options.displayWindow}}) {
    if (window && !window->fitsInside(width, height)) {
      throw Error(
          fmt::format("{} window {}x{} at ({}, {}) is not inside the {}x{} frame of {}", name,
                      window->width, window->height, window->x, window->y, width, height, path),
          context);
    }
  }
  const Encoding encoding = encodingFor(extension, options);
  const OIIO::ImageSpec spec =
      makeSpec(extension, encoding, width, height, channels, metadata, options);
  const std::vector<unsigned char> pixels =
      encode(encoding, static_cast<size_t>(width) * height, channels);
  // The data window's first pixel and the frame's row length: only the window is stored.
  const size_t pixelBytes = pixels.size() / (static_cast<size_t>(width) * height);
  const PixelWindow stored = extension == "exr" && options.dataWindow
                                 ? *options.dataWindow
                                 : PixelWindow{0, 0, width, height};
  const unsigned char* first =
      pixels.data() + (static_cast<size_t>(stored.y) * width + stored.x) * pixelBytes;

  // Encoded into memory, then written by fs::writeFileAtomically, which checks every step down
  // to the disk: OIIO's own file writers miss some failures (a PNG on a full disk came out
  // empty or truncated with no error).
  std::vector<unsigned char> fileBytes;
  OIIO::Filesystem::IOVecOutput memory(fileBytes);
  OIIO::ImageSpec memorySpec = spec;
  void* proxy = &memory;
  memorySpec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  applyThreadLimitToOiio();
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write " + path + ": " + oiioMessage(OIIO::geterror()), context);
  // The file's name only: DPX records it in its header, and a frame must not depend on the folder.
  const std::string fileName = std::filesystem::path(path).filename().string();
  bool encoded = out->open(fileName, memorySpec) &&
                 out->write_image(OIIO::TypeUnknown, first, static_cast<OIIO::stride_t>(pixelBytes),
                                  static_cast<OIIO::stride_t>(pixelBytes * width));
  encoded = out->close() && encoded;
  if (!encoded || fileBytes.empty())
    throw Error("cannot encode " + path + ": " + oiioMessage(out->geterror()), context);
  try {
    fs::writeFileAtomically(path, fileBytes.data(), fileBytes.size());
  } catch (const Error& e) {
    throw Error(e.what(), context);
  }
}

}  // namespace pluvia
