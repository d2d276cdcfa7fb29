#include "pipeline/cache.h"

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

}  // namespace pluvia
