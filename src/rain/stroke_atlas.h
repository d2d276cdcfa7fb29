#pragma once
// What is computed from a stroke atlas alone, without the library's files: its mean matte, the
// quad scales the renderer draws it with, and the atlas as one JSON value for the cache (and
// for pluvia-bench-strokes, which runs without pluvia's image I/O).
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rain/streak_types.h"

namespace pluvia::rain {

// Mean matte value over all strokes' rectangles (1 for an empty atlas).
double meanMatte(const StrokeAtlas& atlas);

// Per stroke, how much larger than the matte's own equivalent width and length (half-maximum,
// rain/stroke_profile.h) its rectangle is: {across, along}. A matte cut from footage keeps its
// soft sides and ends, so its rectangle is wider and longer than the stroke it holds; the
// renderer grows each quad by these factors so that the stroke itself is the drop's streak.
// {1, 1} for an empty rectangle.
std::vector<std::array<float, 2>> strokeQuadScales(const StrokeAtlas& atlas);

// A whole atlas as one JSON value (alpha inline), for the artifact cache.
nlohmann::json strokeAtlasToJson(const StrokeAtlas& atlas);
// Throws pluvia::Error naming `source` when the JSON is not a valid atlas.
StrokeAtlas strokeAtlasFromJson(const nlohmann::json& json, const std::string& source);

}  // namespace pluvia::rain
