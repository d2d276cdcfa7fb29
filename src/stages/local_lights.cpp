#include "stages/local_lights.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace pluvia {
namespace {

constexpr int kTilePx = 16;
// A lit tile is interpolated from its corners when its depth varies by under 5 % and its corner
// glows by under 10 % (addHalos).
constexpr double kSmoothDepth = 0.05;
constexpr double kSmoothGlow = 0.1;

optics::Vec3 unitRay(const Camera& camera, double px, double py, double& lengthPerDepth) {
  const Eigen::Vector3d r = camera.rayCamera(px, py);
  lengthPerDepth = r.norm();  // r has z = -1: the ray's length per metre of z-depth
  const Eigen::Vector3d u = r / lengthPerDepth;
  return {u.x(), u.y(), u.z()};
}

double maxChannel(const std::array<double, 3>& rgb) {
  return std::max({rgb[0], rgb[1], rgb[2]});
}

}  // namespace

std::vector<FrameLight> lightsAtFrame(const LightsSettings& settings, const Camera& camera,
                                      double frame) {
  std::vector<FrameLight> out;
  const Eigen::Matrix3d cameraFromWorld = camera.worldFromCamera.transpose();
  for (size_t i = 0; i < settings.lights.size(); ++i) {
    const LightSpec& spec = settings.lights[i];
    FrameLight light;
    Eigen::Vector3d position(spec.xMeters.valueAt(frame), spec.yMeters.valueAt(frame),
                             spec.zMeters.valueAt(frame));
    Eigen::Vector3d axis(spec.direction[0], spec.direction[1], spec.direction[2]);
    if (spec.worldFrame) {
      position = cameraFromWorld * (position - camera.positionMeters);
      axis = cameraFromWorld * axis;
    }
    const double intensity = spec.intensity.valueAt(frame);
    for (int c = 0; c < 3; ++c) light.rgbIntensity[size_t(c)] = intensity * spec.rgb[size_t(c)];
    light.positionMeters = {position.x(), position.y(), position.z()};
    light.radiusMeters = spec.radiusMeters;
    if (spec.spot) {
      if (!(axis.norm() > 1e-9))
        throw Error(fmt::format("lights.list[{}]: a spot's axis (dir_x, dir_y, dir_z) = ({}, {}, "
                                "{}) has no length",
                                i, spec.direction[0], spec.direction[1], spec.direction[2]),
                    {"lights"});
      axis.normalize();
      light.spot = true;
      light.axis = {axis.x(), axis.y(), axis.z()};
      light.cosHalfAngle = std::cos(spec.halfAngleDeg.valueAt(frame) * M_PI / 180.0);
      light.falloffQ = spec.falloffQ;
    }
    out.push_back(light);
  }
  return out;
}

optics::LocalLight localLight(const FrameLight& light) {
  optics::LocalLight l;
  l.positionMeters = light.positionMeters;
  l.radiusMeters = light.radiusMeters;
  l.spot = light.spot;
  l.axis = light.axis;
  l.cosHalfAngle = light.cosHalfAngle;
  l.q = light.falloffQ;
  return l;
}

double spotFactor(const FrameLight& light, double cosTheta) {
  if (!light.spot) return 1.0;
  if (cosTheta < light.cosHalfAngle) return 0.0;
  const double span = 1.0 - light.cosHalfAngle;
  // A cone of A -> 0: only its axis is lit, at full intensity.
  const double t = span > 1e-12 ? std::min(1.0, (cosTheta - light.cosHalfAngle) / span) : 1.0;
  return (1.0 - light.falloffQ) * t + light.falloffQ;
}

HaloResult addHalos(Image& image, const Camera& camera, const std::vector<FrameLight>& lights,
                    double betaPerMeter, const optics::ScatteringTables& tables,
                    double thresholdRadiance) {
  HaloResult result;
  // The lights AOV (--aov lights): the light added, alone; its alpha stays 0 (light adds, it
  // covers nothing).
  std::array<std::vector<float>*, 3> aov{&image.plane("lights.R"), &image.plane("lights.G"),
                                         &image.plane("lights.B")};
  image.plane("lights.A");
  if (lights.empty() || !(betaPerMeter > 0.0)) return result;
  const int width = image.width, height = image.height;
  const int tilesX = (width + kTilePx - 1) / kTilePx, tilesY = (height + kTilePx - 1) / kTilePx;
  const std::vector<float>* depth = image.findPlane("depth");
  std::atomic<size_t> evaluations{0};
  for (const FrameLight& frameLight : lights) {
    const optics::LocalLight light = localLight(frameLight);
    const double scale = maxChannel(frameLight.rgbIntensity);
    if (!(scale > 0.0)) {
      ++result.culled;
      continue;
    }
    // The unoccluded glow at the tile corners: an upper bound of what the pixels get.
    std::vector<uint8_t> cornerLit(static_cast<size_t>((tilesX + 1) * (tilesY + 1)), 0);
    tbb::parallel_for(0, tilesY + 1, [&](int ty) {
      for (int tx = 0; tx <= tilesX; ++tx) {
        double lengthPerDepth;
        const optics::Vec3 ray = unitRay(camera, std::min(tx * kTilePx, width),
                                         std::min(ty * kTilePx, height), lengthPerDepth);
        const double glow =
            scale * optics::inscatteredRadiance(tables, light, ray, HUGE_VAL, betaPerMeter);
        cornerLit[static_cast<size_t>(ty * (tilesX + 1) + tx)] = glow >= thresholdRadiance;
      }
    });
    // The tile holding the light's own image is always evaluated (its peak is between corners).
    int lightTileX = -10, lightTileY = -10;
    if (frameLight.positionMeters[2] < 0.0) {
      const double z = -frameLight.positionMeters[2];
      const double px = camera.cx + camera.focalPx * frameLight.positionMeters[0] / z;
      const double py = camera.cy - camera.focalPx * frameLight.positionMeters[1] / z;
      if (std::abs(px) < 1e7 && std::abs(py) < 1e7) {
        lightTileX = int(std::floor(px / kTilePx));
        lightTileY = int(std::floor(py / kTilePx));
      }
    }
    std::vector<uint8_t> tileLit(static_cast<size_t>(tilesX * tilesY), 0);
    bool any = false;
    for (int ty = 0; ty < tilesY; ++ty) {
      for (int tx = 0; tx < tilesX; ++tx) {
        bool lit = std::abs(tx - lightTileX) <= 1 && std::abs(ty - lightTileY) <= 1;
        // The corners of this tile and of its 8 neighbours.
        for (int cy = std::max(0, ty - 1); cy <= std::min(tilesY, ty + 2) && !lit; ++cy)
          for (int cx = std::max(0, tx - 1); cx <= std::min(tilesX, tx + 2) && !lit; ++cx)
            lit = cornerLit[static_cast<size_t>(cy * (tilesX + 1) + cx)] != 0;
        tileLit[static_cast<size_t>(ty * tilesX + tx)] = lit;
        any = any || lit;
      }
    }
    bool cornerAny = std::any_of(cornerLit.begin(), cornerLit.end(), [](uint8_t v) { return v; });
    if (!cornerAny) {
      // Not even near its own image: the light's glow is invisible here.
      ++result.culled;
      continue;
    }
    if (!any) continue;
    auto glowAt = [&](double px, double py, double z) {
      double lengthPerDepth;
      const optics::Vec3 ray = unitRay(camera, px, py, lengthPerDepth);
      const double length = std::isfinite(z) && z > 0.0 ? z * lengthPerDepth : HUGE_VAL;
      return optics::inscatteredRadiance(tables, light, ray, length, betaPerMeter);
    };
    auto add = [&](size_t pixel, double glow) {
      if (!(glow > 0.0)) return;
      for (int c = 0; c < 3; ++c) {
        const float value = float(glow * frameLight.rgbIntensity[size_t(c)]);
        image.rgba[pixel * 4 + size_t(c)] += value;
        (*aov[size_t(c)])[pixel] += value;
      }
    };
    tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
      if (!tileLit[static_cast<size_t>(tile)]) return;
      const int tx = tile % tilesX, ty = tile / tilesX;
      const int x0 = tx * kTilePx, y0 = ty * kTilePx;
      const int x1 = std::min(width, x0 + kTilePx), y1 = std::min(height, y0 + kTilePx);
      auto zAt = [&](int x, int y) {
        return depth ? double((*depth)[static_cast<size_t>(y) * width + x]) : HUGE_VAL;
      };
      // A smooth tile is interpolated from its corner pixels: its depth varies by under
      // kSmoothDepth and its corners' glow by under kSmoothGlow, so the glow inside is bilinear
      // to well under 1 % (a tile is 16 px; a glow varying that little across it is many tiles
      // wide). Near the light's own image, at depth edges and where the glow turns fast, every
      // pixel is evaluated.
      bool smooth = (std::abs(tx - lightTileX) > 1 || std::abs(ty - lightTileY) > 1) &&
                    x1 - x0 > 1 && y1 - y0 > 1;
      double zMin = HUGE_VAL, zMax = 0.0;
      for (int y = y0; y < y1 && smooth; ++y)
        for (int x = x0; x < x1; ++x) {
          const double z = zAt(x, y);
          zMin = std::min(zMin, z);
          zMax = std::max(zMax, z);
        }
      if (smooth && std::isfinite(zMax)) smooth = zMax <= zMin * (1.0 + kSmoothDepth);
      if (smooth && !std::isfinite(zMax)) smooth = !std::isfinite(zMin);  // all sky
      std::array<double, 4> corner{};
      if (smooth) {
        const int xs[2] = {x0, x1 - 1}, ys[2] = {y0, y1 - 1};
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i)
            corner[size_t(j * 2 + i)] = glowAt(xs[i] + 0.5, ys[j] + 0.5, zAt(xs[i], ys[j]));
        const auto [lo, hi] = std::minmax_element(corner.begin(), corner.end());
        smooth = *hi <= *lo * (1.0 + kSmoothGlow);
      }
      size_t done = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const size_t pixel = static_cast<size_t>(y) * width + x;
          if (smooth) {
            const double u = double(x - x0) / (x1 - 1 - x0), v = double(y - y0) / (y1 - 1 - y0);
            add(pixel, (1 - v) * ((1 - u) * corner[0] + u * corner[1]) +
                           v * ((1 - u) * corner[2] + u * corner[3]));
          } else {
            add(pixel, glowAt(x + 0.5, y + 0.5, zAt(x, y)));
            ++done;
          }
        }
      evaluations += smooth ? 4 : done;
    });
  }
  result.pixelsLit = evaluations.load();
  return result;
}

std::array<float, 3> dropLocalRadiance(const optics::TransferTable& transfer,
                                       const std::vector<FrameLight>& lights, double betaPerMeter,
                                       const std::array<double, 3>& drop,
                                       const std::array<double, 3>& view) {
  std::array<double, 3> sum{0, 0, 0};
  for (const FrameLight& light : lights) {
    const std::array<double, 3> w{light.positionMeters[0] - drop[0],
                                  light.positionMeters[1] - drop[1],
                                  light.positionMeters[2] - drop[2]};
    const double distance = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    // Inside the bulb the irradiance stays that of its surface.
    const double d = std::max(distance, light.radiusMeters);
    double cosView = 1.0, cosSpot = 1.0;
    if (distance > 0.0) {
      cosView = (view[0] * w[0] + view[1] * w[1] + view[2] * w[2]) / distance;
      // The spot's theta: between its axis and the light -> drop direction, -w.
      cosSpot = -(light.axis[0] * w[0] + light.axis[1] * w[1] + light.axis[2] * w[2]) / distance;
    }
    const double cone = spotFactor(light, cosSpot);
    if (cone <= 0.0) continue;
    const double irradiancePerIntensity = cone * std::exp(-betaPerMeter * d) / (d * d);
    const double D = transfer.at(std::clamp(cosView, -1.0, 1.0));
    for (int c = 0; c < 3; ++c)
      sum[size_t(c)] += D * irradiancePerIntensity * light.rgbIntensity[size_t(c)];
  }
  // Float's range bounds it (an intensity of 1e9 at the bulb's surface).
  return {float(std::min(sum[0], 1e30)), float(std::min(sum[1], 1e30)),
          float(std::min(sum[2], 1e30))};
}

}  // namespace pluvia
