#include "rain/stroke_library.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"
#include "util/hash.h"

namespace pluvia::rain {

gpu::StrokeAtlas makeAnalyticStrokes(int count, uint64_t seed) {
  const int cellWidth = 8;
  const int cellHeight = 64;
  gpu::StrokeAtlas atlas;
  atlas.width = cellWidth * count;
  atlas.height = cellHeight;
  atlas.alpha.assign(static_cast<size_t>(atlas.width) * atlas.height, 0.0f);
  for (int s = 0; s < count; ++s) {
    CounterRng rng(seed, static_cast<uint64_t>(s));
    const double sigma = 0.16 + 0.06 * rng.uniform();      // cross-section, fraction of the width
    const double taper = 0.08 + 0.12 * rng.uniform();      // length of each soft end, fraction
    const double phase = 2.0 * M_PI * rng.uniform();
    const double ripple = 0.15 * rng.uniform();            // brightness variation along the stroke
    for (int y = 0; y < cellHeight; ++y) {
      const double v = (y + 0.5) / cellHeight;
      const double ends = std::clamp(std::min(v, 1.0 - v) / taper, 0.0, 1.0);
      const double along = ends * ends * (3.0 - 2.0 * ends) * (1.0 - ripple + ripple * std::sin(phase + 9.0 * v));
      for (int x = 0; x < cellWidth; ++x) {
        const double u = (x + 0.5) / cellWidth - 0.5;
        const double across = std::exp(-0.5 * u * u / (sigma * sigma));
        atlas.alpha[static_cast<size_t>(y) * atlas.width + s * cellWidth + x] = static_cast<float>(across * along);
      }
    }
    atlas.rects.push_back({float(s * cellWidth), 0.0f, float((s + 1) * cellWidth), float(cellHeight)});
  }
  return atlas;
}

double meanMatte(const gpu::StrokeAtlas& atlas) {
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

nlohmann::json strokeAtlasToJson(const gpu::StrokeAtlas& atlas) {
  return {{"width", atlas.width}, {"height", atlas.height}, {"alpha", atlas.alpha}, {"rects", atlas.rects}};
}

gpu::StrokeAtlas strokeAtlasFromJson(const nlohmann::json& json, const std::string& source) {
  gpu::StrokeAtlas atlas;
  try {
    atlas.width = json.at("width").get<int>();
    atlas.height = json.at("height").get<int>();
    atlas.alpha = json.at("alpha").get<std::vector<float>>();
    atlas.rects = json.at("rects").get<std::vector<std::array<float, 4>>>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("not a stroke library: ") + e.what(), {"rain", {}, source});
  }
  if (atlas.width <= 0 || atlas.height <= 0 || atlas.alpha.size() != size_t(atlas.width) * atlas.height ||
      atlas.rects.empty()) {
    throw Error("stroke library has an empty or inconsistent atlas", {"rain", {}, source});
  }
  return atlas;
}

}  // namespace pluvia::rain
