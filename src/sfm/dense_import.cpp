#include "sfm/dense_import.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>

#include "util/error.h"
#include "util/fs.h"
#include "util/input_guard.h"

namespace pluvia::sfm {
namespace {

const char* kStage = "sfm";

// COLMAP arrays are little-endian; the raw reads below assume a little-endian host.
bool littleEndianHost() {
  const uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw Error("COLMAP array " + path.string() + ": " + what, {kStage, std::nullopt, path.string()});
}

// Reads one "<integer>&" header field.
long headerField(std::istream& in, const std::filesystem::path& path, const char* name) {
  long value = 0;
  char separator = 0;
  if (!(in >> value) || !in.get(separator) || separator != '&')
    fail(path, std::string("bad header: expected ") + name + " followed by '&'");
  return value;
}

}  // namespace

ColmapArray readColmapArray(const std::filesystem::path& path) {
  if (!littleEndianHost()) fail(path, "reading needs a little-endian host");
  fs::requireRegularFile(path, "the COLMAP depth map");
  fs::protectInputs({path.string()});
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open");
  ColmapArray array;
  long w = headerField(in, path, "width");
  long h = headerField(in, path, "height");
  long c = headerField(in, path, "channels");
  if (w <= 0 || h <= 0 || c <= 0 || w > 100000 || h > 100000 || c > 64)
    fail(path, "implausible size " + std::to_string(w) + "x" + std::to_string(h) + "x" +
                   std::to_string(c));
  array.width = static_cast<int>(w);
  array.height = static_cast<int>(h);
  array.channels = static_cast<int>(c);
  array.values.resize(static_cast<size_t>(w) * h * c);
  in.read(reinterpret_cast<char*>(array.values.data()),
          static_cast<std::streamsize>(array.values.size() * sizeof(float)));
  if (static_cast<size_t>(in.gcount()) != array.values.size() * sizeof(float))
    fail(path, "data ends after " + std::to_string(in.gcount()) + " of " +
                   std::to_string(array.values.size() * sizeof(float)) + " bytes");
  return array;
}

void writeColmapArray(const std::filesystem::path& path, const ColmapArray& array) {
  if (array.values.size() != static_cast<size_t>(array.width) * array.height * array.channels)
    fail(path, "value count does not match the size");
  std::ofstream out(path, std::ios::binary);
  out << array.width << "&" << array.height << "&" << array.channels << "&";
  out.write(reinterpret_cast<const char*>(array.values.data()),
            static_cast<std::streamsize>(array.values.size() * sizeof(float)));
  if (!out) fail(path, "cannot write");
}

std::filesystem::path colmapDepthMapPath(const std::filesystem::path& workspace,
                                         const std::string& imageName, bool geometric) {
  return workspace / "stereo" / "depth_maps" /
         (imageName + (geometric ? ".geometric.bin" : ".photometric.bin"));
}

std::vector<float> importColmapDepthMeters(const std::filesystem::path& path, double metersPerUnit,
                                           int* width, int* height) {
  ColmapArray array = readColmapArray(path);
  if (array.channels != 1)
    fail(path, "a depth map has one channel, found " + std::to_string(array.channels));
  if (!(metersPerUnit > 0.0) || !std::isfinite(metersPerUnit))
    fail(path, "the metric scale must be positive and finite");
  std::vector<float> depth(array.values.size());
  for (size_t i = 0; i < depth.size(); ++i) {
    float v = array.values[i];
    depth[i] = (v > 0.0f && std::isfinite(v)) ? static_cast<float>(v * metersPerUnit)
                                              : std::numeric_limits<float>::quiet_NaN();
  }
  if (width) *width = array.width;
  if (height) *height = array.height;
  return depth;
}

}  // namespace pluvia::sfm
