#pragma once
// Environment maps from disk: an equirect HDR (.exr, .hdr, any float format OpenImageIO reads),
// taken as scene-linear Rec.709 radiance, 2:1 aspect, the convention of image/equirect.h.
#include <string>

#include "image/equirect.h"

namespace pluvia::optics {

// Throws pluvia::Error naming the file when it cannot be read, is not 2:1, or holds non-finite
// radiance (reported with the first offending texel). Negative values become 0.
EquirectMap loadEnvironment(const std::string& path);

}  // namespace pluvia::optics
