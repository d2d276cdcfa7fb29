#pragma once
// The drop's radiance map (optics/drop_radiance_map.h) of the clip's environment, made once
// and kept in --cache: half a second a look at proxy size, and the same for every --set change
// that leaves the environment and the drop's optics alone (rate, wind, opacity, grading).
#include <array>

#include "optics/drop_radiance_map.h"
#include "optics/drop_transfer.h"
#include "pipeline/stage.h"

namespace pluvia {

// buildDropRadianceMap(environment, optics, settings), from clip.cache when it holds the map of
// the same environment (by its values), optics and settings; stored there when made.
EquirectMap cachedDropRadianceMap(ClipContext& clip, const EquirectMap& environment,
                                  const std::array<optics::DropOptics, 3>& optics,
                                  const optics::RadianceMapSettings& settings = {});

}  // namespace pluvia
