#include "optics/environment_file.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "io/image_file_reader.h"
#include "util/error.h"
#include "util/input_guard.h"

namespace pluvia::optics {

EquirectMap loadEnvironment(const std::string& path) {
  const ErrorContext context{"environment", {}, path};
  fs::protectInputs({path});
  const Image image = readImageFile(path, std::nullopt);
  if (image.width != 2 * image.height) {
    throw Error(
        fmt::format("an equirect environment must be twice as wide as high, this one is {} x {}",
                    image.width, image.height),
        context);
  }
  EquirectMap map(image.width, image.height);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float value = image.pixel(x, y)[c];
        if (!std::isfinite(value)) {
          throw Error(fmt::format("texel ({}, {}) channel {} holds {}: radiance must be finite", x,
                                  y, c, value),
                      context);
        }
        // Lossy EXR compression (DWAA/DWAB) leaves tiny negative values in dark texels.
        map.texel(x, y)[c] = std::max(value, 0.0f);
      }
    }
  }
  return map;
}

}  // namespace pluvia::optics
