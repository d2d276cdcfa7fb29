#pragma once
// One image file through OpenImageIO, as pluvia's float RGBA (see clip_reader.h for the rules).
#include <cstdint>
#include <optional>
#include <string>

#include "image/image.h"

namespace pluvia {

struct ImageFileHeader {
  int width = 0;
  int height = 0;
  int channels = 0;      // as stored
  bool isFloat = false;  // half or float samples
};

// Reads only the header. Throws pluvia::Error naming the file (and frame, when given).
ImageFileHeader readImageHeader(const std::string& path, std::optional<int64_t> frame);

// Reads the pixels: 1 channel -> gray RGB, 2 -> gray + alpha, 3 -> RGB, 4 or more -> the first
// four as RGBA. Alpha stays straight as stored (PNG/TIFF are not premultiplied on the way in).
Image readImageFile(const std::string& path, std::optional<int64_t> frame);

}  // namespace pluvia
