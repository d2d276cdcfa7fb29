#include "stages/skylight_fog.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/parallel.h"

namespace pluvia {
namespace {

// The widest node spacing: 16 px at 1080p and a 64-wide table is a tenth of a texel.
constexpr int kMaxNodeStepPx = 16;
// Nodes an eighth of a table texel apart at the frame's centre (where a pixel spans the
// widest angle): L_in is the table's bilinear lookup, and between nodes a bilinear of it.
constexpr double kNodesPerTexel = 8.0;

}  // namespace

int skylightNodeStepPx(const Camera& camera, const optics::SkylightTable& table) {
  const double texelRadians = 2.0 * M_PI / std::max(table.dropRadiance.width, 1);
  return std::clamp(int(texelRadians / kNodesPerTexel * camera.focalPx), 1, kMaxNodeStepPx);
}

void applySkylightFog(Image& image, const Camera& camera, const optics::SkylightTable& table,
                      const optics::SkylightMedium& medium, double maxPathMeters) {
  const double sigma = medium.extinctionPerMeter();
  if (!(sigma > 0.0)) return;
  const std::vector<float>& depth = image.plane(kDepthPlane);
  const int width = image.width, height = image.height;
  const int step = skylightNodeStepPx(camera, table);
  // Nodes at every step-th pixel centre and at the last row and column.
  const int nx = (width - 1 + step - 1) / step + 1, ny = (height - 1 + step - 1) / step + 1;
  auto nodeCoordinate = [step](int k, int size) { return std::min(k * step, size - 1); };
  std::vector<std::array<float, 3>> nodes(static_cast<size_t>(nx) * static_cast<size_t>(ny));
  forEachRow(ny, [&](int j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector3d view =
          (camera.worldFromCamera *
           camera.rayCamera(nodeCoordinate(i, width) + 0.5, nodeCoordinate(j, height) + 0.5))
              .normalized();
      nodes[size_t(j) * size_t(nx) + size_t(i)] =
          optics::skylightInscatter(table, medium, {view.x(), view.y(), view.z()});
    }
  });
  const float sigmaF = float(sigma), maxPath = float(std::min(maxPathMeters, 1e30));
  const float inverseFocal = float(1.0 / camera.focalPx);
  forEachRow(height, [&](int y) {
    const int j0 = y / step, j1 = std::min(j0 + 1, ny - 1);
    const int y0 = nodeCoordinate(j0, height), y1 = nodeCoordinate(j1, height);
    const float fy = y1 > y0 ? float(y - y0) / float(y1 - y0) : 0.0f;
    const float dy = (float(y) + 0.5f - float(camera.cy)) * inverseFocal;
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const float z = depth[i];
      if (!(z < std::numeric_limits<float>::infinity())) continue;  // sky: its own airlight
      const int i0 = x / step, i1 = std::min(i0 + 1, nx - 1);
      const int x0 = nodeCoordinate(i0, width), x1 = nodeCoordinate(i1, width);
      const float fx = x1 > x0 ? float(x - x0) / float(x1 - x0) : 0.0f;
      const float dx = (float(x) + 0.5f - float(camera.cx)) * inverseFocal;
      // The path along the pixel's ray: z-depth times the ray's length at z = 1.
      const float path = std::min(std::max(z, 0.0f) * std::sqrt(dx * dx + dy * dy + 1.0f), maxPath);
      const float alpha = 1.0f - std::exp(-sigmaF * path);
      const std::array<float, 3>& a = nodes[size_t(j0) * size_t(nx) + size_t(i0)];
      const std::array<float, 3>& b = nodes[size_t(j0) * size_t(nx) + size_t(i1)];
      const std::array<float, 3>& c = nodes[size_t(j1) * size_t(nx) + size_t(i0)];
      const std::array<float, 3>& d = nodes[size_t(j1) * size_t(nx) + size_t(i1)];
      float* p = image.rgba.data() + i * 4;
      for (int k = 0; k < 3; ++k) {
        const float top = a[size_t(k)] + fx * (b[size_t(k)] - a[size_t(k)]);
        const float bottom = c[size_t(k)] + fx * (d[size_t(k)] - c[size_t(k)]);
        const float in = top + fy * (bottom - top);
        p[k] = alpha * in + (1.0f - alpha) * p[k];
      }
    }
  });
}

}  // namespace pluvia
