#include "rain/ripple_field.h"

#include <algorithm>
#include <cmath>

#include "optics/fresnel.h"
#include "rain/depth_surface.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

constexpr double kWaterIndex = 1.333;
constexpr double kPacketReach = 4.0;  // the slope's reach, in packet half widths (ripples.cpp)
constexpr int kBandRows = 16;         // rows drawn by one task

struct RingBox {
  const Impact* impact;
  RippleRing ring;
  int x0, x1, y0, y1;
};

}  // namespace

double rippleReachMeters(const Camera& camera) {
  const double halfPacket = 0.5 * M_PI / minPhaseSpeedWavenumber();
  return camera.focalPx * halfPacket;
}

void addRippleSlopes(const Camera& camera, const std::vector<float>& depth,
                     const std::vector<uint8_t>& water, const std::vector<const Impact*>& rings,
                     double timeSeconds, std::vector<float>& slopeX, std::vector<float>& slopeZ) {
  const int w = camera.width, h = camera.height;
  // Each ring's pixel box: its outer circle's points projected.
  std::vector<RingBox> boxes;
  for (const Impact* impact : rings) {
    const RippleRing ring = rippleRing(*impact, timeSeconds - impact->timeSeconds);
    if (!(ring.amplitudeMeters > 0.0)) continue;
    const double outer = ring.radiusMeters + kPacketReach * ring.packetWidthMeters;
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
    bool seen = true;
    for (int k = 0; k < 16 && seen; ++k) {
      const double a = 2.0 * M_PI * k / 16.0;
      // 16 chords of the circle: its points pushed out to cover the arcs between them.
      const double reach = outer / std::cos(M_PI / 16.0);
      const Eigen::Vector3d p =
          impact->point + Eigen::Vector3d(reach * std::cos(a), 0.0, reach * std::sin(a));
      double px, py, z;
      seen = camera.project(p, px, py, z);
      x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
    }
    if (!seen) continue;
    const int bx0 = std::max(0, int(std::floor(x0))), bx1 = std::min(w - 1, int(std::ceil(x1)));
    const int by0 = std::max(0, int(std::floor(y0))), by1 = std::min(h - 1, int(std::ceil(y1)));
    if (bx0 > bx1 || by0 > by1) continue;
    boxes.push_back({impact, ring, bx0, bx1, by0, by1});
  }
  const int bands = (h + kBandRows - 1) / kBandRows;
  forEachRow(bands, [&](int band) {
    const int r0 = band * kBandRows, r1 = std::min(h, r0 + kBandRows);
    for (const RingBox& box : boxes) {
      if (box.y1 < r0 || box.y0 >= r1) continue;
      const Eigen::Vector3d& c = box.impact->point;
      // A pixel of another surface in the box (a kerb, a step) is not this ring's water.
      const double tolerance = 0.05 + 0.01 * (c - camera.positionMeters).norm();
      for (int y = std::max(r0, box.y0); y <= std::min(r1 - 1, box.y1); ++y)
        for (int x = box.x0; x <= box.x1; ++x) {
          const size_t i = size_t(y) * size_t(w) + size_t(x);
          if (!water[i]) continue;
          const Eigen::Vector3d p = worldPoint(camera, x + 0.5, y + 0.5, depth[i]);
          if (std::abs(p.y() - c.y()) > tolerance) continue;
          const double dx = p.x() - c.x(), dz = p.z() - c.z(), r = std::hypot(dx, dz);
          if (!(r > 0.0)) continue;
          const double s = rippleRadialSlope(box.ring, r);
          if (s == 0.0) continue;
          slopeX[i] += float(s * dx / r);
          slopeZ[i] += float(s * dz / r);
        }
    }
  });
}

namespace {

// Bilinear RGB of `image` at pixel position (px, py), pixel centres at +0.5; false when the four
// texels are not all inside the frame and on the water.
bool sampleWater(const Image& image, const std::vector<uint8_t>& water, double px, double py,
                 std::array<float, 3>& rgb) {
  const double fx = px - 0.5, fy = py - 0.5;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= image.width || y0 + 1 >= image.height) return false;
  const double ax = fx - x0, ay = fy - y0;
  rgb = {0.0f, 0.0f, 0.0f};
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const size_t i = size_t(y0 + dy) * size_t(image.width) + size_t(x0 + dx);
      if (!water[i]) return false;
      const double weight = (dx ? ax : 1.0 - ax) * (dy ? ay : 1.0 - ay);
      for (int c = 0; c < 3; ++c) rgb[c] += float(weight * image.rgba[i * 4 + size_t(c)]);
    }
  return true;
}

}  // namespace

void shadeRippleMirror(Image& image, const Camera& camera, const std::vector<float>& depth,
                       const std::vector<float>& slopeX, const std::vector<float>& slopeZ,
                       const EnvironmentLookup& environment, const Image* plate,
                       const std::vector<uint8_t>* water) {
  const int w = camera.width, h = camera.height;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  forEachRow(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (slopeX[i] == 0.0f && slopeZ[i] == 0.0f) continue;
      const Eigen::Vector3d p = worldPoint(camera, x + 0.5, y + 0.5, depth[i]);
      const Eigen::Vector3d v = (p - camera.positionMeters).normalized();
      const Eigen::Vector3d n = Eigen::Vector3d(-slopeX[i], 1.0, -slopeZ[i]).normalized();
      const double cosLevel = -v.dot(up), cosTilted = -v.dot(n);
      if (!(cosLevel > 0.0) || !(cosTilted > 0.0)) continue;  // seen from below: not this water
      const Eigen::Vector3d level = v + 2.0 * cosLevel * up, tilted = v + 2.0 * cosTilted * n;
      const double rTilted = optics::fresnelReflectance(cosTilted, kWaterIndex);
      float* px = &image.rgba[i * 4];
      if (plate && water && tilted.y() > 0.0) {
        // The view ray whose level reflection is the tilted one, and where it meets the frame.
        const Eigen::Vector3d seen(tilted.x(), -tilted.y(), tilted.z());
        double qx, qy, qz;
        std::array<float, 3> shown;
        if (camera.project(camera.positionMeters + seen, qx, qy, qz) &&
            sampleWater(*plate, *water, qx, qy, shown)) {
          const double rAtQ = optics::fresnelReflectance(tilted.y(), kWaterIndex);
          for (int c = 0; c < 3; ++c) px[c] = std::max(0.0f, float(rTilted / rAtQ * shown[c]));
          continue;
        }
      }
      const double rLevel = optics::fresnelReflectance(cosLevel, kWaterIndex);
      const std::array<float, 3> lLevel = environment(level), lTilted = environment(tilted);
      for (int c = 0; c < 3; ++c)
        px[c] = std::max(0.0f, px[c] + float(rTilted * lTilted[c] - rLevel * lLevel[c]));
    }
  });
}

}  // namespace pluvia::rain
