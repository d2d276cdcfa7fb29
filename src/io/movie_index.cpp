#include "io/movie_index.h"

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "io/sequence_pattern.h"

namespace pluvia {

std::string movieIndexProblem(const std::string& path) {
  const std::string extension = lowerExtension(path);
  if (extension != "mov" && extension != "mp4" && extension != "m4v") return "";
  std::error_code ec;
  const uint64_t fileBytes = std::filesystem::file_size(path, ec);
  if (ec) return "cannot read its size: " + ec.message();
  std::ifstream in(path, std::ios::binary);
  bool index = false;
  uint64_t at = 0;
  while (at < fileBytes) {
    unsigned char header[16];
    in.seekg(std::streamoff(at));
    if (fileBytes - at < 8 || !in.read(reinterpret_cast<char*>(header), 8))
      return "it ends inside a box header (cut short)";
    uint64_t size = 0;
    for (int i = 0; i < 4; ++i) size = size << 8 | header[i];
    const std::string type(reinterpret_cast<const char*>(header + 4), 4);
    if (size == 1) {
      if (fileBytes - at < 16 || !in.read(reinterpret_cast<char*>(header + 8), 8))
        return "it ends inside a box header (cut short)";
      size = 0;
      for (int i = 8; i < 16; ++i) size = size << 8 | header[i];
    } else if (size == 0) {
      size = fileBytes - at;
    }
    if (size < 8 || size > fileBytes - at)
      return "its '" + type + "' box runs past the end of the file (cut short)";
    index |= type == "moov";
    at += size;
  }
  if (!index)
    return "it has no index ('moov' box): the disk filled or the encoder stopped before the end";
  return "";
}

}  // namespace pluvia
