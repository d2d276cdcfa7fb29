#include "io/written_frame.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "io/clip_reader.h"
#include "io/image_file_reader.h"
#include "io/movie_index.h"
#include "io/sequence_pattern.h"
#include "util/error.h"

namespace pluvia {
namespace {

// EXR and PNG keep a key as a named attribute; TIFF and JPEG inside the description
// ("key=value; key=value", see image_file_writer.cpp). Empty when absent.
std::string recordedValue(const OIIO::ImageSpec& spec, const std::string& key) {
  std::string value = spec.get_string_attribute(key);
  if (!value.empty()) return value;
  const std::string description = spec.get_string_attribute("ImageDescription");
  const std::string field = key + "=";
  size_t start = description.find(field);
  // A match must start a field ("pluvia:size=" is not inside another key's value).
  while (start != std::string::npos && start != 0 && description.compare(start - 2, 2, "; ") != 0)
    start = description.find(field, start + 1);
  if (start == std::string::npos) return "";
  const size_t end = description.find(';', start);
  return description.substr(start + field.size(), end == std::string::npos
                                                      ? std::string::npos
                                                      : end - start - field.size());
}

bool formatRecordsMetadata(const std::string& extension) {
  return extension == "exr" || extension == "png" || extension == "tif" || extension == "tiff" ||
         extension == "jpg" || extension == "jpeg";
}

}  // namespace

const char* const kResumeIdentityKeys[8] = {"pluvia:presetHash", "pluvia:version", "pluvia:plate",
                                            "pluvia:size",       "pluvia:proxy",   "pluvia:colour",
                                            "pluvia:aovs",       "pluvia:format"};

std::string reasonToRenderAgain(const std::string& path,
                                const std::map<std::string, std::string>& metadata) {
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 || ec) return "the file is empty";
  try {
    readImageFile(path, std::nullopt);
  } catch (const Error&) {
    return "the file does not decode (truncated or corrupt)";
  }
  if (!formatRecordsMetadata(lowerExtension(path))) return "";
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
  if (!input) return "the file does not decode (truncated or corrupt)";
  for (const char* key : kResumeIdentityKeys) {
    const auto wanted = metadata.find(key);
    const std::string expected = wanted == metadata.end() ? "" : wanted->second;
    const std::string recorded = recordedValue(input->spec(), key);
    if (recorded == expected) continue;
    if (recorded.empty()) return std::string("the file records no ") + key;
    if (std::string(key) == "pluvia:presetHash")
      return "it was rendered with preset " + recorded + ", this render's is " + expected;
    if (std::string(key) == "pluvia:plate")
      return fmt::format(
          "it was rendered from another plate (or the plate changed since): {} {}, "
          "this render's {}",
          key, recorded, expected);
    return fmt::format("it was rendered with {} '{}', this render's is '{}'", key, recorded,
                       expected.empty() ? "(none)" : expected);
  }
  return "";
}

std::string reasonToRenderMovieAgain(const std::string& path, size_t frames,
                                     const std::string& size) {
  if (const std::string problem = movieIndexProblem(path); !problem.empty())
    return "the movie is not whole: " + problem;
  try {
    const ClipInfo info = openClip(path)->info();
    // A codec that shares chroma between pixel pairs pads an odd size by one (movie_writer.cpp).
    const std::string held = fmt::format("{}x{}", info.width, info.height);
    int width = 0, height = 0;
    std::sscanf(size.c_str(), "%dx%d", &width, &height);
    const bool padded = info.width == width + width % 2 && info.height == height + height % 2;
    if (held != size && !padded) return "it is " + held + ", this render makes " + size;
    if (info.frames.size() != frames)
      return "it holds " + std::to_string(info.frames.size()) + " frames, this render makes " +
             std::to_string(frames);
  } catch (const Error&) {
    return "the movie does not decode (empty, truncated or corrupt)";
  }
  return "";
}

}  // namespace pluvia
