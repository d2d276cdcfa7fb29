#include "stages/cached_drop_radiance.h"

#include <cstring>

#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

std::string radianceMapKey(const EquirectMap& environment,
                           const std::array<optics::DropOptics, 3>& optics,
                           const optics::RadianceMapSettings& settings) {
  Hasher hasher;
  hasher.add("drop-radiance").add(kVersion);
  hasher.add(uint64_t(environment.width)).add(uint64_t(environment.height));
  hasher.add(std::string_view(reinterpret_cast<const char*>(environment.rgb.data()),
                              environment.rgb.size() * sizeof(float)));
  for (const optics::DropOptics& channel : optics)
    hasher.add(channel.eta).add(uint64_t(channel.terms));
  for (int value :
       {settings.outputWidth, settings.inputWidth, settings.bins, settings.kernelSubsamples})
    hasher.add(uint64_t(value));
  return hasher.hex();
}

}  // namespace

EquirectMap cachedDropRadianceMap(ClipContext& clip, const EquirectMap& environment,
                                  const std::array<optics::DropOptics, 3>& optics,
                                  const optics::RadianceMapSettings& settings) {
  if (!clip.cache) return optics::buildDropRadianceMap(environment, optics, settings);
  const std::string key = radianceMapKey(environment, optics, settings);
  if (auto blob = clip.cache->loadBlob("drop-radiance", key)) {
    EquirectMap map;
    try {
      map.width = blob->header.at("width").get<int>();
      map.height = blob->header.at("height").get<int>();
    } catch (const nlohmann::json::exception&) {
      map.width = map.height = 0;
    }
    if (map.width > 0 && map.height > 0 &&
        blob->bytes.size() == size_t(map.width) * size_t(map.height) * 3 * sizeof(float)) {
      map.rgb.resize(size_t(map.width) * size_t(map.height) * 3);
      std::memcpy(map.rgb.data(), blob->bytes.data(), blob->bytes.size());
      log::debug("drop radiance map " + std::to_string(map.width) + "x" +
                 std::to_string(map.height) + ": from cache");
      return map;
    }
  }
  EquirectMap map = optics::buildDropRadianceMap(environment, optics, settings);
  clip.cache->storeBlob("drop-radiance", key, {{"width", map.width}, {"height", map.height}},
                        map.rgb.data(), map.rgb.size() * sizeof(float));
  return map;
}

}  // namespace pluvia
