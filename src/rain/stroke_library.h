#pragma once
// Stroke libraries: the rain mattes particles carry (Wang et al. section 3).
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "gpu/rain_renderer.h"

namespace pluvia::rain {

// PLACEHOLDER (analytic, not from footage): `count` procedural strokes, each a vertical matte
// with a Gaussian cross-section, soft tapered ends and a gentle random variation of brightness
// along its length. The stroke-extraction issue replaces this with strokes cut from real rain.
gpu::StrokeAtlas makeAnalyticStrokes(int count, uint64_t seed);

// Mean matte value over all strokes' rectangles (1 for an empty atlas).
double meanMatte(const gpu::StrokeAtlas& atlas);

// A stroke library as JSON: {"width", "height", "alpha": [row-major floats], "rects": [[x0,y0,x1,y1]...]}.
nlohmann::json strokeAtlasToJson(const gpu::StrokeAtlas& atlas);
// Throws pluvia::Error naming `source` when the JSON is not a valid library.
gpu::StrokeAtlas strokeAtlasFromJson(const nlohmann::json& json, const std::string& source);

}  // namespace pluvia::rain
