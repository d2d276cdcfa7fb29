#include "rain/stroke_atlas.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "rain/stroke_profile.h"
#include "util/error.h"

namespace pluvia::rain {

double meanMatte(const StrokeAtlas& atlas) {
  double sum = 0.0;
  size_t count = 0;
  for (const auto& r : atlas.rects) {
    for (int y = int(r[1]); y < int(r[3]); ++y)
      for (int x = int(r[0]); x < int(r[2]); ++x) {
        sum += atlas.alpha[size_t(y) * atlas.width + x];
        ++count;
      }
  }
  return count && sum > 0 ? sum / double(count) : 1.0;
}

std::vector<std::array<float, 2>> strokeQuadScales(const StrokeAtlas& atlas) {
  std::vector<std::array<float, 2>> scales;
  scales.reserve(atlas.rects.size());
  for (const auto& r : atlas.rects) {
    const int x0 = int(r[0]), y0 = int(r[1]), cols = int(r[2]) - x0, rows = int(r[3]) - y0;
    const StrokeProfile profile = cols > 0 && rows > 0
                                      ? strokeProfile(&atlas.alpha[size_t(y0) * atlas.width + x0],
                                                      size_t(atlas.width), cols, rows)
                                      : StrokeProfile{};
    if (profile.widthPx <= 0.0 || profile.lengthPx <= 0.0) {
      scales.push_back({1.0f, 1.0f});
      continue;
    }
    // Never smaller than the rectangle: a matte is not cropped.
    scales.push_back({float(std::max(1.0, cols / profile.widthPx)),
                      float(std::max(1.0, rows / profile.lengthPx))});
  }
  return scales;
}

nlohmann::json strokeAtlasToJson(const StrokeAtlas& atlas) {
  return {{"width", atlas.width},
          {"height", atlas.height},
          {"alpha", atlas.alpha},
          {"rects", atlas.rects}};
}

StrokeAtlas strokeAtlasFromJson(const nlohmann::json& json, const std::string& source) {
  StrokeAtlas atlas;
  try {
    atlas.width = json.at("width").get<int>();
    atlas.height = json.at("height").get<int>();
    atlas.alpha = json.at("alpha").get<std::vector<float>>();
    atlas.rects = json.at("rects").get<std::vector<std::array<float, 4>>>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("not a stroke atlas: ") + e.what(), {"rain", {}, source});
  }
  if (atlas.width <= 0 || atlas.height <= 0 ||
      atlas.alpha.size() != size_t(atlas.width) * atlas.height || atlas.rects.empty()) {
    throw Error("stroke atlas is empty or inconsistent", {"rain", {}, source});
  }
  for (size_t i = 0; i < atlas.rects.size(); ++i) {
    const auto& r = atlas.rects[i];
    if (!(r[0] >= 0 && r[1] >= 0 && r[0] < r[2] && r[1] < r[3] && r[2] <= atlas.width &&
          r[3] <= atlas.height)) {
      throw Error(fmt::format("stroke atlas: stroke {} lies outside the {}x{} atlas", i,
                              atlas.width, atlas.height),
                  {"rain", {}, source});
    }
  }
  return atlas;
}

}  // namespace pluvia::rain
