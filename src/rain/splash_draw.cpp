#include "rain/splash_draw.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace pluvia::rain {
namespace {

// Rows drawn by one task: a particle is drawn by every band its box meets, each band in the
// particles' order, so a pixel sees the same compositing order whatever the thread count.
constexpr int kBandRows = 32;

// A particle projected into the picture: its segment, radius, depths and opacity.
struct Projected {
  double ax, ay, az, bx, by, bz, radius, length;
  float alpha;
  int x0, x1, y0, y1;  // the pixels whose centres lie within radius + 0.5 of the segment
  size_t index;        // into the particles, for the radiance
};

bool project(const Camera& camera, const SplashParticle& p, float opacity, Projected& out) {
  if (!camera.project(p.from, out.ax, out.ay, out.az) ||
      !camera.project(p.to, out.bx, out.by, out.bz))
    return false;
  const double diameterPx = camera.focalPx * p.diameterMeters / (0.5 * (out.az + out.bz));
  out.radius = std::max(0.5 * diameterPx, 0.5);
  out.length = std::hypot(out.bx - out.ax, out.by - out.ay);
  // Drawn at least a pixel wide: a thinner particle covers (d_px)^2 of that pixel's area.
  const double drawn = std::max(diameterPx, 1.0);
  out.alpha =
      float(opacity * (diameterPx / drawn) * (diameterPx / drawn) * drawn / (out.length + drawn));
  if (!(out.alpha >= kMinParticleCoverage)) return false;
  // A pixel's rim weight is radius + 0.5 - distance: zero beyond radius + 0.5 of the segment.
  const double reach = out.radius + 0.5;
  out.x0 = std::max(0, int(std::ceil(std::min(out.ax, out.bx) - reach - 0.5)));
  out.x1 = std::min(camera.width - 1, int(std::floor(std::max(out.ax, out.bx) + reach - 0.5)));
  out.y0 = std::max(0, int(std::ceil(std::min(out.ay, out.by) - reach - 0.5)));
  out.y1 = std::min(camera.height - 1, int(std::floor(std::max(out.ay, out.by) + reach - 0.5)));
  return out.x0 <= out.x1 && out.y0 <= out.y1;
}

}  // namespace

float splashParticleCoverage(const Camera& camera, const SplashParticle& particle, float opacity) {
  Projected p;
  return project(camera, particle, opacity, p) ? p.alpha : 0.0f;
}

void drawSplashParticles(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                         const Camera& camera, const std::vector<ShadedParticle>& particles,
                         float opacity) {
  const int w = camera.width, h = camera.height;
  std::vector<Projected> projected(particles.size());
  std::vector<char> shown(particles.size(), 0);
  tbb::parallel_for(size_t(0), particles.size(), [&](size_t k) {
    projected[k].index = k;
    shown[k] = project(camera, particles[k].particle, opacity, projected[k]);
  });
  const int bands = (h + kBandRows - 1) / kBandRows;
  std::vector<std::vector<const Projected*>> inBand(static_cast<size_t>(bands));
  for (size_t k = 0; k < particles.size(); ++k) {
    if (!shown[k]) continue;
    for (int b = projected[k].y0 / kBandRows; b <= projected[k].y1 / kBandRows; ++b)
      inBand[size_t(b)].push_back(&projected[k]);
  }
  tbb::parallel_for(0, bands, [&](int band) {
    const int rowLo = band * kBandRows, rowHi = std::min(h - 1, rowLo + kBandRows - 1);
    for (const Projected* p : inBand[size_t(band)]) {
      const std::array<float, 3>& radiance = particles[p->index].radiance;
      const double sx = p->bx - p->ax, sy = p->by - p->ay;
      for (int y = std::max(p->y0, rowLo); y <= std::min(p->y1, rowHi); ++y)
        for (int x = p->x0; x <= p->x1; ++x) {
          // Distance from the pixel centre to the segment, with the depth there.
          const double cx = x + 0.5 - p->ax, cy = y + 0.5 - p->ay;
          const double s = p->length > 0.0
                               ? std::clamp((cx * sx + cy * sy) / (p->length * p->length), 0.0, 1.0)
                               : 0.0;
          const double ex = cx - s * sx, ey = cy - s * sy;
          const double dist = std::sqrt(ex * ex + ey * ey);
          const double edge = std::clamp(p->radius + 0.5 - dist, 0.0, 1.0);  // anti-aliased rim
          if (edge <= 0.0) continue;
          const size_t i = size_t(y) * size_t(w) + size_t(x);
          const double z = p->az + s * (p->bz - p->az);
          const double surface = depth[i];
          if (z > surface + std::max(kSurfaceToleranceMeters, 0.01 * surface)) continue;
          const float k = p->alpha * float(edge);
          float* rgba = image.rgba.data() + i * 4;
          for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * (1.0f - k) + radiance[size_t(c)] * k;
          alpha[i] = alpha[i] * (1.0f - k) + k;
        }
    }
  });
}

}  // namespace pluvia::rain
