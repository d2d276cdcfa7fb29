#include "rain/splash_draw.h"

#include <algorithm>
#include <cmath>

#include "rain/counter_stream.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

// Rows drawn by one task: a particle is drawn by every band its box meets, each band in the
// particles' order, so a pixel sees the same compositing order whatever the thread count.
constexpr int kBandRows = 32;

}  // namespace

bool projectSplashParticle(const Camera& camera, const SplashParticle& p, float opacity,
                           const std::array<float, 3>& radiance, uint64_t key,
                           ProjectedParticle& out) {
  double ax, ay, az, bx, by, bz;
  if (!camera.project(p.from, ax, ay, az) || !camera.project(p.to, bx, by, bz)) return false;
  const double diameterPx = camera.focalPx * p.diameterMeters / (0.5 * (az + bz));
  const double radius = std::max(0.5 * diameterPx, 0.5);
  const double length = std::hypot(bx - ax, by - ay);
  // Drawn at least a pixel wide: a thinner particle covers (d_px)^2 of that pixel's area.
  const double drawn = std::max(diameterPx, 1.0);
  out.alpha =
      float(opacity * (diameterPx / drawn) * (diameterPx / drawn) * drawn / (length + drawn));
  if (!(out.alpha >= kMinParticleCoverage)) return false;
  if (out.alpha < kThinnedCoverage) {
    const float u = float(double(mix(key) >> 11) * 0x1.0p-53);
    if (u * kThinnedCoverage >= out.alpha) return false;
    out.alpha = kThinnedCoverage;
  }
  // A pixel's rim weight is radius + 0.5 - distance: zero beyond radius + 0.5 of the segment.
  const double reach = radius + 0.5;
  out.x0 = std::max(0, int(std::ceil(std::min(ax, bx) - reach - 0.5)));
  out.x1 = std::min(camera.width - 1, int(std::floor(std::max(ax, bx) + reach - 0.5)));
  out.y0 = std::max(0, int(std::ceil(std::min(ay, by) - reach - 0.5)));
  out.y1 = std::min(camera.height - 1, int(std::floor(std::max(ay, by) + reach - 0.5)));
  if (out.x0 > out.x1 || out.y0 > out.y1) return false;
  out.ax = float(ax), out.ay = float(ay), out.az = float(az);
  out.bx = float(bx), out.by = float(by), out.bz = float(bz);
  out.radius = float(radius);
  out.inverseLengthSquared = length > 0.0 ? float(1.0 / (length * length)) : 0.0f;
  out.radiance = radiance;
  return true;
}

void drawProjectedParticles(Image& image, std::vector<float>& alpha,
                            const std::vector<float>& depth, int w, int h,
                            const std::vector<std::vector<ProjectedParticle>>& groups) {
  const int bands = (h + kBandRows - 1) / kBandRows;
  std::vector<std::vector<const ProjectedParticle*>> inBand(static_cast<size_t>(bands));
  for (const std::vector<ProjectedParticle>& group : groups)
    for (const ProjectedParticle& p : group)
      for (int b = p.y0 / kBandRows; b <= p.y1 / kBandRows; ++b) inBand[size_t(b)].push_back(&p);
  forEachIndex(bands, [&](int band) {
    const int rowLo = band * kBandRows, rowHi = std::min(h - 1, rowLo + kBandRows - 1);
    for (const ProjectedParticle* p : inBand[size_t(band)]) {
      const float sx = p->bx - p->ax, sy = p->by - p->ay;
      for (int y = std::max(p->y0, rowLo); y <= std::min(p->y1, rowHi); ++y)
        for (int x = p->x0; x <= p->x1; ++x) {
          // Distance from the pixel centre to the segment, with the depth there.
          const float cx = float(x) + 0.5f - p->ax, cy = float(y) + 0.5f - p->ay;
          const float s = std::clamp((cx * sx + cy * sy) * p->inverseLengthSquared, 0.0f, 1.0f);
          const float ex = cx - s * sx, ey = cy - s * sy;
          const float dist = std::sqrt(ex * ex + ey * ey);
          const float edge = std::min(p->radius + 0.5f - dist, 1.0f);  // anti-aliased rim
          if (!(edge > 0.0f)) continue;
          const size_t i = size_t(y) * size_t(w) + size_t(x);
          const float z = p->az + s * (p->bz - p->az);
          const float surface = depth[i];
          if (z > surface + std::max(float(kSurfaceToleranceMeters), 0.01f * surface)) continue;
          const float k = p->alpha * edge;
          float* rgba = image.rgba.data() + i * 4;
          for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * (1.0f - k) + p->radiance[size_t(c)] * k;
          alpha[i] = alpha[i] * (1.0f - k) + k;
        }
    }
  });
}

void drawSplashParticles(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                         const Camera& camera, const std::vector<ShadedParticle>& particles,
                         float opacity) {
  std::vector<std::vector<ProjectedParticle>> groups(1);
  for (size_t k = 0; k < particles.size(); ++k) {
    ProjectedParticle p;
    if (projectSplashParticle(camera, particles[k].particle, opacity, particles[k].radiance, k, p))
      groups[0].push_back(p);
  }
  drawProjectedParticles(image, alpha, depth, camera.width, camera.height, groups);
}

}  // namespace pluvia::rain
