#include "stages/skylight_fog.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pluvia {

void applySkylightFog(Image& image, const Camera& camera, const optics::SkylightTable& table,
                      const optics::SkylightMedium& medium, double maxPathMeters) {
  const double sigma = medium.extinctionPerMeter();
  if (!(sigma > 0.0)) return;
  const std::vector<float>& depth = image.plane("depth");
  const int width = image.width;
  tbb::parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const float z = depth[i];
      if (!(z < std::numeric_limits<float>::infinity())) continue;        // sky: its own airlight
      const Eigen::Vector3d rayCam = camera.rayCamera(x + 0.5, y + 0.5);  // z = -1
      const Eigen::Vector3d view = (camera.worldFromCamera * rayCam).normalized();
      const double path = std::min(std::max(double(z), 0.0) * rayCam.norm(), maxPathMeters);
      const float alpha = float(1.0 - std::exp(-sigma * path));
      const std::array<float, 3> in =
          optics::skylightInscatter(table, medium, {view.x(), view.y(), view.z()});
      float* p = image.rgba.data() + i * 4;
      for (int c = 0; c < 3; ++c) p[c] = alpha * in[size_t(c)] + (1.0f - alpha) * p[c];
    }
  });
}

}  // namespace pluvia
