#include "rain/wet_ground.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "image/luminance.h"
#include "optics/fresnel.h"
#include "optics/wet_surface.h"
#include "rain/depth_surface.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

// Three depths lie on one plane when 1 / z's second difference is under this share of its first.
constexpr double kPlanarity = 0.1;
constexpr int kMaterialPx = 15;

}  // namespace

std::vector<float> wetGroundWeights(const Camera& camera, const std::vector<float>& depth,
                                    double fullTiltDeg, double fadeDeg) {
  const int w = camera.width, h = camera.height;
  std::vector<float> weights(depth.size(), 0.0f);
  const double full = std::cos(fullTiltDeg * M_PI / 180.0);
  const double none = std::cos(std::min(fullTiltDeg + fadeDeg, 90.0) * M_PI / 180.0);
  forEachRow(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const double z = depth[i];
      if (!(std::isfinite(z) && z > 0.0)) continue;
      // The neighbour on either side that continues the surface (the right one first), or, at
      // grazing angles where depth grows faster than that from pixel to pixel, both when 1 / z
      // runs straight through the three (on a plane 1 / z is affine in the image).
      auto along = [&](int dx, int dy, Eigen::Vector3d& edge) {
        auto depthAt = [&](int s) {
          const int nx = x + s * dx, ny = y + s * dy;
          return nx < 0 || ny < 0 || nx >= w || ny >= h
                     ? std::numeric_limits<double>::quiet_NaN()
                     : double(depth[size_t(ny) * size_t(w) + size_t(nx)]);
        };
        auto point = [&](int s, double zs) {
          return worldPoint(camera, x + s * dx + 0.5, y + s * dy + 0.5, zs);
        };
        const double after = depthAt(1), before = depthAt(-1);
        if (depthsContinuous(z, after)) return edge = point(1, after) - point(0, z), true;
        if (depthsContinuous(z, before)) return edge = point(0, z) - point(-1, before), true;
        const bool finite =
            std::isfinite(after) && std::isfinite(before) && after > 0.0 && before > 0.0;
        if (finite && std::abs(1.0 / after + 1.0 / before - 2.0 / z) <=
                          kPlanarity * std::abs(1.0 / after - 1.0 / before))
          return edge = 0.5 * (point(1, after) - point(-1, before)), true;
        return false;
      };
      Eigen::Vector3d ex, ey;
      if (!along(1, 0, ex) || !along(0, 1, ey)) continue;
      Eigen::Vector3d n = ex.cross(ey);
      const double length = n.norm();
      if (!(length > 0.0)) continue;
      n /= length;
      // The face the camera sees.
      if (n.dot(camera.positionMeters - worldPoint(camera, x + 0.5, y + 0.5, z)) < 0.0) n = -n;
      weights[i] = float(std::clamp((n.y() - none) / std::max(full - none, 1e-9), 0.0, 1.0));
    }
  });
  return weights;
}

std::array<double, 3> levelIrradiance(const EquirectMap& environment) {
  // Each row's cosine-weighted solid angle exactly: the integral of cos(theta) over the row's band
  // of polar angles [theta0, theta1] (above the horizon), (cos^2 theta0 - cos^2 theta1) / 2, times
  // its texel's azimuth 2 pi / width.
  std::array<double, 3> sum{0, 0, 0};
  for (int y = 0; y < environment.height; ++y) {
    const double up0 = std::cos(M_PI * y / environment.height);
    const double up1 = std::max(0.0, std::cos(M_PI * (y + 1) / environment.height));
    if (up0 <= 0.0) break;
    const double weight = 0.5 * (up0 * up0 - up1 * up1) * 2.0 * M_PI / environment.width;
    for (int x = 0; x < environment.width; ++x) {
      const float* texel = environment.texel(x, y);
      for (size_t c = 0; c < 3; ++c) sum[c] += texel[c] * weight;
    }
  }
  return sum;
}

double filmCoverage(const float* rgb) {
  const double high = std::max({rgb[0], rgb[1], rgb[2]}), low = std::min({rgb[0], rgb[1], rgb[2]});
  if (!(high > 0.0)) return 1.0;
  return std::clamp(1.0 - (high - std::max(low, 0.0)) / high / kSoakingSaturation, 0.0, 1.0);
}

LevelFilmView levelFilmView(const Camera& camera, const std::vector<float>& weights,
                            const WetGroundLight& light, double eta) {
  LevelFilmView view;
  view.reflectance.assign(weights.size(), 0.0f);
  view.mirrored.assign(weights.size(), {0.0f, 0.0f, 0.0f});
  forEachRow(camera.height, [&](int y) {
    for (int x = 0; x < camera.width; ++x) {
      const size_t i = size_t(y) * size_t(camera.width) + size_t(x);
      if (weights[i] <= 0.0f) continue;
      const Eigen::Vector3d ray =
          (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
      view.reflectance[i] = float(optics::fresnelReflectance(std::abs(ray.y()), eta));
      view.mirrored[i] =
          sampleEquirect(light.gloss, float(ray.x()), float(std::abs(ray.y())), float(ray.z()));
    }
  });
  return view;
}

void wetGround(Image& image, const std::vector<float>& weights, const LevelFilmView& view,
               double wetness, double gloss, const WetGroundLight& light, double eta) {
  const optics::WetFilm water = optics::wetFilm(eta);
  const double irradiance = rec709Luminance(light.irradiance);
  // The material is a region's, not a pixel's: the colour is taken over kMaterialPx around each
  // pixel, so the grey blades in a lawn's texture do not glitter.
  cv::Mat local;
  if (gloss > 0.0)
    cv::blur(image.rgbaMat(), local, cv::Size(kMaterialPx, kMaterialPx), cv::Point(-1, -1),
             cv::BORDER_REFLECT);
  forEachRow(image.height, [&](int y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t i = size_t(y) * size_t(image.width) + size_t(x);
      const double weight = wetness * weights[i];
      if (weight <= 0.0) continue;
      const double r = view.reflectance[i];
      float* rgb = image.pixel(x, y);
      const double film = gloss > 0.0 ? filmCoverage(local.ptr<float>(y) + size_t(x) * 4) : 0.0;
      for (size_t c = 0; c < 3; ++c) {
        const double dry = std::max(0.0f, rgb[c]);
        // The albedo per channel, as Lekner and Dorf's is per wavelength, pi L / E against the
        // irradiance's luminance: the light taken as white, as the camera balanced it. The
        // environment's own colour would take its tint for the ground's, and one without the
        // plate's sun (a blue sky alone) would turn sunlit stone red. A channel's darker
        // albedo darkens more under the film, so wet grass and brick gain saturation. Over 1 the
        // pixel is lit by more than the environment holds (a sun it leaves out, a lamp): taken
        // as 1, the film darkens it least.
        const double albedo = irradiance > 0.0 ? std::min(1.0, M_PI * dry / irradiance) : 1.0;
        const double ratio = optics::wetRadianceRatioAt(water, albedo, r);
        const double wet = dry * ratio + gloss * film * r * view.mirrored[i][c];
        rgb[c] = float(rgb[c] + weight * (wet - rgb[c]));
      }
    }
  });
}

}  // namespace pluvia::rain
