#include "rain/splash_draw.h"

#include <algorithm>
#include <cmath>

namespace pluvia::rain {

void drawSplashParticles(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                         const Camera& camera, const std::vector<ShadedParticle>& particles,
                         float opacity) {
  const int w = camera.width, h = camera.height;
  for (const ShadedParticle& sp : particles) {
    const SplashParticle& p = sp.particle;
    double ax, ay, az, bx, by, bz;
    if (!camera.project(p.from, ax, ay, az) || !camera.project(p.to, bx, by, bz)) continue;
    const double zMid = 0.5 * (az + bz);
    const double diameterPx = camera.focalPx * p.diameterMeters / zMid;
    const double radius = std::max(0.5 * diameterPx, 0.5);
    const double length = std::hypot(bx - ax, by - ay);
    // Drawn at least a pixel wide: a thinner particle covers (d_px)^2 of that pixel's area.
    const double drawn = std::max(diameterPx, 1.0);
    const float a =
        float(opacity * (diameterPx / drawn) * (diameterPx / drawn) * drawn / (length + drawn));
    if (!(a > 0.0f)) continue;
    const int x0 = std::max(0, int(std::floor(std::min(ax, bx) - radius - 1)));
    const int x1 = std::min(w - 1, int(std::ceil(std::max(ax, bx) + radius + 1)));
    const int y0 = std::max(0, int(std::floor(std::min(ay, by) - radius - 1)));
    const int y1 = std::min(h - 1, int(std::ceil(std::max(ay, by) + radius + 1)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        // Distance from the pixel centre to the segment, with the depth there.
        const double cx = x + 0.5 - ax, cy = y + 0.5 - ay, sx = bx - ax, sy = by - ay;
        const double s =
            length > 0.0 ? std::clamp((cx * sx + cy * sy) / (length * length), 0.0, 1.0) : 0.0;
        const double dist = std::hypot(cx - s * sx, cy - s * sy);
        const double edge = std::clamp(radius + 0.5 - dist, 0.0, 1.0);  // anti-aliased rim
        if (edge <= 0.0) continue;
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        const double z = az + s * (bz - az);
        const double surface = depth[i];
        if (z > surface + std::max(kSurfaceToleranceMeters, 0.01 * surface)) continue;
        const float k = a * float(edge);
        float* rgba = image.rgba.data() + i * 4;
        for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * (1.0f - k) + sp.radiance[size_t(c)] * k;
        alpha[i] = alpha[i] * (1.0f - k) + k;
      }
  }
}

}  // namespace pluvia::rain
