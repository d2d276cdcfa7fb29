#pragma once
// The artifact cache for per-clip analysis (--cache DIR): one JSON file per result, named by
// stage and key, the key a hash of the inputs, the parameters and the pluvia version (OCIO's
// cache-ID idea). Writes are atomic; a corrupt entry is treated as missing.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

namespace pluvia {

class ArtifactCache {
 public:
  explicit ArtifactCache(std::filesystem::path folder);
  std::filesystem::path pathFor(const std::string& stage, const std::string& key) const;
  bool contains(const std::string& stage, const std::string& key) const;
  std::optional<nlohmann::json> load(const std::string& stage, const std::string& key) const;
  void store(const std::string& stage, const std::string& key, const nlohmann::json& value) const;

  // A result too large for JSON (a still, a mask, a radiance map): its bytes in STAGE-KEY.bin
  // beside a JSON entry holding `header` (its shape) and the byte count. The bytes are written
  // first, so an entry whose JSON exists is whole; loadBlob gives nothing for a missing entry
  // or one whose file holds another count of bytes.
  void storeBlob(const std::string& stage, const std::string& key, const nlohmann::json& header,
                 const void* bytes, size_t size) const;
  struct Blob {
    nlohmann::json header;
    std::string bytes;
    // The header's "width" and "height" when both are positive and the bytes are exactly
    // width * height pixels of `bytesPerPixel`; nullopt otherwise (an entry edited or cut short).
    std::optional<std::pair<int, int>> pixelSize(size_t bytesPerPixel) const;
  };
  std::optional<Blob> loadBlob(const std::string& stage, const std::string& key) const;

 private:
  std::filesystem::path folder_;
};

}  // namespace pluvia
