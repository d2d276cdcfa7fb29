#include "geometry/depth_layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/error.h"

namespace pluvia {

namespace {
struct PixelRect {
  int x0, x1, y0, y1;  // half-open
};

PixelRect rectOf(const Camera& camera, const nlohmann::json& layer) {
  auto edge = [&](const char* key, double fallback, int size) {
    double f = layer.value(key, fallback);
    return static_cast<int>(std::lround(std::clamp(f, 0.0, 1.0) * size));
  };
  return {edge("x0", 0.0, camera.width), edge("x1", 1.0, camera.width), edge("y0", 0.0, camera.height),
          edge("y1", 1.0, camera.height)};
}
}  // namespace

std::vector<float> rasterizeDepthLayers(const Camera& camera, const nlohmann::json& layers) {
  const float sky = std::numeric_limits<float>::infinity();
  std::vector<float> depth(static_cast<size_t>(camera.width) * camera.height, sky);
  for (size_t index = 0; index < layers.size(); ++index) {
    const auto& layer = layers[index];
    const std::string type = layer.value("type", "");
    if (type == "ground") {
      const double heightMeters = camera.positionMeters.y();
      for (int y = 0; y < camera.height; ++y) {
        for (int x = 0; x < camera.width; ++x) {
          Eigen::Vector3d rayWorld = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
          if (rayWorld.y() >= -1e-9) continue;  // at or above the horizon
          // rayCamera has z = -1, so the ray parameter is the z-depth itself.
          depth[static_cast<size_t>(y) * camera.width + x] = static_cast<float>(heightMeters / -rayWorld.y());
        }
      }
    } else if (type == "card" || type == "sky") {
      PixelRect r = rectOf(camera, layer);
      float value = type == "sky" ? sky : static_cast<float>(layer.value("distance_m", 10.0));
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) depth[static_cast<size_t>(y) * camera.width + x] = value;
    } else {
      throw Error("depth layer " + std::to_string(index) + " has unknown type '" + type + "'", {"depth"});
    }
  }
  return depth;
}

}  // namespace pluvia
