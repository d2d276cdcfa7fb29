#include "pipeline/cache.h"

#include <fstream>

#include "util/fs.h"
#include "util/log.h"

namespace pluvia {

ArtifactCache::ArtifactCache(std::filesystem::path folder) : folder_(std::move(folder)) {}

std::filesystem::path ArtifactCache::pathFor(const std::string& stage,
                                             const std::string& key) const {
  return folder_ / (stage + "-" + key + ".json");
}

bool ArtifactCache::contains(const std::string& stage, const std::string& key) const {
  return load(stage, key).has_value();
}

std::optional<nlohmann::json> ArtifactCache::load(const std::string& stage,
                                                  const std::string& key) const {
  auto path = pathFor(stage, key);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  try {
    return nlohmann::json::parse(fs::readTextFile(path));
  } catch (const std::exception&) {
    log::warning("ignoring unreadable cache entry " + path.string());
    return std::nullopt;
  }
}

void ArtifactCache::store(const std::string& stage, const std::string& key,
                          const nlohmann::json& value) const {
  fs::writeTextFile(pathFor(stage, key), value.dump(1));
}

namespace {

std::filesystem::path blobPathOf(const std::filesystem::path& entry) {
  return std::filesystem::path(entry).replace_extension(".bin");
}

}  // namespace

void ArtifactCache::storeBlob(const std::string& stage, const std::string& key,
                              const nlohmann::json& header, const void* bytes, size_t size) const {
  const std::filesystem::path entry = pathFor(stage, key);
  fs::writeFileAtomically(blobPathOf(entry), bytes, size);
  store(stage, key, {{"header", header}, {"bytes", size}});
}

std::optional<std::pair<int, int>> ArtifactCache::Blob::pixelSize(size_t bytesPerPixel) const {
  const auto dimension = [&](const char* name) {
    const auto it = header.find(name);
    return it != header.end() && it->is_number_integer() ? it->get<int64_t>() : int64_t(0);
  };
  const int64_t width = dimension("width"), height = dimension("height");
  if (width <= 0 || height <= 0 || width > (1 << 20) || height > (1 << 20) ||
      bytes.size() != size_t(width) * size_t(height) * bytesPerPixel)
    return std::nullopt;
  return std::pair{int(width), int(height)};
}

std::optional<ArtifactCache::Blob> ArtifactCache::loadBlob(const std::string& stage,
                                                           const std::string& key) const {
  const std::optional<nlohmann::json> entry = load(stage, key);
  if (!entry) return std::nullopt;
  const std::filesystem::path path = blobPathOf(pathFor(stage, key));
  try {
    const size_t size = entry->at("bytes").get<size_t>();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {  // a FIFO would block the read
      log::warning("ignoring cache entry " + path.string() + ": not a regular file");
      return std::nullopt;
    }
    std::ifstream in(path, std::ios::binary);
    Blob blob{entry->at("header"), std::string(size, '\0')};
    if (!in.read(blob.bytes.data(), std::streamsize(size)) || in.peek() != EOF) {
      log::warning("ignoring cache entry " + path.string() + ": not the size its entry says");
      return std::nullopt;
    }
    return blob;
  } catch (const std::exception&) {
    log::warning("ignoring unreadable cache entry " + pathFor(stage, key).string());
    return std::nullopt;
  }
}

}  // namespace pluvia
