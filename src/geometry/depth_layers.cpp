#include "geometry/depth_layers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "util/error.h"

namespace pluvia {

namespace {
using nlohmann::json;
using PixelPoint = std::array<double, 2>;

struct PixelRect {
  int x0, x1, y0, y1;  // half-open
};

// The message names the layer; the context carries the frame ("[depth @ frame 12] ...").
std::string layerName(size_t index) {
  return "depth layer " + std::to_string(index);
}
ErrorContext layerContext(double frame) {
  return {"depth", static_cast<int64_t>(std::llround(frame)), {}};
}

// A layer's field at `frame`: a plain number, keyframes through `numberAt`, or `fallback` when the
// field is absent (or null: an optional field the preset left out).
double fieldAt(const json& layer, const char* key, double fallback, double frame,
               const KeyedNumberAt& numberAt, size_t index) {
  if (!layer.contains(key) || layer[key].is_null()) return fallback;
  const json& value = layer[key];
  if (value.is_number()) return value.get<double>();
  if (!numberAt)
    throw Error(layerName(index) + ": '" + key + "' is keyframed but no keyframe reader was given",
                layerContext(frame));
  return numberAt(value, frame);
}

PixelRect rectAt(const Camera& camera, const json& layer, double frame,
                 const KeyedNumberAt& numberAt, size_t index) {
  auto edge = [&](const char* key, double fallback, int size) {
    double f = fieldAt(layer, key, fallback, frame, numberAt, index);
    return static_cast<int>(std::lround(std::clamp(f, 0.0, 1.0) * size));
  };
  return {edge("x0", 0.0, camera.width), edge("x1", 1.0, camera.width),
          edge("y0", 0.0, camera.height), edge("y1", 1.0, camera.height)};
}

PixelPoint pointOf(const json& point, const Camera& camera, size_t index, double frame) {
  if (!point.is_array() || point.size() != 2 || !point[0].is_number() || !point[1].is_number())
    throw Error(layerName(index) + ": a point is not [x, y] (got " + point.dump() + ")",
                layerContext(frame));
  return {point[0].get<double>() * camera.width, point[1].get<double>() * camera.height};
}

std::vector<PixelPoint> staticPoints(const json& points, const Camera& camera, size_t index,
                                     double frame) {
  std::vector<PixelPoint> pixels;
  for (const auto& p : points) pixels.push_back(pointOf(p, camera, index, frame));
  return pixels;
}

// "points" at a frame, in pixels: [[x, y], ...] or keys [{"frame": F, "points": [...]}, ...].
std::vector<PixelPoint> pointsAt(const Camera& camera, const json& points, double frame,
                                 size_t index) {
  if (!points.is_array() || points.empty())
    throw Error(layerName(index) + ": \"points\" must be a list of [x, y] or of keys",
                layerContext(frame));
  std::vector<PixelPoint> pixels;
  if (!points[0].is_object()) {
    pixels = staticPoints(points, camera, index, frame);
  } else {
    auto keyFrame = [&](const json& key) {
      if (!key.is_object() || !key.contains("frame") || !key["frame"].is_number() ||
          !key.contains("points"))
        throw Error(layerName(index) + ": a points key is not {\"frame\": F, \"points\": [...]}",
                    layerContext(frame));
      return key["frame"].get<double>();
    };
    size_t next = 0;  // first key after `frame`
    while (next < points.size() && keyFrame(points[next]) <= frame) ++next;
    if (next == 0 || next == points.size()) {
      pixels = staticPoints(points[next == 0 ? 0 : next - 1]["points"], camera, index, frame);
    } else {
      const json& before = points[next - 1];
      const json& after = points[next];
      const double t = (frame - keyFrame(before)) / (keyFrame(after) - keyFrame(before));
      std::vector<PixelPoint> a = staticPoints(before["points"], camera, index, frame);
      std::vector<PixelPoint> b = staticPoints(after["points"], camera, index, frame);
      if (a.size() != b.size())
        throw Error(layerName(index) + ": points keys have different numbers of points",
                    layerContext(frame));
      for (size_t i = 0; i < a.size(); ++i)
        pixels.push_back({a[i][0] + t * (b[i][0] - a[i][0]), a[i][1] + t * (b[i][1] - a[i][1])});
    }
  }
  if (pixels.size() < 3)
    throw Error(layerName(index) + ": a polygon needs at least 3 points", layerContext(frame));
  return pixels;
}

// Even-odd fill at pixel centres; `depthAtRow(yCentre)` gives the value for a row. A centre on a
// left edge is inside and on a right edge outside; an edge's lower end point (larger y) is
// excluded, so a vertex shared by two edges is counted once.
template <typename DepthAtRow>
void fillPolygon(std::vector<float>& depth, const Camera& camera,
                 const std::vector<PixelPoint>& polygon, DepthAtRow depthAtRow) {
  double top = polygon[0][1], bottom = polygon[0][1];
  for (const auto& p : polygon) {
    top = std::min(top, p[1]);
    bottom = std::max(bottom, p[1]);
  }
  const int firstRow = std::max(0, static_cast<int>(std::ceil(top - 0.5)));
  const int lastRow = std::min(camera.height - 1, static_cast<int>(std::ceil(bottom - 0.5)) - 1);
  std::vector<double> crossings;
  for (int y = firstRow; y <= lastRow; ++y) {
    const double yc = y + 0.5;
    crossings.clear();
    for (size_t i = 0; i < polygon.size(); ++i) {
      const PixelPoint& a = polygon[i];
      const PixelPoint& b = polygon[(i + 1) % polygon.size()];
      if ((a[1] <= yc && yc < b[1]) || (b[1] <= yc && yc < a[1]))
        crossings.push_back(a[0] + (yc - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
    }
    std::sort(crossings.begin(), crossings.end());
    const float value = depthAtRow(yc);
    for (size_t i = 0; i + 1 < crossings.size(); i += 2) {
      // Pixel x is inside when crossings[i] <= x + 0.5 < crossings[i + 1].
      const int x0 = std::max(0, static_cast<int>(std::ceil(crossings[i] - 0.5)));
      const int x1 = std::min(camera.width, static_cast<int>(std::ceil(crossings[i + 1] - 0.5)));
      for (int x = x0; x < x1; ++x) depth[static_cast<size_t>(y) * camera.width + x] = value;
    }
  }
}

// The keys of a keyframed number, or null when `value` is a plain number.
const json* keysOf(const json& value) {
  if (value.is_object() && value.contains("keys")) return &value["keys"];
  if (value.is_array()) return &value;
  return nullptr;
}
}  // namespace

std::vector<float> rasterizeDepthLayers(const Camera& camera, const nlohmann::json& layers,
                                        double frame, const KeyedNumberAt& numberAt) {
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
          depth[static_cast<size_t>(y) * camera.width + x] =
              static_cast<float>(heightMeters / -rayWorld.y());
        }
      }
    } else if ((type == "sky" && layer.contains("points") && !layer["points"].is_null()) ||
               type == "polygon") {
      if (!layer.contains("points"))
        throw Error(layerName(index) + ": a polygon needs \"points\"", layerContext(frame));
      const std::vector<PixelPoint> polygon = pointsAt(camera, layer["points"], frame, index);
      if (type == "sky") {
        fillPolygon(depth, camera, polygon, [&](double) { return sky; });
        continue;
      }
      const double nearTop = fieldAt(layer, "depth_m", 10.0, frame, numberAt, index);
      const double atBottom = fieldAt(layer, "depth_bottom_m", nearTop, frame, numberAt, index);
      double top = polygon[0][1], bottom = polygon[0][1];
      for (const auto& p : polygon) {
        top = std::min(top, p[1]);
        bottom = std::max(bottom, p[1]);
      }
      fillPolygon(depth, camera, polygon, [&](double yc) {
        const double t = bottom > top ? std::clamp((yc - top) / (bottom - top), 0.0, 1.0) : 0.0;
        return static_cast<float>(nearTop + t * (atBottom - nearTop));
      });
    } else if (type == "card" || type == "sky") {
      PixelRect r = rectAt(camera, layer, frame, numberAt, index);
      float value =
          type == "sky"
              ? sky
              : static_cast<float>(fieldAt(layer, "distance_m", 10.0, frame, numberAt, index));
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) depth[static_cast<size_t>(y) * camera.width + x] = value;
    } else {
      throw Error("depth layer " + std::to_string(index) + " has unknown type '" + type + "'",
                  layerContext(frame));
    }
  }
  return depth;
}

bool depthLayersHaveGround(const nlohmann::json& layers) {
  for (const auto& layer : layers)
    if (layer.is_object() && layer.value("type", "") == "ground") return true;
  return false;
}

bool depthLayersAnimated(const nlohmann::json& layers) {
  for (const auto& layer : layers) {
    if (!layer.is_object()) continue;
    for (auto it = layer.begin(); it != layer.end(); ++it) {
      if (it.key() == "points") {
        const json& points = it.value();
        if (!points.is_array() || points.empty() || !points[0].is_object()) continue;
        for (size_t i = 1; i < points.size(); ++i)
          if (points[i].value("points", json()) != points[0].value("points", json())) return true;
        continue;
      }
      const json* keys = keysOf(it.value());
      if (!keys) continue;
      for (size_t i = 1; i < keys->size(); ++i)
        if ((*keys)[i].size() == 2 && (*keys)[0].size() == 2 && (*keys)[i][1] != (*keys)[0][1])
          return true;
    }
  }
  return false;
}

}  // namespace pluvia
