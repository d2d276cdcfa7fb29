#include "rain/splatter.h"

#include <algorithm>
#include <cmath>

#include "rain/counter_stream.h"
#include "rain/splash_draw.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

// The texture's shape, in drop diameters (splatter.h).
constexpr double kCoreRadius = 1.2, kRayHalfWidth = 0.2, kRayMin = 2.5, kRayMax = 4.0;
constexpr double kTipRadius = 0.3, kTipGap = 0.3;
constexpr int kMaxRays = 8;
static_assert(kRayMax + kTipGap + 2.0 * kTipRadius < kSplatterReachPerDiameter);
constexpr uint64_t kSplatterSalt = 0x5b1a77e5ULL;  // a stream apart from the droplets'
constexpr int kBandRows = 32;                      // rows drawn by one task (splash_draw.cpp)

struct Shape {
  int rays = 0;
  std::array<double, kMaxRays> cosAngle{}, sinAngle{}, length{};
};

Shape shapeOf(const Impact& impact) {
  Stream rng{mix(impact.key ^ kSplatterSalt)};
  Shape s;
  s.rays = 5 + int(rng.uniform() * 4.0);
  const double turn = 2.0 * M_PI * rng.uniform();
  for (int k = 0; k < s.rays; ++k) {
    const double angle = turn + 2.0 * M_PI * (k + 0.35 * (rng.uniform() - 0.5)) / s.rays;
    s.cosAngle[size_t(k)] = std::cos(angle), s.sinAngle[size_t(k)] = std::sin(angle);
    s.length[size_t(k)] = kRayMin + (kRayMax - kRayMin) * rng.uniform();
  }
  return s;
}

// Signed distance (in D) from (u, v) (in D) to the texture: negative inside.
double signedDistance(const Shape& s, double u, double v) {
  double d = std::sqrt(u * u + v * v) - kCoreRadius;
  for (int k = 0; k < s.rays; ++k) {
    const double along = u * s.cosAngle[size_t(k)] + v * s.sinAngle[size_t(k)];
    const double across = -u * s.sinAngle[size_t(k)] + v * s.cosAngle[size_t(k)];
    const double t = std::clamp(along, 0.0, s.length[size_t(k)]);
    d = std::min(d, std::hypot(along - t, across) - kRayHalfWidth);
    const double tip = s.length[size_t(k)] + kTipGap + kTipRadius;
    d = std::min(d, std::hypot(along - tip, across) - kTipRadius);
  }
  return d;
}

double opacityOf(const Shape& s, const Impact& impact, double u, double v, double blurMeters) {
  const double diameter = impact.diameterMm * 1e-3;
  const double blur = std::max(blurMeters / diameter, 1e-3);
  const double d = signedDistance(s, u / diameter, v / diameter);
  return kSplatterPeakOpacity * std::clamp(0.5 - d / blur, 0.0, 1.0);
}

struct Box {
  int x0, x1, y0, y1;
  size_t index;
  float share;
  Shape shape;
};

}  // namespace

double splatterOpacity(const Impact& impact, double u, double v, double blurMeters) {
  return opacityOf(shapeOf(impact), impact, u, v, blurMeters);
}

double splatterExposureShare(double impactSeconds, double flashSeconds, double open, double close) {
  const double overlap =
      std::min(close, impactSeconds + flashSeconds) - std::max(open, impactSeconds);
  return overlap > 0.0 && close > open ? overlap / (close - open) : 0.0;
}

void drawSplatters(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                   const Camera& camera, const std::vector<ShadedImpact>& impacts,
                   double flashSeconds, double open, double close, float opacity) {
  const int w = camera.width, h = camera.height;
  std::vector<Box> boxes(impacts.size());
  std::vector<char> seen(impacts.size(), 0);
  forEachIndex(impacts.size(), [&](size_t k) {
    const Impact& impact = *impacts[k].impact;
    const double share =
        splatterExposureShare(impact.timeSeconds, flashSeconds, open, close) * opacity;
    double px, py, z;
    if (!(share > 0.0) || !camera.project(impact.point, px, py, z)) return;
    // The texture's reach seen face on bounds its image (a flat one is foreshortened).
    const double reachPx =
        camera.focalPx * kSplatterReachPerDiameter * impact.diameterMm * 1e-3 / z;
    Box& b = boxes[k];
    b.x0 = std::max(0, int(std::floor(px - reachPx - 1.0)));
    b.x1 = std::min(w - 1, int(std::ceil(px + reachPx + 1.0)));
    b.y0 = std::max(0, int(std::floor(py - reachPx - 1.0)));
    b.y1 = std::min(h - 1, int(std::ceil(py + reachPx + 1.0)));
    b.index = k;
    b.share = float(share);
    b.shape = shapeOf(impact);
    seen[k] = b.x0 <= b.x1 && b.y0 <= b.y1;
  });
  const int bands = (h + kBandRows - 1) / kBandRows;
  std::vector<std::vector<const Box*>> inBand(static_cast<size_t>(bands));
  for (size_t k = 0; k < boxes.size(); ++k) {
    if (!seen[k]) continue;
    for (int b = boxes[k].y0 / kBandRows; b <= boxes[k].y1 / kBandRows; ++b)
      inBand[size_t(b)].push_back(&boxes[k]);
  }
  forEachIndex(bands, [&](int band) {
    const int rowLo = band * kBandRows, rowHi = std::min(h - 1, rowLo + kBandRows - 1);
    for (const Box* b : inBand[size_t(band)]) {
      const Impact& impact = *impacts[b->index].impact;
      const std::array<float, 3>& radiance = impacts[b->index].radiance;
      for (int y = std::max(b->y0, rowLo); y <= std::min(b->y1, rowHi); ++y)
        for (int x = b->x0; x <= b->x1; ++x) {
          const size_t i = size_t(y) * size_t(w) + size_t(x);
          const double z = depth[i];
          if (!std::isfinite(z) || !(z > 0.0)) continue;
          // The pixel's surface point, on the impact's horizontal plane or not drawn.
          const Eigen::Vector3d p =
              camera.positionMeters +
              camera.worldFromCamera * (camera.rayCamera(x + 0.5, y + 0.5) * z);
          if (std::abs(p.y() - impact.point.y()) > std::max(kSurfaceToleranceMeters, 0.01 * z))
            continue;
          const double o = opacityOf(b->shape, impact, p.x() - impact.point.x(),
                                     p.z() - impact.point.z(), z / camera.focalPx);
          if (!(o > 0.0)) continue;
          const float k = float(o) * b->share;
          float* rgba = image.rgba.data() + i * 4;
          for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * (1.0f - k) + radiance[size_t(c)] * k;
          alpha[i] = alpha[i] * (1.0f - k) + k;
        }
    }
  });
}

}  // namespace pluvia::rain
