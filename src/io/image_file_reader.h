#pragma once
// One image file through OpenImageIO, as pluvia's float RGBA (see clip_reader.h for the rules).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "io/pixel_window.h"

namespace pluvia {

struct ImageFileHeader {
  int width = 0;
  int height = 0;
  int channels = 0;      // as stored
  bool isFloat = false;  // half or float samples
  int bitsPerSample = 8;
  // The frame is the display window, grown to hold a data window that reaches past it
  // (overscan, EXR); width and height are the frame's. Where it grew, the display window's
  // place in it: the picture the camera frames.
  std::optional<PixelWindow> displayWindow;
  // The data window, in the frame, where it is not the whole frame.
  std::optional<PixelWindow> dataWindow;
  // Metadata to carry to the output (see carriedMetadataNames()): timecode as
  // "smpte:TimeCode" = "HH:MM:SS:FF", camera and lens fields as text.
  std::map<std::string, std::string> metadata;
};

// The header fields carried from an input to the output: timecode, and the camera, lens and
// exposure fields in OpenImageIO's names.
const std::vector<std::string>& carriedMetadataNames();

// Reads only the header. Throws pluvia::Error naming the file (and frame, when given).
ImageFileHeader readImageHeader(const std::string& path, std::optional<int64_t> frame);

// Reads the pixels: 1 channel -> gray RGB, 2 -> gray + alpha, 3 -> RGB, 4 or more -> the first
// four as RGBA. Alpha stays straight as stored (PNG/TIFF are not premultiplied on the way in).
Image readImageFile(const std::string& path, std::optional<int64_t> frame);

}  // namespace pluvia
