#include "io/written_frame.h"

#include <filesystem>
#include <memory>

#include <OpenImageIO/imageio.h>

#include "io/clip_reader.h"
#include "io/image_file_reader.h"
#include "io/sequence_pattern.h"
#include "util/error.h"

namespace pluvia {
namespace {

constexpr const char* kHashKey = "pluvia:presetHash";

// EXR and PNG keep the key as a named attribute; TIFF and JPEG inside the description
// ("key=value; key=value", see image_file_writer.cpp). Empty when absent.
std::string recordedPresetHash(const std::string& path) {
  std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::open(path);
  if (!input) return "";
  const OIIO::ImageSpec& spec = input->spec();
  std::string hash = spec.get_string_attribute(kHashKey);
  if (!hash.empty()) return hash;
  const std::string description = spec.get_string_attribute("ImageDescription");
  const std::string field = std::string(kHashKey) + "=";
  const size_t start = description.find(field);
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

std::string reasonToRenderAgain(const std::string& path, const std::string& presetHash) {
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 || ec) return "the file is empty";
  try {
    readImageFile(path, std::nullopt);
  } catch (const Error&) {
    return "the file does not decode (truncated or corrupt)";
  }
  if (!formatRecordsMetadata(lowerExtension(path))) return "";
  const std::string recorded = recordedPresetHash(path);
  if (recorded.empty()) return std::string("the file records no ") + kHashKey;
  if (recorded != presetHash)
    return "it was rendered with preset " + recorded + ", this render's is " + presetHash;
  return "";
}

std::string reasonToRenderMovieAgain(const std::string& path, size_t frames) {
  try {
    const size_t held = openClip(path)->info().frames.size();
    if (held != frames)
      return "it holds " + std::to_string(held) + " frames, this render makes " +
             std::to_string(frames);
  } catch (const Error&) {
    return "the movie does not decode (empty, truncated or corrupt)";
  }
  return "";
}

}  // namespace pluvia
