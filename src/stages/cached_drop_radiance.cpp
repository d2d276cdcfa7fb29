#include "stages/cached_drop_radiance.h"

#include <cstring>

#include <fmt/format.h>

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
    // The map is outputWidth x outputWidth / 2: an entry of another size is made again.
    if (blob->pixelSize(3 * sizeof(float)) ==
        std::pair{settings.outputWidth, settings.outputWidth / 2}) {
      EquirectMap map;
      map.width = settings.outputWidth;
      map.height = settings.outputWidth / 2;
      map.rgb.resize(blob->bytes.size() / sizeof(float));
      std::memcpy(map.rgb.data(), blob->bytes.data(), blob->bytes.size());
      log::debug(fmt::format("drop radiance map {}x{}: from cache", map.width, map.height));
      return map;
    }
  }
  EquirectMap map = optics::buildDropRadianceMap(environment, optics, settings);
  clip.cache->storeBlob("drop-radiance", key, {{"width", map.width}, {"height", map.height}},
                        map.rgb.data(), map.rgb.size() * sizeof(float));
  return map;
}

}  // namespace pluvia
